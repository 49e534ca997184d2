// springbones/inline: the same API as springbones, with the runtime module inlined (base64 in this
// JavaScript), for bundlers and hosts that cannot find or serve a separate .wasm. Opt-in: it costs
// about a third more bytes before compression, and the module is compiled from bytes (no
// streaming compilation while it downloads, no compiled-code cache between visits). README,
// "Install", has the measured cost.
//
// createSpringBones() with no module option decodes the inlined bytes; given `wasm`,
// `wasmBinary`, `wasmUrl` or `crowd: true`, it behaves as springbones' own. The creator tools are not inlined:
// sb.creatorTools() fetches their module as in springbones (or takes its options).
import { createSpringBones as createFromModule, SpringBonesError } from './springbones.js';
import { runtimeWasmBase64 } from './dist/springbones_wasm_base64.js';
import { kBinarySource, loadFailed } from './module_loader.js';

export { SpringBonesError };

/** createSpringBones with the inlined module as the default. */
export function createSpringBones(options = {}) {
  // The crowd module is not inlined: `crowd: true` fetches it as springbones does.
  const givesModule = options !== null && typeof options === 'object' &&
      (options.wasm !== undefined || options.wasmBinary !== undefined || options.wasmUrl !== undefined ||
       options.crowd === true);
  if (givesModule || options === null || typeof options !== 'object') return createFromModule(options);
  // Load errors name the inlined module, not a wasmBinary option the caller did not give.
  const source = 'the inline module (springbones/inline, dist/springbones_wasm_base64.js)';
  let wasmBinary;
  try {
    wasmBinary = decodeBase64(runtimeWasmBase64);
  } catch (cause) {
    return Promise.reject(loadFailed(source, cause));
  }
  return createFromModule({ ...options, wasmBinary, [kBinarySource]: source });
}

function decodeBase64(text) {
  const binary = atob(text);
  const bytes = new Uint8Array(binary.length);
  for (let i = 0; i < binary.length; i++) bytes[i] = binary.charCodeAt(i);
  return bytes;
}
