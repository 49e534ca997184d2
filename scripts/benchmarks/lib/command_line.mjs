// The benchmarks' command-line options, read out of the argument list so that what is left is the
// positional arguments: `--name value` options and `--name` flags, anywhere on the line.

/**
 * Reads options out of `args` (changed in place: each option read is removed from it).
 *   const { option, flag } = commandLine(args);
 *   const second = flag('second');            // true if --second was given
 *   const link = option('link', 'slow 4G');   // the value after --link, or the fallback
 */
export function commandLine(args) {
  return {
    option(name, fallback) {
      const i = args.indexOf(`--${name}`);
      if (i < 0) return fallback;
      const [, value] = args.splice(i, 2);
      if (value === undefined) throw new Error(`--${name} needs a value`);
      return value;
    },
    flag(name) {
      const i = args.indexOf(`--${name}`);
      if (i >= 0) args.splice(i, 1);
      return i >= 0;
    },
  };
}
