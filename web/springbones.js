// springbones: spring-bone physics for avatar wearables, the JavaScript API.
//
// A thin ES module over the WebAssembly core (wasm/bindings.cpp). The contract is
// springbones.d.ts; DESIGN.md section 6 is the sketch it implements. What this file adds to the
// core: argument checks before anything crosses into WASM (TypeError for wrong types, RangeError
// for out-of-range values), one error type (SpringBonesError) for everything the core rejects,
// frozen plain data for the rig description, and typed-array views over the instance buffers
// that are rebuilt when WASM memory grows. Per frame exactly one call crosses the boundary
// (instance.step) and nothing is allocated on either side.
//
// The module files (dist/springbones_wasm.js + .wasm) are built by `scripts/build wasm` and
// copied next to this file. In Node the .wasm is read with fs and handed to the glue as
// wasmBinary (the glue is built for the web only, see wasm/CMakeLists.txt); in browsers the glue
// fetches it from dist/, relative to this file, with streaming compilation.

const kModuleUrl = new URL('./dist/springbones_wasm.wasm', import.meta.url);
const kIsNode =
  typeof process === 'object' && process !== null && typeof process.versions === 'object' &&
  process.versions !== null && typeof process.versions.node === 'string';

const kMaxStepHz = 1000;
const kMaxSubsteps = 64;

/** Every failure the library reports, apart from TypeError/RangeError for bad arguments. */
export class SpringBonesError extends Error {
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

/**
 * Loads and instantiates the WebAssembly module. Each call creates an independent module (its own
 * memory); one per page or process is the normal case.
 * @param {{wasmBinary?: ArrayBuffer | Uint8Array, wasmUrl?: string | URL}} [options]
 */
export async function createSpringBones(options = {}) {
  if (options === null || typeof options !== 'object') {
    throw new TypeError('createSpringBones: options must be an object');
  }
  checkKeys('createSpringBones', options, ['wasmBinary', 'wasmUrl']);
  const { wasmBinary, wasmUrl } = options;
  if (wasmBinary !== undefined && !(wasmBinary instanceof ArrayBuffer || wasmBinary instanceof Uint8Array)) {
    throw new TypeError('createSpringBones: wasmBinary must be an ArrayBuffer or a Uint8Array');
  }
  if (wasmUrl !== undefined && typeof wasmUrl !== 'string' && !(wasmUrl instanceof URL)) {
    throw new TypeError('createSpringBones: wasmUrl must be a string or a URL');
  }
  const url = wasmUrl === undefined ? kModuleUrl : new URL(wasmUrl, kModuleUrl);

  let factory;
  try {
    ({ default: factory } = await import('./dist/springbones_wasm.js'));
  } catch (cause) {
    throw withCause(new SpringBonesError('module-not-found',
        'the WebAssembly module (web/dist/springbones_wasm.js) could not be imported; build it ' +
        `with scripts/build wasm (${cause?.message ?? cause})`), cause);
  }

  const moduleOptions = {};
  try {
    if (wasmBinary !== undefined) {
      moduleOptions.wasmBinary = wasmBinary;
    } else if (kIsNode && url.protocol === 'file:') {
      const { readFile } = await import(/* webpackIgnore: true */ /* @vite-ignore */ 'node:fs/promises');
      moduleOptions.wasmBinary = await readFile(url);
    } else {
      moduleOptions.locateFile = () => url.href;
    }
    const module = await factory(moduleOptions);
    return new SpringBones(module);
  } catch (cause) {
    throw withCause(new SpringBonesError('module-load-failed',
        `the WebAssembly module (${url.href}) could not be loaded: ${cause?.message ?? cause}`), cause);
  }
}

// ---------------------------------------------------------------------------------------------

class SpringBones {
  #m;

  constructor(module) {
    this.#m = module;
  }

  /**
   * Loads a wearable: GLB (or glTF JSON) bytes, its data.springBones (object, JSON text, or
   * null/undefined for none) and which models entry applies.
   */
  loadRig(glbBytes, springBones, options) {
    const bytes = toBytes('loadRig: glbBytes', glbBytes);
    const metadataText = toJsonText('loadRig: springBones', springBones, /* allowNull */ true);
    const m = this.#m;
    let hash = '';
    if (options !== undefined && options !== null) {
      if (typeof options !== 'object') throw new TypeError('loadRig: options must be an object');
      checkKeys('loadRig', options, ['contentHash', 'entity', 'bodyShape']);
      const { contentHash, entity, bodyShape } = options;
      if (contentHash !== undefined) {
        if (typeof contentHash !== 'string') throw new TypeError('loadRig: contentHash must be a string');
        if (contentHash.length === 0) throw new RangeError('loadRig: contentHash must not be empty');
      }
      if (entity !== undefined || bodyShape !== undefined) {
        if (entity === undefined) throw new TypeError('loadRig: bodyShape needs an entity');
        if (typeof bodyShape !== 'string') {
          throw new TypeError('loadRig: with an entity, bodyShape must be a string (a body shape URN)');
        }
        if (bodyShape.length === 0) throw new RangeError('loadRig: bodyShape must not be empty');
      }
      const entityText = entity === undefined ? undefined : toJsonText('loadRig: entity', entity, false);
      // Preference order of DESIGN.md section 4: the caller's hash, then the entity's.
      if (contentHash !== undefined) {
        hash = contentHash;
      } else if (entityText !== undefined) {
        hash = call(() => m.mainFileHash(entityText, bodyShape));
        if (hash === '') throw takeError(m);
      }
    }
    const handle = withBytes(m, bytes, (ptr, size) => m.loadRig(ptr, size, metadataText, hash));
    if (handle === 0) throw takeError(m);
    const info = call(() => m.rigInfo(handle));
    if (info === '') {
      m.disposeRig(handle);
      throw takeError(m);
    }
    return new Rig(m, handle, JSON.parse(info));
  }

  /** The Decentraland content hash (CIDv1 string) of some bytes, as the catalyst computes it. */
  contentHash(bytes) {
    const view = toBytes('contentHash: bytes', bytes);
    const m = this.#m;
    const hash = withBytes(m, view, (ptr, size) => m.hashBytes(ptr, size));
    if (hash === '') throw takeError(m);
    return hash;
  }

  /** Diagnostics: live rigs and instances, WASM memory size and bytes in use by malloc. */
  stats() {
    const s = JSON.parse(this.#m.stats());
    return { rigs: s.rigs, instances: s.instances, heapBytes: this.#m.HEAPU8.byteLength, heapInUse: s.heapInUse };
  }
}

class Rig {
  #m;
  #handle;

  constructor(m, handle, info) {
    this.#m = m;
    this.#handle = handle;
    /** The models key the rig was built from. */
    this.contentHash = info.contentHash;
    /** Nodes in the GLB. */
    this.nodeCount = info.nodeCount;
    /** Simulated joints, parents before children; rotations[4*i..4*i+3] belongs to joints[i]. */
    this.joints = deepFreeze(info.joints);
    /** Indices into joints of the chain roots. */
    this.chains = deepFreeze(info.chains);
    /** Nodes whose world matrices the caller writes each frame; driverMatrices[16*i..] is drivers[i]. */
    this.drivers = deepFreeze(info.drivers);
    /** Everything the loader clamped, replaced or ignored: {code, message, path}. */
    this.warnings = deepFreeze(info.warnings);
    Object.freeze(this);
  }

  get disposed() {
    return this.#handle === 0;
  }

  /** A simulation state for one avatar wearing this item. */
  createInstance(options) {
    if (this.#handle === 0) throw disposedError('rig');
    let stepHz = 60;
    let maxSubsteps = 4;
    if (options !== undefined && options !== null) {
      if (typeof options !== 'object') throw new TypeError('createInstance: options must be an object');
      checkKeys('createInstance', options, ['stepHz', 'maxSubsteps', 'integrator']);
      if (options.stepHz !== undefined) {
        stepHz = options.stepHz;
        if (typeof stepHz !== 'number') throw new TypeError('createInstance: stepHz must be a number');
        if (!(stepHz >= 1 && stepHz <= kMaxStepHz)) {
          throw new RangeError(`createInstance: stepHz must be in [1, ${kMaxStepHz}], got ${stepHz}`);
        }
      }
      if (options.maxSubsteps !== undefined) {
        maxSubsteps = options.maxSubsteps;
        if (typeof maxSubsteps !== 'number') throw new TypeError('createInstance: maxSubsteps must be a number');
        if (!Number.isInteger(maxSubsteps) || maxSubsteps < 1 || maxSubsteps > kMaxSubsteps) {
          throw new RangeError(`createInstance: maxSubsteps must be an integer in [1, ${kMaxSubsteps}], got ${maxSubsteps}`);
        }
      }
      if (options.integrator !== undefined) {
        if (typeof options.integrator !== 'string') throw new TypeError('createInstance: integrator must be a string');
        if (options.integrator !== 'vrm') {
          throw new RangeError(`createInstance: integrator '${options.integrator}' is not available (only 'vrm')`);
        }
      }
    }
    const m = this.#m;
    const handle = call(() => m.createInstance(this.#handle, stepHz, maxSubsteps));
    if (handle === 0) throw takeError(m);
    return new Instance(m, handle);
  }

  /**
   * Releases the rig. Instances created from it keep working (they share its data) until they
   * are disposed of themselves. Calling dispose() again does nothing.
   */
  dispose() {
    if (this.#handle === 0) return;
    this.#m.disposeRig(this.#handle);
    this.#handle = 0;
  }
}

class Instance {
  #m;
  #handle;
  #driverPtr;
  #rotationsPtr;
  #driverFloats;
  #rotationFloats;
  #drivers;
  #rotations;

  constructor(m, handle) {
    this.#m = m;
    this.#handle = handle;
    this.#driverPtr = m.driverMatricesPtr(handle);
    this.#rotationsPtr = m.rotationsPtr(handle);
    this.#driverFloats = 16 * m.driverCount(handle);
    this.#rotationFloats = 4 * m.jointCount(handle);
    this.#drivers = this.#view(this.#driverPtr, this.#driverFloats);
    this.#rotations = this.#view(this.#rotationsPtr, this.#rotationFloats);
    Object.freeze(this);
  }

  get disposed() {
    return this.#handle === 0;
  }

  /** Driver world matrices (column-major 4x4, 16 floats per rig.drivers entry), written before step(). */
  get driverMatrices() {
    if (this.#handle === 0) throw disposedError('instance');
    if (this.#drivers.buffer !== this.#m.HEAPF32.buffer) {
      this.#drivers = this.#view(this.#driverPtr, this.#driverFloats);
    }
    return this.#drivers;
  }

  /** Local rotations (x, y, z, w), 4 floats per rig.joints entry, current after step(). */
  get rotations() {
    if (this.#handle === 0) throw disposedError('instance');
    if (this.#rotations.buffer !== this.#m.HEAPF32.buffer) {
      this.#rotations = this.#view(this.#rotationsPtr, this.#rotationFloats);
    }
    return this.#rotations;
  }

  /** Advances by a frame of dt seconds (fixed substeps inside). dt <= 0 does nothing. */
  step(dt) {
    if (this.#handle === 0) throw disposedError('instance');
    if (typeof dt !== 'number') throw new TypeError('step: dt must be a number of seconds');
    if (!Number.isFinite(dt)) throw new RangeError(`step: dt must be finite, got ${dt}`);
    this.#m.step(this.#handle, dt);
  }

  /** Forgets the motion (teleports, avatar swaps): the next step starts at rest. */
  reset() {
    if (this.#handle === 0) throw disposedError('instance');
    this.#m.reset(this.#handle);
  }

  /** Frees the instance; its views must not be used afterwards. Calling it again does nothing. */
  dispose() {
    if (this.#handle === 0) return;
    this.#m.disposeInstance(this.#handle);
    this.#handle = 0;
  }

  #view(ptr, length) {
    return new Float32Array(this.#m.HEAPF32.buffer, ptr, length);
  }
}

// ---------------------------------------------------------------------------------------------
// Helpers

function checkKeys(where, object, allowed) {
  for (const key of Object.keys(object)) {
    if (!allowed.includes(key)) {
      throw new TypeError(`${where}: unknown option '${key}' (known: ${allowed.join(', ')})`);
    }
  }
}

function toBytes(what, value) {
  if (value instanceof Uint8Array) return value;
  if (value instanceof ArrayBuffer) return new Uint8Array(value);
  throw new TypeError(`${what} must be a Uint8Array or an ArrayBuffer`);
}

// Objects are serialised; strings are taken as JSON text (the core parses and reports errors);
// null/undefined is "no spring bones" where allowed.
function toJsonText(what, value, allowNull) {
  if (typeof value === 'string') return value;
  if (value === null || value === undefined) {
    if (allowNull) return 'null';
    throw new TypeError(`${what} must be an object or JSON text`);
  }
  if (typeof value !== 'object') {
    throw new TypeError(`${what} must be an object, JSON text${allowNull ? ', null or undefined' : ''}`);
  }
  return JSON.stringify(value);  // throws TypeError itself for cycles and BigInt
}

// Copies bytes into WASM memory for the duration of fn(ptr, size).
function withBytes(m, bytes, fn) {
  const ptr = m._malloc(Math.max(1, bytes.length));
  if (ptr === 0) {
    throw new SpringBonesError('out-of-memory', `could not allocate ${bytes.length} bytes in WebAssembly memory`);
  }
  try {
    m.HEAPU8.set(bytes, ptr);  // read HEAPU8 after malloc: it may have grown the memory
    return call(() => fn(ptr, bytes.length));
  } finally {
    m._free(ptr);
  }
}

// The bindings catch every C++ exception; what can still come out of a call is a trap (a bug in
// the core, or running out of stack) or embind's own argument errors. Both become errors of ours.
function call(fn) {
  try {
    return fn();
  } catch (cause) {
    if (cause instanceof WebAssembly.RuntimeError) {
      throw withCause(new SpringBonesError('internal-error', `WebAssembly trap: ${cause.message}`), cause);
    }
    throw cause;
  }
}

function takeError(m) {
  const { code, message, path } = JSON.parse(m.takeError());
  return new SpringBonesError(code, message, path);
}

function disposedError(what) {
  return new SpringBonesError('disposed', `the ${what} has been disposed`);
}

function withCause(error, cause) {
  Object.defineProperty(error, 'cause', { value: cause, configurable: true, writable: true });
  return error;
}

function deepFreeze(value) {
  if (value !== null && typeof value === 'object') {
    for (const key of Object.keys(value)) deepFreeze(value[key]);
    Object.freeze(value);
  }
  return value;
}
