// The error type of springbones and how a failure in either WebAssembly module becomes one.
// Shared by the runtime API (springbones.js) and the creator tools (creator_tools.js).

/** Every failure the library reports, apart from TypeError/RangeError for bad arguments. */
export class SpringBonesError extends Error {
  // The class's own name, stated: the minified bundles rename the class (to a letter), and Node
  // prints an error as `<constructor name> [<error name>]` when the two differ.
  static name = 'SpringBonesError';

  /**
   * @param {string} code stable identifier ("glb-truncated", "metadata-bad-json", "disposed", ...)
   * @param {string} message human-readable description
   * @param {string} [path] JSON pointer into springBones (or the entity) for metadata errors
   */
  constructor(code, message, path = '') {
    super(message);
    this.name = 'SpringBonesError';
    this.code = code;
    this.path = path;
  }
}

// The bindings catch every C++ exception; what can still come out of a call is a trap (a bug in
// the core, or running out of stack) or, in the creator tools, embind's own argument errors. Both
// become errors of ours.
export function call(fn) {
  try {
    return fn();
  } catch (cause) {
    if (cause instanceof WebAssembly.RuntimeError) {
      throw withCause(new SpringBonesError('internal-error', `WebAssembly trap: ${cause.message}`), cause);
    }
    throw cause;
  }
}

/** The error a module left pending (wasm/binding_errors.h), read once. */
export function takeError(m) {
  const { code, message, path } = JSON.parse(m.takeError());
  return new SpringBonesError(code, message, path);
}

/** The error of a call on a rig, instance or scene after its dispose(). */
export function disposedError(what) {
  return new SpringBonesError('disposed', `the ${what} has been disposed`);
}

export function withCause(error, cause) {
  Object.defineProperty(error, 'cause', { value: cause, configurable: true, writable: true });
  return error;
}
