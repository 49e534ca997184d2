// springbones: spring-bone physics for avatar wearables, the JavaScript API.
//
// A thin ES module over the WebAssembly core's runtime module (wasm/bindings.cpp, its entry points
// on the module object by runtime_calls.js). The contract is
// springbones.d.ts; docs/design.md ("Across the JavaScript boundary") explains it. Per frame exactly
// one call crosses the boundary (instance.step, or scene.step for a whole page) and nothing is
// allocated on either side. Structured inputs cross as typed input (typed_value.js): what the page
// parsed, never JSON text.
//
// This file starts the module and is the object it gives (sb: loadRig, loadVrm, contentHash,
// createScene, the other modules). The rest, one responsibility a file:
//   - module_loader.js fetches, compiles and instantiates a module; errors.js, the one error type;
//   - rig.js, instance.js, scene.js: what loadRig, createInstance and createScene return;
//   - arguments.js, json_arguments.js, rig_options.js, models_entry.js: the argument checks, which
//     run before anything crosses into WebAssembly (arguments.js says which file checks what);
//   - wasm_memory.js: bytes copied into the module's memory, and views on it;
//   - readers.js and creator_tools.js: the readers module (GLB and VRM bytes, and loadVrm's VRM
//     rules; loaded beside the runtime in Node and by sb.readers() in browsers) and the creator tools (deploy-time
//     validation and the Builder edits, loaded on first use by sb.creatorTools()).
//
// The module files (dist/springbones_wasm.js + .wasm) are built by `scripts/build wasm` and
// copied next to this file.

import { optionsObject, toBytes } from './arguments.js';
import { deepFreeze } from './deep_freeze.js';
import { SpringBonesError, call, takeError, withCause } from './errors.js';
import { kHashOptions, resolveHash, typedMetadata } from './models_entry.js';
import { instantiateModule, kIsNode, loadFailed, moduleSource } from './module_loader.js';
import { Rig } from './rig.js';
import { rigOptions } from './rig_options.js';
import { addRuntimeCalls } from './runtime_calls.js';
import { Scene } from './scene.js';
import { takeTyped, typedResult } from './typed_output.js';
import { encodeGltf } from './typed_value.js';
import { version } from './version.js';
import { warmUpWhenIdle } from './warm_up.js';
import { withBytes } from './wasm_memory.js';

export { SpringBonesError };

const kModuleUrl = new URL('./dist/springbones_wasm.wasm', import.meta.url);
// The crowd module: the runtime with its per-frame path built for speed (-O3, SIMD;
// wasm/CMakeLists.txt). Its exports are the runtime's, so it runs on the runtime's glue.
const kCrowdModuleUrl = new URL('./dist/springbones_crowd.wasm', import.meta.url);

/**
 * Loads and instantiates the WebAssembly module. Each call creates an independent module (its own
 * memory); one per page or process is the normal case. `crowd: true` loads the crowd module
 * instead of the runtime: the same API and the same rotations, several times faster per joint
 * for a crowd (docs/design.md, "Three modules").
 * @param {{wasm?: Response | WebAssembly.Module | Promise<Response | WebAssembly.Module>,
 *          wasmBinary?: ArrayBuffer | Uint8Array, wasmUrl?: string | URL, crowd?: boolean}} [options]
 */
export async function createSpringBones(options = {}) {
  // `crowd` chooses the default module; instantiateModule checks the rest of the options.
  let moduleOptions = options, crowd = false;
  if (options !== null && typeof options === 'object') {
    ({ crowd = false, ...moduleOptions } = options);
    if (typeof crowd !== 'boolean') throw new TypeError('createSpringBones: crowd must be true or false');
  }
  // In Node the readers come at once (local files, no download), so that loadRig and loadVrm take
  // bytes as they always have; a page loads them with sb.readers() when it has bytes to read.
  const readers = kIsNode ? loadReaders({}) : undefined;
  readers?.catch(() => {});  // reported by the first call that needs them (loadRig with bytes)
  const module = await instantiateModule('createSpringBones', moduleOptions, {
    importGlue: () => import('./dist/springbones_wasm.js'),
    glueFile: 'web/dist/springbones_wasm.js',
    defaultUrl: crowd ? kCrowdModuleUrl : kModuleUrl,
  });
  let limits;
  try {
    addRuntimeCalls(module);
    // The core's limits and defaults (describeLimits, springbones/boundary.h), read once: the argument checks
    // below use them, so the JS API never types a limit of its own.
    limits = deepFreeze(takeTyped(module, module.limits()));
  } catch (cause) {
    throw loadFailed(moduleSource(module), cause);
  }
  const sb = new SpringBones(module, limits, readers);
  if (readers !== undefined) await sb.readers().catch(() => {});
  warmUpWhenIdle(sb);
  return sb;
}

// The readers module's API, imported on first use: a page that hands over what its loader parsed
// never downloads readers.js or its module.
const loadReaders = (options) => import('./readers.js').then((readers) => readers.loadReaders(options));

// ---------------------------------------------------------------------------------------------

class SpringBones {
  #m;
  #limits;
  #creatorTools;  // the promise of the first creatorTools() call
  #readersLoading;  // the promise of the first readers() call
  #readers;  // the readers, once loaded
  #readersError;  // why the last load of the readers failed

  constructor(module, limits, readers) {
    this.#m = module;
    this.#limits = limits;
    if (readers !== undefined) this.#startReaders(readers);
  }

  /** The package version (package.json's), e.g. '0.2.0'. */
  get version() {
    return version;
  }

  /** Whether this is the crowd module (createSpringBones({ crowd: true })), built to step many instances fast. */
  get crowd() {
    return this.#m.isCrowdModule();
  }

  /**
   * Loads a wearable: the glTF JSON the page's loader already parsed (three.js: parser.json), or
   * GLB / glTF bytes (read by the readers module); its data.springBones (object, JSON text, or
   * null/undefined for none); which models entry applies; optional colliders.
   */
  loadRig(glb, springBones, options) {
    const gltf = this.#gltfInput('loadRig', glb, false);
    const metadata = typedMetadata(springBones, this.#limits);
    const { hash: hashOptions, typed: typedOptions, jumps } = rigOptions('loadRig', options);
    const m = this.#m;
    let hash = resolveHash(m, 'loadRig', hashOptions);
    if (hash === '' && gltf.bytes !== undefined) hash = this.contentHash(gltf.bytes);
    if (hash === '' && springBones !== null && springBones !== undefined) {
      throw new TypeError('loadRig: the glTF was given parsed, so there are no bytes to hash: say which ' +
                          'springBones.models entry applies with contentHash, or entity and bodyShape');
    }
    const handle = withBytes(m, gltf.typed, (gltfPtr, gltfSize) => withBytes(m, metadata,
      (metaPtr, metaSize) => withBytes(m, typedOptions,
        (optPtr, optSize) => m.loadRig(gltfPtr, gltfSize, metaPtr, metaSize, hash, optPtr, optSize))));
    if (handle === 0) throw takeError(m);
    return this.#rig(handle, jumps);
  }

  /**
   * Loads the spring bones of a VRM avatar (.vrm bytes, or the glTF JSON a loader parsed):
   * VRMC_springBone 1.0, or VRM 0.x secondaryAnimation, with their colliders. The rig has the same
   * interface as loadRig's. The VRM rules run in the readers module, which builds the rig and hands
   * it to the runtime as rig data: a page awaits sb.readers() first (Node loads them with the runtime).
   */
  loadVrm(vrm) {
    const gltf = this.#gltfInput('loadVrm', vrm, true);
    const rigData = this.#loadedReaders('loadVrm reads VRM spring bones in the readers module, and it is not loaded: ' +
                                        'await sb.readers() first').readVrm(gltf.typed);
    const m = this.#m;
    const handle = withBytes(m, rigData, (ptr, size) => m.loadVrm(ptr, size));
    if (handle === 0) throw takeError(m);
    return this.#rig(handle);
  }

  /**
   * The readers module, which reads GLB and VRM bytes for loadRig and loadVrm: in Node it comes
   * with createSpringBones(); a page that has bytes to read awaits this first. Takes the options
   * createSpringBones takes, for the readers' .wasm (dist/springbones_readers.wasm by default). A
   * failed load rejects, and the next call tries again.
   */
  readers(options = {}) {
    if (this.#readersLoading === undefined) this.#startReaders(loadReaders(options));
    return this.#readersLoading;
  }

  #startReaders(loading) {
    this.#readersLoading = loading.then((readers) => {
      this.#readers = readers;
    }, (error) => {
      this.#readersLoading = undefined;
      this.#readersError = error;
      throw error;
    });
  }

  // A glTF argument as typed input {typed, bytes?}: a parsed glTF document is written directly;
  // bytes go through the readers.
  #gltfInput(where, value, withExtensions) {
    if (value instanceof Uint8Array || value instanceof ArrayBuffer) {
      const bytes = toBytes(`${where}: bytes`, value);
      const readers = this.#loadedReaders(`${where} was given bytes, which the readers module reads, and it is not loaded: ` +
        'await sb.readers() first, or pass the glTF JSON your loader already parsed (three.js: gltf.parser.json)');
      return { typed: readers.readGltf(bytes, withExtensions), bytes };
    }
    if (value === null || typeof value !== 'object' || Array.isArray(value) || ArrayBuffer.isView(value) ||
        (value.asset === undefined && value.nodes === undefined)) {
      throw new TypeError(`${where}: the glTF must be the parsed glTF JSON (an object with asset and nodes), ` +
                          'a Uint8Array or an ArrayBuffer');
    }
    return { typed: encodeGltf(`${where}: glTF`, value, withExtensions) };
  }

  // The readers, or the 'readers-not-loaded' error saying `why` they were needed (with the cause
  // of their last failed load).
  #loadedReaders(why) {
    if (this.#readers !== undefined) return this.#readers;
    const error = new SpringBonesError('readers-not-loaded', why);
    throw this.#readersError ? withCause(error, this.#readersError) : error;
  }

  /** The Decentraland content hash (CIDv1 string) of some bytes, as the catalyst computes it. */
  contentHash(bytes) {
    const view = toBytes('contentHash: bytes', bytes);
    const m = this.#m;
    const hash = withBytes(m, view, (ptr, size) => m.contentHash(ptr, size));
    if (hash === '') throw takeError(m);
    return hash;
  }

  /**
   * The creator tools (deploy-time validation and the Builder edits): a second WebAssembly
   * module, downloaded and started by the first call; every later call returns the same tools.
   * Takes the options createSpringBones takes, for the creator-tools module's .wasm
   * (dist/springbones_creator_tools.wasm by default). A failed load rejects, and the next call
   * tries again.
   */
  creatorTools(options = {}) {
    if (this.#creatorTools === undefined) {
      const m = this.#m;
      const resolve = (where, opts) => resolveHash(m, where, optionsObject(where, opts, kHashOptions));
      this.#creatorTools = import('./creator_tools.js')
        .then(({ loadCreatorTools }) => loadCreatorTools(options, resolve))
        .catch((error) => {
          this.#creatorTools = undefined;
          throw error;
        });
    }
    return this.#creatorTools;
  }

  /** A scene: many instances stepped in one call, optionally only the nearest ones. */
  createScene() {
    const m = this.#m;
    const handle = call(() => m.createScene());
    if (handle === 0) throw takeError(m);
    return new Scene(m, handle, this.#limits);
  }

  /** Diagnostics: live rigs, instances and scenes, WASM memory size and the bytes requested from malloc and not freed. */
  stats() {
    const s = takeTyped(this.#m, this.#m.stats());
    return {
      rigs: s.rigs, instances: s.instances, scenes: s.scenes,
      heapBytes: this.#m.HEAPU8.byteLength, heapInUse: s.heapInUse,
    };
  }

  #rig(handle, jumps = {}) {
    const m = this.#m;
    // Copied out: the description outlives the handle.
    const length = call(() => m.describeRig(handle));
    if (length === 0) {
      m.disposeRig(handle);
      throw takeError(m);
    }
    return new Rig(m, handle, typedResult(m, length), this.#limits, jumps);
  }
}

