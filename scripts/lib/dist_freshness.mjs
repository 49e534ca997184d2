// Whether web/dist/ holds a complete WebAssembly build that is newer than everything it is built
// from, so that scripts/demo and scripts/package can use it without building (and without waiting
// for a build another script of the checkout runs).
//
// `scripts/build wasm` removes the stamp web/dist/.complete as it starts and writes it when the
// link and the minified JavaScript are done: the list of the files it left in web/dist/ and of the
// input files it was built from, with the stamp's time set to the moment the build started. A source saved while the build ran is then
// newer than the stamp, and the next check builds again. Without a stamp (an interrupted build, a
// build by an older script) web/dist/ counts as incomplete.
//
//   node scripts/lib/dist_freshness.mjs check            exit 0 and say so when fresh, else 1 and why
//   node scripts/lib/dist_freshness.mjs forget           remove the stamp (a build starts)
//   node scripts/lib/dist_freshness.mjs stamp <start ms> write the stamp (the build is done)
import { existsSync, readFileSync, readdirSync, rmSync, statSync, utimesSync, writeFileSync } from 'node:fs';
import { join, relative } from 'node:path';
import { fileURLToPath } from 'node:url';

/** What the modules and the minified JavaScript are built from, relative to the checkout. */
export const kDistInputs = ['src', 'include', 'wasm', 'web', 'CMakeLists.txt', 'CMakePresets.json',
  'scripts/lib/minify.mjs', 'package-lock.json'];
/** Inside the inputs, what the build does not read: its own output, and the demo, served as it is. */
const kNotInputs = new Set(['web/dist', 'web/demo']);
const kStamp = 'web/dist/.complete';

/**
 * Every input file: [{ path, mtimeMs }], by path. Iterative, so a deep tree cannot overflow the
 * stack.
 */
export function listInputs(root) {
  const inputs = [];
  const pending = kDistInputs.map((p) => join(root, p));
  while (pending.length > 0) {
    const path = pending.pop();
    const rel = relative(root, path);
    if (kNotInputs.has(rel) || !existsSync(path)) continue;
    const stat = statSync(path);
    if (stat.isDirectory()) {
      for (const entry of readdirSync(path)) pending.push(join(path, entry));
    } else {
      inputs.push({ path: rel, mtimeMs: stat.mtimeMs });
    }
  }
  return inputs.sort((a, b) => (a.path < b.path ? -1 : a.path > b.path ? 1 : 0));
}

/** { fresh: boolean, reason: string }: why web/dist/ can or cannot be used as it is. */
export function distState(root) {
  const stampPath = join(root, kStamp);
  if (!existsSync(stampPath)) {
    return { fresh: false, reason: `${kStamp} is missing: no complete build of web/dist/ is recorded` };
  }
  let files, inputs;
  try {
    ({ files, inputs } = JSON.parse(readFileSync(stampPath, 'utf8')));
  } catch (error) {
    return { fresh: false, reason: `${kStamp} is unreadable (${error.message})` };
  }
  if (!Array.isArray(files) || files.length === 0 || !Array.isArray(inputs)) {
    return { fresh: false, reason: `${kStamp} lists no files or no inputs` };
  }
  const missing = files.find((f) => !existsSync(join(root, 'web/dist', f)));
  if (missing !== undefined) return { fresh: false, reason: `web/dist/${missing} is missing` };
  const builtAt = statSync(stampPath).mtimeMs;
  const now = listInputs(root);
  const changed = now.find((input) => input.mtimeMs > builtAt);
  if (changed) return { fresh: false, reason: `${changed.path} changed after web/dist/ was built` };
  // A removed or renamed input changes no file's time: the lists tell.
  const nowPaths = new Set(now.map((input) => input.path));
  const removed = inputs.find((path) => !nowPaths.has(path));
  if (removed !== undefined) return { fresh: false, reason: `${removed} was removed after web/dist/ was built` };
  const builtPaths = new Set(inputs);
  const added = now.find((input) => !builtPaths.has(input.path));
  if (added) return { fresh: false, reason: `${added.path} was added after web/dist/ was built` };
  return { fresh: true, reason: `web/dist/ is complete (${files.length} files) and newer than its sources` };
}

export function forgetDistStamp(root) {
  rmSync(join(root, kStamp), { force: true });
}

/** Records a complete build of web/dist/ that started at startedMs (milliseconds since 1970). */
export function writeDistStamp(root, startedMs) {
  const dist = join(root, 'web/dist');
  const files = readdirSync(dist).filter((f) => f !== '.complete').sort();
  const stampPath = join(root, kStamp);
  const inputs = listInputs(root).map((input) => input.path);
  writeFileSync(stampPath, JSON.stringify({ files, inputs }, null, 1) + '\n');
  const started = new Date(startedMs);
  utimesSync(stampPath, started, started);
}

if (process.argv[1] === fileURLToPath(import.meta.url)) {
  const root = join(fileURLToPath(new URL('.', import.meta.url)), '..', '..');
  const [command, argument] = process.argv.slice(2);
  if (command === 'check') {
    const state = distState(root);
    console.log(state.reason);
    process.exit(state.fresh ? 0 : 1);
  } else if (command === 'forget') {
    forgetDistStamp(root);
  } else if (command === 'stamp' && /^[0-9]+$/.test(argument ?? '')) {
    writeDistStamp(root, Number(argument));
  } else {
    console.error('usage: node scripts/lib/dist_freshness.mjs check | forget | stamp <start ms>');
    process.exit(2);
  }
}
