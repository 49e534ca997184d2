// The runtime module's entry points (wasm/bindings.cpp, wasm/module_kind.cpp) as methods of its
// Module object: the module exports each as a C function sb_<name> over numbers, and this table
// says how each one's arguments and result cross. tests/wasm/runtime_calls.test.mjs holds the
// table and the module's exports together.
//
// Arguments: 'n' a number (an integer, a float or a pointer: WebAssembly converts it), 's' a
// string, which crosses as its UTF-8 bytes (pointer and size) copied in for the call. Results:
// 'n' a number, 'p' a pointer (unsigned), 'b' a boolean (the C function returns 0 or 1), 's' a
// string, which the C function leaves in the module's text result (a pointer to it, its size from
// sb_textSize), freed with sb_textFree once decoded.

import { withBytes } from './wasm_memory.js';

export const kRuntimeCalls = Object.freeze({
  isCrowdModule: ['', 'b'],
  takeError: ['', 's'],
  limitsJson: ['', 's'],
  loadRig: ['nnnnsnn', 'n'],
  loadVrm: ['nn', 'n'],
  mainFileHashFor: ['nns', 's'],
  contentHash: ['nn', 's'],
  describeRig: ['n', 's'],
  createInstance: ['nnnnn', 'n'],
  driverMatricesPtr: ['n', 'p'],
  driverCount: ['n', 'n'],
  rotationsPtr: ['n', 'p'],
  worldMatricesPtr: ['n', 'p'],
  jointCount: ['n', 'n'],
  step: ['nn', 'b'],
  reset: ['n', 'b'],
  lastSteps: ['n', 'n'],
  disposeRig: ['n', 'b'],
  disposeInstance: ['n', 'b'],
  createScene: ['', 'n'],
  sceneAdd: ['nn', 'n'],
  sceneRemove: ['nn', 'b'],
  sceneSize: ['n', 'n'],
  scenePositionsPtr: ['n', 'p'],
  sceneSetBudget: ['nnnnn', 'b'],
  sceneStep: ['nn', 'b'],
  sceneIsActive: ['nn', 'b'],
  setWind: ['nnnnnnn', 'b'],
  sceneSetWind: ['nnnnnnn', 'b'],
  sceneActivePtr: ['n', 'p'],
  disposeScene: ['n', 'b'],
  stats: ['', 's'],
  setJumpThresholds: ['nnn', 'b'],
  jump: ['n', 'b'],
  jumps: ['n', 'n'],
  carryFrom: ['nn', 'b'],
  settle: ['nn', 'n'],
  grab: ['nnnnn', 'b'],
  release: ['n', 'b'],
  grabbedJoint: ['n', 'n'],
  setInertia: ['nnn', 'b'],
  setColliders: ['nnn', 's'],
  frameMatricesPtr: ['n', 'p'],
});

const encoder = new TextEncoder();
const decoder = new TextDecoder();

/**
 * Puts every entry point of kRuntimeCalls on the runtime module's Module object `m`, as
 * m.<name>(...arguments). Throws if the module lacks one (a module of another version).
 */
export function addRuntimeCalls(m) {
  for (const [name, [argumentKinds, result]] of Object.entries(kRuntimeCalls)) {
    const exported = m[`_sb_${name}`];
    if (typeof exported !== 'function') throw new Error(`the runtime module has no entry point sb_${name}`);
    m[name] = runtimeCall(m, exported, argumentKinds.indexOf('s'), result);
  }
}

// One entry point: at most one string argument (at index `text`, -1 for none), and its result.
// The per-frame ones (step, sceneStep) take a fixed list of parameters rather than rest
// arguments, so that a call allocates nothing; a WebAssembly function ignores the extra ones.
function runtimeCall(m, exported, text, result) {
  const call = text < 0 ? exported : (...args) => withBytes(m, encoder.encode(args[text]),
    (at, size) => exported(...args.slice(0, text), at, size, ...args.slice(text + 1)));
  switch (result) {
    case 'b': return (a, b, c, d, e, f, g) => call(a, b, c, d, e, f, g) !== 0;
    case 'p': return (a, b, c, d, e, f, g) => call(a, b, c, d, e, f, g) >>> 0;
    case 's': return (...args) => {
      const at = call(...args) >>> 0;
      const text = decoder.decode(m.HEAPU8.subarray(at, at + m._sb_textSize()));
      m._sb_textFree();
      return text;
    };
    default: return call;
  }
}
