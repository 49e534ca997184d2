// The readers: GLB / glTF bytes and VRM files into typed input (web/typed_value.js has the
// encoding), and the VRM spring-bone rules, which build a VRM avatar's rig as rig data for the
// runtime (springbones/boundary.h), over the readers module (wasm/readers_bindings.cpp), a
// WebAssembly module of its own that a preview handing over its loader's parse of a wearable never
// downloads. sb.readers() loads it in browsers; in Node createSpringBones() loads it beside the
// runtime, so that loadRig and loadVrm take bytes at once.

import { call, takeError } from './errors.js';
import { instantiateModule } from './module_loader.js';
import { withBytes } from './wasm_memory.js';

const kModuleUrl = new URL('./dist/springbones_readers.wasm', import.meta.url);

/**
 * The readers over a new instance of their module.
 * @param {object} options createSpringBones's options, for the readers module's .wasm
 */
export async function loadReaders(options) {
  const module = await instantiateModule('readers', options, {
    importGlue: () => import('./dist/springbones_readers.js'),
    glueFile: 'web/dist/springbones_readers.js',
    defaultUrl: kModuleUrl,
  });
  return new Readers(module);
}

class Readers {
  #m;

  constructor(module) {
    this.#m = module;
    Object.freeze(this);
  }

  /**
   * What the runtime reads of a GLB or glTF text: {asset, nodes} (and the root extensions when
   * `withExtensions`), as typed input copied out of the readers' memory. Throws the reader's
   * SpringBonesError (glb-truncated, gltf-bad-json...).
   */
  readGltf(bytes, withExtensions) {
    const m = this.#m;
    const length = withBytes(m, bytes, (ptr, size) => call(() => m.readGltf(ptr, size, withExtensions)));
    return this.#result(length);
  }

  /**
   * A VRM avatar's rig, read from its document's typed input (VRMC_springBone 1.0 or VRM 0.x
   * secondaryAnimation), as rig data for the runtime, copied out of the readers' memory. Throws
   * the VRM rules' SpringBonesError (gltf-invalid, metadata-invalid...).
   */
  readVrm(typed) {
    const m = this.#m;
    const length = withBytes(m, typed, (ptr, size) => call(() => m.readVrm(ptr, size)));
    return this.#result(length);
  }

  // The bytes the last call wrote (its length, or -1 with the error pending).
  #result(length) {
    const m = this.#m;
    if (length < 0) throw takeError(m);
    const at = m.typedResult();
    return m.HEAPU8.slice(at, at + length);
  }
}
