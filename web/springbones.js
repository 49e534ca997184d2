// springbones: spring-bone physics for avatar wearables, the JavaScript API.
//
// A thin ES module over the WebAssembly core's runtime module (wasm/bindings.cpp). The contract is
// springbones.d.ts; docs/design.md ("Across the JavaScript boundary") explains it. What this file adds to the
// core: argument checks before anything crosses into WASM (TypeError for wrong types, RangeError
// for out-of-range values), one error type (SpringBonesError) for everything the core rejects,
// frozen plain data for the rig description, and typed-array views over the instance buffers
// that are rebuilt when WASM memory grows. Per frame exactly one call crosses the boundary
// (instance.step, or scene.step for a whole page) and nothing is allocated on either side.
// Structured inputs cross as typed input (typed_value.js): what the page parsed, never JSON text.
// Bytes (a GLB, a VRM) are read by the readers module (readers.js), loaded beside the runtime in
// Node and by sb.readers() in browsers. Deploy-time validation and the Builder edits are the
// creator tools, another module loaded on first use by sb.creatorTools() (creator_tools.js).
//
// The module files (dist/springbones_wasm.js + .wasm) are built by `scripts/build wasm` and
// copied next to this file; module_loader.js fetches, compiles and instantiates them.

import { checkDenseArray, checkKeys, checkNonEmptyString, checkWellFormed, kHashOptions, optionsObject, toBytes } from './arguments.js';
import { SpringBonesError, call, takeError, withCause } from './errors.js';
import { instantiateModule, kIsNode, loadFailed, moduleSource } from './module_loader.js';
import { checkStringBound, encodeGltf, encodeTyped } from './typed_value.js';
import { version } from './version.js';
import { warmUpWhenIdle } from './warm_up.js';
import { withBytes, withRoomForStrings } from './wasm_memory.js';

export { SpringBonesError };

const kModuleUrl = new URL('./dist/springbones_wasm.wasm', import.meta.url);

/**
 * Loads and instantiates the WebAssembly module. Each call creates an independent module (its own
 * memory); one per page or process is the normal case.
 * @param {{wasm?: Response | WebAssembly.Module | Promise<Response | WebAssembly.Module>,
 *          wasmBinary?: ArrayBuffer | Uint8Array, wasmUrl?: string | URL}} [options]
 */
export async function createSpringBones(options = {}) {
  // In Node the readers come at once (local files, no download), so that loadRig and loadVrm take
  // bytes as they always have; a page loads them with sb.readers() when it has bytes to read.
  const readers = kIsNode ? loadReaders({}) : undefined;
  readers?.catch(() => {});  // reported by the first call that needs them (loadRig with bytes)
  const module = await instantiateModule('createSpringBones', options, {
    importGlue: () => import('./dist/springbones_wasm.js'),
    glueFile: 'web/dist/springbones_wasm.js',
    defaultUrl: kModuleUrl,
  });
  let limits;
  try {
    // The core's limits and defaults (limitsJson, springbones/boundary.h), read once: the argument checks below
    // use them, so the JS API never types a limit of its own.
    limits = deepFreeze(JSON.parse(module.limitsJson()));
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

  /**
   * Loads a wearable: the glTF JSON the page's loader already parsed (three.js: parser.json), or
   * GLB / glTF bytes (read by the readers module); its data.springBones (object, JSON text, or
   * null/undefined for none); which models entry applies; optional colliders.
   */
  loadRig(glb, springBones, options) {
    const gltf = this.#gltfInput('loadRig', glb, false);
    const metadata = typedMetadata(springBones, this.#limits);
    const opts = optionsObject('loadRig', options, [...kHashOptions, 'colliders', 'hitRadius', 'limits', ...kJumpOptions]);
    const rigOptions = typedRigOptions(opts);
    const jumps = jumpOptions('loadRig', opts, {});
    const m = this.#m;
    let hash = resolveHash(m, 'loadRig', opts);
    if (hash === '' && gltf.bytes !== undefined) hash = this.contentHash(gltf.bytes);
    if (hash === '' && springBones !== null && springBones !== undefined) {
      throw new TypeError('loadRig: the glTF was given parsed, so there are no bytes to hash: say which ' +
                          'springBones.models entry applies with contentHash, or entity and bodyShape');
    }
    const handle = withBytes(m, gltf.typed, (gltfPtr, gltfSize) => withBytes(m, metadata,
      (metaPtr, metaSize) => withBytes(m, rigOptions, (optPtr, optSize) => withRoomForStrings(m, [hash],
        () => m.loadRig(gltfPtr, gltfSize, metaPtr, metaSize, hash, optPtr, optSize)))));
    if (handle === 0) throw takeError(m);
    return this.#rig(handle, jumps);
  }

  /**
   * Loads the spring bones of a VRM avatar (.vrm bytes, or the glTF JSON a loader parsed):
   * VRMC_springBone 1.0, or VRM 0.x secondaryAnimation, with their colliders. The rig has the same
   * interface as loadRig's.
   */
  loadVrm(vrm) {
    const gltf = this.#gltfInput('loadVrm', vrm, true);
    const m = this.#m;
    const handle = withBytes(m, gltf.typed, (ptr, size) => m.loadVrm(ptr, size));
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
      if (this.#readers === undefined) {
        const error = new SpringBonesError('readers-not-loaded',
          `${where} was given bytes, which the readers module reads, and it is not loaded: ` +
          'await sb.readers() first, or pass the glTF JSON your loader already parsed (three.js: gltf.parser.json)');
        throw this.#readersError ? withCause(error, this.#readersError) : error;
      }
      return { typed: this.#readers.readGltf(bytes, withExtensions), bytes };
    }
    if (value === null || typeof value !== 'object' || Array.isArray(value) || ArrayBuffer.isView(value) ||
        (value.asset === undefined && value.nodes === undefined)) {
      throw new TypeError(`${where}: the glTF must be the parsed glTF JSON (an object with asset and nodes), ` +
                          'a Uint8Array or an ArrayBuffer');
    }
    return { typed: encodeGltf(`${where}: glTF`, value, withExtensions) };
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
      const resolve = (where, opts) => resolveHash(m, where, opts);
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

  /** Diagnostics: live rigs, instances and scenes, WASM memory size and bytes in use by malloc. */
  stats() {
    const s = JSON.parse(this.#m.stats());
    return {
      rigs: s.rigs, instances: s.instances, scenes: s.scenes,
      heapBytes: this.#m.HEAPU8.byteLength, heapInUse: s.heapInUse,
    };
  }

  #rig(handle, jumps = {}) {
    const m = this.#m;
    // Copied out as text: the description outlives the handle.
    const text = call(() => m.describeRig(handle));
    if (text === '') {
      m.disposeRig(handle);
      throw takeError(m);
    }
    return new Rig(m, handle, text, this.#limits, jumps);
  }
}

const kIntegrators = ['vrm', 'xpbd'];
const kJumpOptions = ['jumpDistance', 'jumpAngle'];

// jumpDistance and jumpAngle of an options object, checked, over `defaults` (a rig's).
function jumpOptions(where, options, defaults) {
  const out = { ...defaults };
  for (const key of kJumpOptions) {
    if (options[key] !== undefined) out[key] = checkNonNegative(`${where}: ${key}`, options[key]);
  }
  return out;
}

// Accessors into the private fields of instances and scenes for the other classes of this file,
// installed by their static blocks.
let instanceInternals;
let sceneInternals;

class Rig {
  #m;
  #handle;
  #descriptionText;  // the core's JSON text (describeRig, springbones/boundary.h) until its first read
  #description;
  #limits;
  #jumps;  // loadRig's jumpDistance / jumpAngle, the default of its instances

  constructor(m, handle, descriptionText, limits, jumps = {}) {
    this.#m = m;
    this.#handle = handle;
    this.#descriptionText = descriptionText;
    this.#limits = limits;
    this.#jumps = jumps;
    Object.freeze(this);
  }

  // The description's fields (springbones.d.ts documents each): frozen plain data, parsed on the
  // first read of any (the per-frame path never needs them) and the same objects on every read
  // after; readable after dispose().
  static {
    for (const key of ['contentHash', 'format', 'nodeCount', 'joints', 'chains', 'drivers', 'colliders', 'warnings']) {
      Object.defineProperty(Rig.prototype, key, { get() { return this.#parsedDescription()[key]; }, configurable: true });
    }
  }

  #parsedDescription() {
    if (this.#description === undefined) {
      this.#description = deepFreeze(JSON.parse(this.#descriptionText));
      this.#descriptionText = undefined;
    }
    return this.#description;
  }

  get disposed() {
    return this.#handle === 0;
  }

  /** A simulation state for one avatar wearing this item. */
  createInstance(options) {
    if (this.#handle === 0) throw disposedError('rig');
    const opts = optionsObject('createInstance', options,
                               ['stepHz', 'maxSubsteps', 'integrator', 'xpbdIterations', 'inertia', ...kJumpOptions]);
    const jumps = jumpOptions('createInstance', opts, this.#jumps);
    const integrator = opts.integrator === undefined
      ? 'vrm' : checkOneOf('createInstance: integrator', opts.integrator, kIntegrators);
    // 0 leaves a value to the core's default for the integrator.
    const { maxStepHz, maxSubsteps: maxSubstepsLimit, maxXpbdIterations, integrators } = this.#limits;
    const stepHz = opts.stepHz === undefined ? 0 : checkRange('createInstance: stepHz', opts.stepHz, 1, maxStepHz);
    const maxSubsteps = opts.maxSubsteps === undefined
      ? 0 : checkInteger('createInstance: maxSubsteps', opts.maxSubsteps, 1, maxSubstepsLimit);
    let xpbdIterations = integrators.xpbd.xpbdIterations;
    if (opts.xpbdIterations !== undefined) {
      xpbdIterations = checkInteger('createInstance: xpbdIterations', opts.xpbdIterations, 1, maxXpbdIterations);
      if (integrator !== 'xpbd') {
        throw new RangeError("createInstance: xpbdIterations only applies to integrator 'xpbd'");
      }
    }
    const inertia = opts.inertia === undefined ? undefined : checkRange('createInstance: inertia', opts.inertia, 0, 1);
    const m = this.#m;
    const handle = call(() => m.createInstance(this.#handle, stepHz, maxSubsteps,
                                               integrator === 'xpbd' ? 1 : 0, xpbdIterations));
    if (handle === 0) throw takeError(m);
    if (jumps.jumpDistance !== undefined || jumps.jumpAngle !== undefined) {
      // NaN keeps the core's default for the one not given.
      m.setJumpThresholds(handle, jumps.jumpDistance ?? NaN, jumps.jumpAngle ?? NaN);
    }
    if (inertia !== undefined) m.setInertia(handle, inertia, -1);
    // The chain count for setInertia's check, read from the description only when it is needed.
    return new Instance(m, handle, this.#limits, () => this.chains.length);
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
  #limits;
  #driverPtr;
  #rotationsPtr;
  #worldPtr;
  #driverFloats;
  #rotationFloats;
  #drivers;
  #rotations;
  #world;
  #scenes = new Set();  // scenes this instance is in, left on dispose
  #chainCount;  // () => the rig's chain count

  static {
    instanceInternals = {
      module: (instance) => instance.#m,
      handle: (instance) => instance.#handle,
      scenes: (instance) => instance.#scenes,
    };
  }

  constructor(m, handle, limits, chainCount) {
    this.#m = m;
    this.#handle = handle;
    this.#limits = limits;
    this.#chainCount = chainCount;
    this.#driverPtr = m.driverMatricesPtr(handle);
    this.#rotationsPtr = m.rotationsPtr(handle);
    this.#worldPtr = m.worldMatricesPtr(handle);
    this.#driverFloats = 16 * m.driverCount(handle);
    this.#rotationFloats = 4 * m.jointCount(handle);
    this.#drivers = this.#view(this.#driverPtr, this.#driverFloats);
    this.#rotations = this.#view(this.#rotationsPtr, this.#rotationFloats);
    this.#world = this.#view(this.#worldPtr, 4 * this.#rotationFloats);
    Object.freeze(this);
  }

  get disposed() {
    return this.#handle === 0;
  }

  /** Driver world matrices (column-major 4x4, 16 floats per rig.drivers entry), written before step(). */
  get driverMatrices() {
    this.#live();
    if (isStale(this.#m, this.#drivers, this.#driverFloats)) {
      this.#drivers = this.#view(this.#driverPtr, this.#driverFloats);
    }
    return this.#drivers;
  }

  /** Local rotations (x, y, z, w), 4 floats per rig.joints entry, current after step(). */
  get rotations() {
    this.#live();
    if (isStale(this.#m, this.#rotations, this.#rotationFloats)) {
      this.#rotations = this.#view(this.#rotationsPtr, this.#rotationFloats);
    }
    return this.#rotations;
  }

  /**
   * Joint world matrices (column-major 4x4, 16 floats per rig.joints entry) after the last step.
   * The core writes them on request, so each read of this property is one call into WebAssembly.
   */
  get worldMatrices() {
    this.#m.worldMatricesPtr(this.#live());  // fills the buffer; its address never changes
    if (isStale(this.#m, this.#world, 4 * this.#rotationFloats)) {
      this.#world = this.#view(this.#worldPtr, 4 * this.#rotationFloats);
    }
    return this.#world;
  }

  /** Advances by a frame of dt seconds (fixed substeps inside). dt <= 0 does nothing. */
  step(dt) {
    this.#m.step(this.#live(), checkDt(dt));
  }

  /**
   * Fixed steps the last frame ran (its step, or its scene's): 0 when dt did not reach the next
   * step or a scene's budget held the instance; maxSubsteps when the frame was longer.
   */
  get lastSteps() {
    return this.#m.lastSteps(this.#live());
  }

  /** Forgets the motion (avatar swaps): the next step starts at rest. */
  reset() {
    this.#m.reset(this.#live());
  }

  /**
   * Treats the driver change before the next step as a discontinuity (an animation starting, a
   * cut): the chains are carried across it with the drivers they hang from, keeping their shape
   * and motion, with no whip. Teleports and snap turns beyond jumpDistance / jumpAngle are
   * noticed without it.
   */
  jump() {
    this.#m.jump(this.#live());
  }

  /**
   * Wind on this instance from its next step on: {direction: [x, y, z] (world, normalized),
   * strength (world units per second, like gravityPower), gustFrequency? (gusts per second, 0:
   * steady), seed? (an integer; the same seed, the same gusts)}; null for none. Overrides its
   * scenes' wind until a scene's is set again.
   */
  setWind(wind) {
    this.#m.setWind(this.#live(), ...windArguments('setWind', wind, this.#limits));
  }

  /**
   * Takes over the motion of `previous`, an instance of another rig of the same skeleton (the rig
   * rebuilt with edited parameters), with no pop: call it after writing this instance's
   * driverMatrices with the pose `previous` last stepped under, before this instance's first step.
   * Joints both rigs have keep their tail state (position and velocity) and rotation, new joints
   * start at rest; the step clock and wind carry over. `previous` is left as it is.
   */
  carryFrom(previous) {
    if (!(previous instanceof Instance)) throw new TypeError('carryFrom: previous must be an instance from rig.createInstance()');
    if (previous.#m !== this.#m) throw new TypeError('carryFrom: previous belongs to another springbones module');
    if (previous.#handle === 0) throw disposedError('instance');
    this.#m.carryFrom(this.#live(), previous.#handle);
  }

  /** Discontinuities carried so far (jump() calls that reached a step, and detected jumps). */
  get jumps() {
    return this.#m.jumps(this.#live());
  }

  /**
   * Runs the springs to rest under the driver matrices as they are, without a frame (thumbnails,
   * turntables, emote starts): at most `seconds` x stepHz steps, fewer once no joint turns any
   * more. Deterministic; returns the steps it ran. The next step starts from there at rest.
   */
  settle(seconds = this.#limits.settleSeconds) {
    const handle = this.#live();
    checkRange('settle: seconds', seconds, 0, this.#limits.maxSettleSeconds);
    return this.#m.settle(handle, seconds);
  }

  /**
   * Holds rig.joints[joint]'s tail toward a world point ([x, y, z]) from the next step on, as far
   * as its chain reaches, colliders still holding; call it every frame with the moving point.
   * RangeError for a disposed instance, a joint out of range or a non-finite point.
   */
  grab(joint, point) {
    const handle = this.#grabHandle('grab');
    checkInteger('grab: joint', joint, 0, this.#rotationFloats / 4 - 1);
    const [x, y, z] = checkVec3('grab: point', point);
    this.#m.grab(handle, joint, x, y, z);
  }

  /** Lets go of the grabbed joint: the chain swings back from where it is. RangeError once disposed. */
  release() {
    this.#m.release(this.#grabHandle('release'));
  }

  /** The joint grab() holds, or -1. */
  get grabbedJoint() {
    return this.#m.grabbedJoint(this.#live());
  }

  /**
   * How much of the motion of the driver a chain hangs from it feels, in [0, 1]: 1 all of it (the
   * default), 0 none (hair calm in a vehicle). `chain`: an index into rig.chains; omitted, every
   * chain. From the next step on.
   */
  setInertia(value, chain) {
    const handle = this.#live();
    checkRange('setInertia: value', value, 0, 1);
    let index = -1;
    if (chain !== undefined) index = checkInteger('setInertia: chain', chain, 0, this.#chainCount() - 1);
    this.#m.setInertia(handle, value, index);
  }

  /**
   * Frees the instance, first taking it out of every scene it is in; its views must not be used
   * afterwards. Calling it again does nothing.
   */
  dispose() {
    if (this.#handle === 0) return;
    for (const scene of this.#scenes) sceneInternals.forget(scene, this);
    this.#scenes.clear();
    this.#m.disposeInstance(this.#handle);  // also removes it from the scenes on the WASM side
    this.#handle = 0;
  }

  // The handle, checked: every method but dispose() throws once the instance is disposed of.
  #live() {
    if (this.#handle === 0) throw disposedError('instance');
    return this.#handle;
  }

  // grab and release take a disposed instance for a bad argument, as an out-of-range joint: a
  // pointer handler keeps calling them with whatever instance it last picked.
  #grabHandle(where) {
    if (this.#handle === 0) throw new RangeError(`${where}: the instance has been disposed`);
    return this.#handle;
  }

  #view(ptr, length) {
    return new Float32Array(this.#m.HEAPF32.buffer, ptr, length);
  }
}

class Scene {
  #m;
  #handle;
  #limits;
  #members = [];  // instances in slot order, as the core holds them
  #positions;
  #active;

  static {
    sceneInternals = {
      forget: (scene, instance) => scene.#forget(instance),
    };
  }

  constructor(m, handle, limits) {
    this.#m = m;
    this.#handle = handle;
    this.#limits = limits;
    this.#refresh();
    Object.freeze(this);
  }

  get disposed() {
    return this.#handle === 0;
  }

  /** Number of instances in the scene. */
  get size() {
    return this.#members.length;
  }

  /**
   * x, y, z per instance in slot order (the order of add(); slots shift down on remove), written
   * by the caller, e.g. each avatar's root position; used by the budget. Same view rules as
   * instance.driverMatrices, and the view is also replaced by add() and remove().
   */
  get positions() {
    this.#live();
    if (isStale(this.#m, this.#positions, 3 * this.#members.length)) this.#refresh();
    return this.#positions;
  }

  /**
   * isActive for every instance at once: 1 or 0 per slot, in slot order, as the last step left
   * them (1 before any step). For pages that handle many avatars a frame (the three.js group
   * writes only the active ones' bones). Read-only; same view rules as positions.
   */
  get active() {
    this.#live();
    if (isStale(this.#m, this.#active, this.#members.length)) this.#refresh();
    return this.#active;
  }

  /** Adds an instance (of this module) and returns its slot; adding it again returns the same slot. */
  add(instance) {
    const handle = this.#instanceHandle('add', instance);
    const existing = this.#members.indexOf(instance);
    if (existing >= 0) return existing;
    const m = this.#m;
    const slot = call(() => m.sceneAdd(this.#handle, handle));
    if (slot === 0) throw takeError(m);
    this.#members.push(instance);
    instanceInternals.scenes(instance).add(this);
    this.#refresh();
    return slot - 1;
  }

  /** Takes an instance out (its later slots shift down). Not in the scene: nothing happens. */
  remove(instance) {
    const handle = this.#instanceHandle('remove', instance);
    if (!this.#members.includes(instance)) return;
    this.#m.sceneRemove(this.#handle, handle);
    instanceInternals.scenes(instance).delete(this);
    this.#forget(instance);
  }

  /** The slot of an instance in positions, or -1 when it is not in the scene. */
  slotOf(instance) {
    this.#live();
    return this.#members.indexOf(instance);
  }

  /**
   * Simulate only the maxActive instances nearest to the viewer (the others hold their last pose
   * and restart from rest when they come back). maxActive null or Infinity: no budget.
   */
  setBudget(maxActive, viewerX = 0, viewerY = 0, viewerZ = 0) {
    const handle = this.#live();
    let max = -1;
    if (maxActive !== null && maxActive !== Infinity) {
      max = checkInteger('setBudget: maxActive', maxActive, 0, 0x7fffffff);
    }
    // Checked one by one, not through an array of pairs: pages call this every frame. They cross
    // as float32, where a larger value is infinite and the core would ignore the viewer.
    checkFloat32('setBudget: viewerX', viewerX);
    checkFloat32('setBudget: viewerY', viewerY);
    checkFloat32('setBudget: viewerZ', viewerZ);
    this.#m.sceneSetBudget(handle, max, viewerX, viewerY, viewerZ);
  }

  /**
   * Wind on every instance of the scene, and on each one added later (instance.setWind's
   * argument; null for none). An instance's own setWind afterwards overrides it for that one.
   */
  setWind(wind) {
    this.#m.sceneSetWind(this.#live(), ...windArguments('setWind', wind, this.#limits));
  }

  /** Steps every instance (or the budget's nearest) by dt seconds, in one call into WebAssembly. */
  step(dt) {
    this.#m.sceneStep(this.#live(), checkDt(dt));
  }

  /** Whether the instance was simulated by the last step (false when it is not in the scene). */
  isActive(instance) {
    this.#live();
    const slot = this.#members.indexOf(instance);
    return slot >= 0 && this.#m.sceneIsActive(this.#handle, slot);
  }

  /** Frees the scene; its instances are not disposed of. Calling it again does nothing. */
  dispose() {
    if (this.#handle === 0) return;
    for (const instance of this.#members) instanceInternals.scenes(instance).delete(this);
    this.#members = [];
    this.#m.disposeScene(this.#handle);
    this.#handle = 0;
  }

  // The handle, checked: every method but dispose() throws once the scene is disposed of.
  #live() {
    if (this.#handle === 0) throw disposedError('scene');
    return this.#handle;
  }

  #instanceHandle(where, instance) {
    this.#live();
    if (!(instance instanceof Instance)) throw new TypeError(`${where}: expected an instance from rig.createInstance()`);
    if (instanceInternals.module(instance) !== this.#m) {
      throw new TypeError(`${where}: the instance belongs to another springbones module`);
    }
    const handle = instanceInternals.handle(instance);
    if (handle === 0) throw disposedError('instance');
    return handle;
  }

  // The core dropped the instance (remove, or its dispose): mirror the slot shift.
  #forget(instance) {
    const slot = this.#members.indexOf(instance);
    if (slot >= 0) this.#members.splice(slot, 1);
    this.#refresh();
  }

  // The views, made again: after add() and remove(), and when memory growth detached them.
  #refresh() {
    const m = this.#m;
    this.#positions = new Float32Array(m.HEAPF32.buffer, m.scenePositionsPtr(this.#handle), 3 * this.#members.length);
    this.#active = new Uint8Array(m.HEAPU8.buffer, m.sceneActivePtr(this.#handle), this.#members.length);
  }
}

// ---------------------------------------------------------------------------------------------
// Helpers

/**
 * Whether a view of `length` elements on the module's memory has to be made again: memory growth
 * replaces the ArrayBuffer and detaches every view on the old one, which drops its length to 0.
 * Comparing lengths is what the per-frame getters can afford (TypedArray.prototype.buffer is a
 * runtime call in V8, ~35 ns); only an empty view needs the buffer compared.
 */
function isStale(m, view, length) {
  return view.length !== length || (length === 0 && view.buffer !== m.HEAPU8.buffer);
}

// Which models key applies (docs/semantics.md, "Which models entry"): the caller's hash, then the entity's; '' lets
// the core hash the GLB itself.
function resolveHash(m, where, options) {
  const { contentHash, entity, bodyShape } = options;
  if (contentHash !== undefined) checkStringBound(`${where}: contentHash`, checkNonEmptyString(`${where}: contentHash`, contentHash));
  if (entity !== undefined || bodyShape !== undefined) {
    if (entity === undefined) throw new TypeError(`${where}: bodyShape needs an entity`);
    if (typeof bodyShape !== 'string') {
      throw new TypeError(`${where}: with an entity, bodyShape must be a string (a body shape URN)`);
    }
    checkStringBound(`${where}: bodyShape`, checkNonEmptyString(`${where}: bodyShape`, bodyShape));
  }
  const typedEntity = entity === undefined ? undefined : encodeTyped(`${where}: entity`, parsedArgument(
    `${where}: entity`, entity, 'entity-bad-json', 'an object or JSON text'));
  if (contentHash !== undefined) return contentHash;
  if (typedEntity === undefined) return '';
  const hash = call(() => withBytes(m, typedEntity, (ptr, size) => withRoomForStrings(m, [bodyShape],
    () => m.mainFileHashFor(ptr, size, bodyShape))));
  if (hash === '') throw takeError(m);
  return hash;
}

// An object argument, or JSON text parsed here (a SpringBonesError with `badJsonCode` when it does
// not parse).
function parsedArgument(what, value, badJsonCode, described) {
  if (typeof value === 'string') {
    checkWellFormed(what, value);
    try {
      return JSON.parse(value);
    } catch (cause) {
      throw withCause(new SpringBonesError(badJsonCode, `${what} JSON does not parse: ${cause.message}`), cause);
    }
  }
  if (value === null || typeof value !== 'object') throw new TypeError(`${what} must be ${described}`);
  return value;
}

// data.springBones as typed input: an object, JSON text (at most maxMetadataBytes), or
// null/undefined for none.
function typedMetadata(springBones, limits) {
  const what = 'loadRig: springBones';
  if (springBones === null || springBones === undefined) return encodeTyped(what, null);
  if (typeof springBones === 'string' && springBones.length > limits.maxMetadataBytes / 3 &&
      new TextEncoder().encode(springBones).length > limits.maxMetadataBytes) {
    throw new SpringBonesError('limit-exceeded',
      `springBones JSON is more than the limit of ${limits.maxMetadataBytes} bytes`);
  }
  return encodeTyped(what, parsedArgument(what, springBones, 'metadata-bad-json',
                                          'an object, JSON text, null or undefined'));
}

// The colliders (a list, or a preset's name) and hitRadius of loadRig's options, checked, as the
// typed input the bindings read (no bytes for none).
function typedRigOptions(options) {
  const { colliders, hitRadius, limits } = options;
  if (colliders === undefined && hitRadius === undefined && limits === undefined) return new Uint8Array(0);
  const out = {};
  if (limits !== undefined) out.limits = checkedLimits('loadRig: limits', limits);
  if (hitRadius !== undefined) out.hitRadius = checkNonNegative('loadRig: hitRadius', hitRadius);
  if (typeof colliders === 'string') {
    if (!kColliderPresets.includes(colliders)) {
      throw new RangeError(`loadRig: colliders must be an array or one of ${kColliderPresets.join(', ')}, got '${colliders}'`);
    }
    out.preset = colliders;
  } else if (colliders !== undefined) {
    if (!Array.isArray(colliders)) throw new TypeError(`loadRig: colliders must be an array or '${kColliderPresets[0]}'`);
    out.colliders = checkDenseArray('loadRig: colliders', colliders).map((c, i) => colliderJson(`loadRig: colliders[${i}]`, c));
  }
  return encodeTyped('loadRig: options', out);
}

const kColliderShapes = ['sphere', 'capsule', 'plane'];

// One collider of loadRig's options, checked: a sphere, a capsule (a tail) or a plane (a normal),
// as `shape` says or, without it, as a tail makes it a capsule. Sphere and capsule take `inside`.
function colliderJson(where, c) {
  if (c === null || typeof c !== 'object' || Array.isArray(c)) throw new TypeError(`${where} must be an object`);
  checkKeys(where, c, ['node', 'shape', 'offset', 'radius', 'tail', 'normal', 'inside']);
  checkNonEmptyString(`${where}.node`, c.node, 'a string (a node name)');
  if (c.shape !== undefined) checkOneOf(`${where}.shape`, c.shape, kColliderShapes);
  const shape = c.shape ?? (c.tail !== undefined ? 'capsule' : 'sphere');
  const only = (key, shapes) => {
    if (c[key] !== undefined && !shapes.includes(shape)) {
      throw new TypeError(`${where}.${key} is not a property of a ${shape} collider`);
    }
  };
  only('tail', ['capsule']);
  only('normal', ['plane']);
  only('radius', ['sphere', 'capsule']);
  only('inside', ['sphere', 'capsule']);
  const collider = { node: c.node, offset: c.offset === undefined ? [0, 0, 0] : checkVec3(`${where}.offset`, c.offset) };
  if (shape === 'plane') {
    const normal = c.normal === undefined ? [0, 0, 1] : checkVec3(`${where}.normal`, c.normal);
    if (normal.every((v) => v === 0)) throw new RangeError(`${where}.normal must not be [0, 0, 0]`);
    collider.normal = scaledDirection(normal);
    return collider;
  }
  collider.radius = checkNonNegative(`${where}.radius`, c.radius);
  if (shape === 'capsule') collider.tail = c.tail === undefined ? [0, 0, 0] : checkVec3(`${where}.tail`, c.tail);
  if (c.inside !== undefined) {
    if (typeof c.inside !== 'boolean') throw new TypeError(`${where}.inside must be a boolean`);
    collider.inside = c.inside;
  }
  return collider;
}

const kColliderPresets = ['dcl-body'];

// loadRig's `limits`: joint names to one limit each, as VRMC_springBone_limit spells it. Types and
// shapes are checked here; the core clamps angles out of the draft's ranges with a warning.
function checkedLimits(where, limits) {
  if (limits === null || typeof limits !== 'object' || Array.isArray(limits)) {
    throw new TypeError(`${where} must be an object of joint names`);
  }
  const out = Object.create(null);  // a joint may be called __proto__
  for (const [name, limit] of Object.entries(limits)) {
    const at = `${where}[${JSON.stringify(name)}]`;
    if (limit === null || typeof limit !== 'object' || Array.isArray(limit)) {
      throw new TypeError(`${at} must be an object`);
    }
    const kinds = Object.keys(limit);
    if (kinds.length !== 1 || !['cone', 'hinge', 'spherical'].includes(kinds[0])) {
      throw new TypeError(`${at} must have exactly one of cone, hinge, spherical`);
    }
    const kind = kinds[0];
    const shape = limit[kind];
    if (shape === null || typeof shape !== 'object' || Array.isArray(shape)) {
      throw new TypeError(`${at}.${kind} must be an object`);
    }
    const angles = kind === 'spherical' ? ['pitch', 'yaw'] : ['angle'];
    checkKeys(`${at}.${kind}`, shape, [...angles, 'rotation']);
    const checked = {};
    for (const key of angles) checked[key] = checkFinite(`${at}.${kind}.${key}`, shape[key]);
    if (shape.rotation !== undefined) {
      const r = shape.rotation;
      if (!(Array.isArray(r) || ArrayBuffer.isView(r)) || r.length !== 4) {
        throw new TypeError(`${at}.${kind}.rotation must be 4 numbers (x, y, z, w)`);
      }
      checked.rotation = Array.from(r, (v, i) => checkFinite(`${at}.${kind}.rotation[${i}]`, v));
      if (checked.rotation.every((v) => v === 0)) {
        throw new RangeError(`${at}.${kind}.rotation must not be [0, 0, 0, 0]`);
      }
    }
    out[name] = { [kind]: checked };
  }
  return out;
}
const kWindKeys = ['direction', 'strength', 'gustFrequency', 'seed'];

// setWind's argument, checked against the core's limits: [dx, dy, dz, strength, gustFrequency,
// seed]; null is no wind.
function windArguments(where, wind, limits) {
  if (wind === null) return [1, 0, 0, 0, 0, 0];
  if (typeof wind !== 'object' || Array.isArray(wind)) {
    throw new TypeError(`${where}: wind must be an object {direction, strength, gustFrequency?, seed?} or null`);
  }
  checkKeys(`${where}: wind`, wind, kWindKeys);
  const direction = checkVec3(`${where}: wind.direction`, wind.direction);
  const strength = checkRange(`${where}: wind.strength`, wind.strength, 0, limits.maxWindStrength);
  const gustFrequency = wind.gustFrequency === undefined
    ? 0 : checkRange(`${where}: wind.gustFrequency`, wind.gustFrequency, 0, limits.maxGustFrequency);
  const seed = wind.seed === undefined ? 0 : checkInteger(`${where}: wind.seed`, wind.seed, 0, 0xffffffff);
  if (direction.every((v) => v === 0)) {
    if (strength > 0) throw new RangeError(`${where}: wind.direction must not be zero`);
    return [1, 0, 0, strength, gustFrequency, seed];
  }
  return [...scaledDirection(direction), strength, gustFrequency, seed];
}

function checkRange(what, value, min, max) {
  if (typeof value !== 'number') throw new TypeError(`${what} must be a number`);
  if (!(value >= min && value <= max)) throw new RangeError(`${what} must be in [${min}, ${max}], got ${value}`);
  return value;
}

function checkFinite(what, value) {
  if (typeof value !== 'number') throw new TypeError(`${what} must be a number`);
  if (!Number.isFinite(value)) throw new RangeError(`${what} must be finite, got ${value}`);
  return value;
}

// A finite number that is finite as float32 too (|value| below 2^128 less half a float32 step).
function checkFloat32(what, value) {
  checkFinite(what, value);
  if (!Number.isFinite(Math.fround(value))) throw new RangeError(`${what} must be within float32's range (about ±3.4e38), got ${value}`);
  return value;
}

function checkOneOf(what, value, choices) {
  if (typeof value !== 'string') throw new TypeError(`${what} must be a string`);
  if (!choices.includes(value)) throw new RangeError(`${what} must be one of ${choices.join(', ')}, got '${value}'`);
  return value;
}

function checkVec3(what, value) {
  if (!(Array.isArray(value) || ArrayBuffer.isView(value)) || value.length !== 3) {
    throw new TypeError(`${what} must be an array of 3 numbers`);
  }
  if (Array.isArray(value)) checkDenseArray(what, value);  // a hole is a TypeError that says so
  const out = Array.from(value);
  for (const v of out) {
    if (typeof v !== 'number') throw new TypeError(`${what} must be an array of 3 numbers`);
    checkFinite(what, v);
  }
  return out;
}

// A direction (3 finite numbers, not all 0) as it crosses, as float32: one whose largest
// component is beyond float32's normal range ([1e39, 0, 0] would be infinite there, [1e-46, 0, 0]
// zero) is divided by that component's size first, in double precision. The core makes it unit,
// scaled alike first, so [1e20, 0, 0] or [1e-25, 0, 0] do not overflow or underflow there either.
// Others cross unchanged, so that native and JavaScript callers giving the same direction get
// the same bits.
function scaledDirection(v) {
  const largest = Math.max(Math.abs(v[0]), Math.abs(v[1]), Math.abs(v[2]));
  return largest >= 2 ** -126 && largest < 2 ** 127 ? v : v.map((c) => c / largest);
}

function checkNonNegative(what, value) {
  if (typeof value !== 'number') throw new TypeError(`${what} must be a number`);
  if (!(Number.isFinite(value) && value >= 0)) throw new RangeError(`${what} must be finite and >= 0, got ${value}`);
  return value;
}

function checkInteger(what, value, min, max) {
  if (typeof value !== 'number') throw new TypeError(`${what} must be a number`);
  if (!Number.isInteger(value) || value < min || value > max) {
    throw new RangeError(`${what} must be an integer in [${min}, ${max}], got ${value}`);
  }
  return value;
}

function checkDt(dt) {
  if (typeof dt !== 'number') throw new TypeError('step: dt must be a number of seconds');
  return checkFinite('step: dt', dt);
}

function disposedError(what) {
  return new SpringBonesError('disposed', `the ${what} has been disposed`);
}

function deepFreeze(value) {
  if (value !== null && typeof value === 'object') {
    for (const key of Object.keys(value)) deepFreeze(value[key]);
    Object.freeze(value);
  }
  return value;
}
