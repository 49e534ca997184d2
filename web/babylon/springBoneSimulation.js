// springbones for Babylon.js: a drop-in for the `SpringBoneSimulation` class of Decentraland's
// wearable preview (the same four methods with the same arguments, constructed with no argument),
// with the standard's rules from the core: roots by isRoot, branches, member overrides, tips,
// defaults and clamps, centers, colliders, fixed steps.
//
//   const simulation = new SpringBoneSimulation();             // or (sb), or (createSpringBones())
//   container.addAllToScene();
//   simulation.registerWearable(scene, container, urn, springBones.models[hash]);
//   simulation.start(scene);                                   // one before-render step per frame
//   simulation.updateParams(urn, editedEntry);                 // the Builder's live tuning
//   simulation.dispose(scene);                                 // and register + start again later
//
// A wearable is read from its container (wearableSkeleton.js): the glTF nodes Babylon's loader
// made, their rest transforms, in the glTF's space (handedness.js). Per frame, in the scene's
// before-render (after the animations moved the nodes): each driver's world matrix, made current
// (currentWorldMatrices.js), goes into its instance's driverMatrices (mirrored into the glTF's
// space), one scene.step(dt) steps every registered wearable, and each joint's rotation goes
// into its rotationQuaternion. No allocation per frame.
//
// A page that drops this in changes its import line only, so nothing that leaves hair still may
// pass silently: each such case (the module failing to load, an entry without isRoot, a hash or
// id that matches nothing, a driver bone not found) is one console warning per wearable and an
// entry in `warnings`, never a throw from the preview's four methods.
//
// Babylon itself is never imported: everything comes from the scene and containers passed in,
// so the same file serves Babylon 4.2 (`babylonjs` and `@babylonjs/core`) and the current major.
import { pageModule } from '../page_module.js';
import { nodesToRecompute } from './currentWorldMatrices.js';
import { copyWorldMatrix, isMirroredScene } from './handedness.js';
import { resolveMetadata } from './wearableMetadata.js';
import { springBonesOf } from './springBonesLoaderExtension.js';
import { readWearableSkeleton } from './wearableSkeleton.js';
import { boneNotMatched, consoleReporter, diagnostic, failureDiagnostic, rigDiagnostics } from '../wearable/diagnostics.js';
import { modelsEntry } from '../wearable/wearable_entry.js';
import { carryMotion, liveEdit, loadWearableRig } from '../wearable/rig_life.js';
import { FrameCopyLists } from '../wearable/frame_copies.js';

/**
 * The one place that carries an instance across a discontinuity of its drivers (an animation
 * group starting, an avatar teleporting): the core's instance.jump() keeps the chains' shape and
 * adds no velocity, where Decentraland's preview re-seeds them at rest.
 */
export function carryAcrossJump(instance) {
  instance.jump();
}

const isObject = (value) => value !== null && typeof value === 'object' && !Array.isArray(value);

/** springBones with every entry's gravityDir read in a left-handed scene's space (x mirrored). */
function mirroredGravity(springBones) {
  if (!isObject(springBones) || !isObject(springBones.models)) return springBones;
  const models = {};
  for (const [key, model] of Object.entries(springBones.models)) {
    if (!isObject(model)) {
      models[key] = model;
      continue;
    }
    models[key] = Object.fromEntries(Object.entries(model).map(([name, entry]) => {
      const g = entry?.gravityDir;
      const mirror = isObject(entry) && Array.isArray(g) && g.length === 3 && typeof g[0] === 'number';
      return [name, mirror ? { ...entry, gravityDir: [-g[0], g[1], g[2]] } : entry];
    }));
  }
  return { ...springBones, models };
}

/** One registered wearable: its container's nodes, its rig and instance once the module is there. */
class RegisteredWearable {
  constructor(simulation, scene, container, itemId, skeleton, metadata) {
    this.simulation = simulation;
    this.scene = scene;
    this.container = container;
    this.itemId = itemId;
    this.nodes = skeleton.nodes;
    this.gltf = skeleton.gltf;  // the nodes as a glTF document, handed to loadRig as it is
    this.metadata = metadata;  // { springBones, options, key, problem? } (wearableMetadata.js)
    this.rig = null;
    this.instance = null;
    this.jointNodes = [];
    this.driverNodes = [];
    this.restRotations = new Map();  // joint node -> [x, y, z, w] as registered
    this.error = null;
    this.problems = new Map();  // code -> warning: what leaves this wearable's hair still, now
    this._console = consoleReporter(() => `wearable ${itemId}`);  // once per code per registration
  }

  /** Records a diagnostic (web/wearable/diagnostics.js): in `warnings`, and once on the console. */
  report(found) {
    this.problems.set(found.code, Object.freeze({ ...found, itemId: this.itemId }));
    this._console(found);
  }

  /** The Babylon node of each rig driver: by glTF index, or by name for a node outside the GLB. */
  findDriver(driver) {
    if (driver.node >= 0) return this.nodes[driver.node] ?? null;
    const own = this.nodes.find((n) => n?.name === driver.name);
    return own ?? this.scene.getTransformNodeByName?.(driver.name) ?? null;
  }

  /** The springBones as the core is to read it (gravityDir in the scene's space when asked). */
  springBonesForCore() {
    const { springBones } = this.metadata;
    return this.simulation._gravityInScene && isMirroredScene(this.scene) ? mirroredGravity(springBones) : springBones;
  }

  /** The models entry the rig read (node name -> parameters), or null. */
  entry() {
    return modelsEntry(this.metadata.springBones, this.rig?.contentHash ?? this.metadata.key);
  }

  /**
   * Builds a rig from the rest skeleton and the current metadata, and a new instance of it. With
   * `carry`, the new instance takes the previous one's motion over (instance.carryFrom: the
   * joints both rigs have keep moving, new ones start from where they are drawn) instead of
   * starting at rest. Joints the previous rig moved and this one does not go back to their rest
   * rotation. Throws what loadRig throws, before changing anything.
   */
  build(sb, { carry = false } = {}) {
    const rig = loadWearableRig(sb, this.gltf, this.springBonesForCore(), this.metadata.options);
    let instance;
    try {
      instance = rig.createInstance(this.metadata.instance);
    } catch (error) {
      rig.dispose();
      throw error;
    }
    const previous = this.jointNodes;
    const previousInstance = this.instance;
    const previousRig = this.rig;
    this.rig = rig;
    this.instance = instance;
    this.error = null;
    if (rig.contentHash) this.metadata.key = rig.contentHash;
    this.jointNodes = rig.joints.map((j) => this.nodes[j.node] ?? null);
    this.driverNodes = rig.drivers.map((d) => this.findDriver(d));
    for (const node of this.jointNodes) {
      if (!node || this.restRotations.has(node)) continue;
      if (!node.rotationQuaternion) node.rotationQuaternion = node.rotation.toQuaternion();
      const q = node.rotationQuaternion;
      this.restRotations.set(node, [q.x, q.y, q.z, q.w]);
    }
    if (carry) carryMotion(instance, previousInstance, () => this.writeDrivers());
    previousInstance?.dispose();
    previousRig?.dispose();
    const current = new Set(this.jointNodes);
    for (const node of previous) {
      if (node && !current.has(node)) this.restoreRest(node);
    }
    this.diagnose();
  }

  /** The drivers' current world matrices into the instance (what the last frame stepped under). */
  writeDrivers() {
    const { nodes, force } = nodesToRecompute(this.driverNodes);
    for (const node of nodes) node.computeWorldMatrix(force);
    const view = this.instance.driverMatrices;
    const mirrored = isMirroredScene(this.scene);
    this.driverNodes.forEach((node, d) => {
      if (node !== null) copyWorldMatrix(node.getWorldMatrix().m, view, 16 * d, mirrored);
    });
  }

  /**
   * Finds what leaves hair still although the page meant it to move, after a build: the shared
   * diagnostics over the rig and the wearable's nodes, and the drivers no node of the scene is.
   */
  diagnose() {
    for (const code of kRigCodes) this.problems.delete(code);
    const rig = this.rig;
    if (this.problems.has('springbones-ambiguous')) return;  // said already, with its own fix
    const springBones = this.metadata.springBones;
    const found = rigDiagnostics({ rig, springBones, entry: springBones ? this.entry() : null, nodes: this.gltf.nodes });
    const missing = new Set();
    rig.drivers.forEach((d, i) => {
      if (this.driverNodes[i] === null) missing.add(i);
    });
    const unmatched = boneNotMatched(rig, missing, [...missing].map((i) => rig.drivers[i].name));
    if (unmatched) found.push(unmatched);
    for (const warning of found) this.report(warning);
  }

  restoreRest(node) {
    const rest = this.restRotations.get(node);
    if (rest && node.rotationQuaternion) node.rotationQuaternion.set(rest[0], rest[1], rest[2], rest[3]);
  }

  /** Disposes of the rig and instance (the joints keep their pose). */
  release() {
    this.instance?.dispose();
    this.rig?.dispose();
    this.instance = null;
    this.rig = null;
  }

  /** Releases everything and puts every joint back in its rest rotation. */
  dispose() {
    this.release();
    for (const node of this.restRotations.keys()) this.restoreRest(node);
    this.jointNodes = [];
    this.driverNodes = [];
  }
}

/**
 * The per-frame copies for every wearable with an instance, in flat arrays rebuilt when the
 * members change (so a frame walks arrays and allocates nothing).
 */
class FrameCopies extends FrameCopyLists {
  set(wearables) {
    this.setCounts(wearables.map((w) => w.instance), wearables.map((w) => w.driverNodes.length), wearables.map((w) => w.jointNodes.length));
    this.driverNodes = wearables.flatMap((w) => w.driverNodes);
    ({ nodes: this.recompute, force: this.forceRecompute } = nodesToRecompute(this.driverNodes));
    this.jointNodes = wearables.flatMap((w) => w.jointNodes);
  }

  /** Each driver's current world matrix into its instance, in the glTF's space. */
  readDrivers(mirrored) {
    const { instances, driverCounts, driverNodes, recompute, forceRecompute } = this;
    for (let i = 0; i < recompute.length; i++) recompute[i].computeWorldMatrix(forceRecompute);
    for (let i = 0, d = 0; i < instances.length; i++) {
      const view = this.driverView(i);
      for (let o = 0, end = d + driverCounts[i]; d < end; d++, o += 16) {
        const node = driverNodes[d];
        if (node !== null) copyWorldMatrix(node.getWorldMatrix().m, view, o, mirrored);
      }
    }
  }

  /** Each instance's rotations into its joints' rotationQuaternion (set() marks them dirty). */
  writeRotations() {
    const { instances, jointCounts, jointNodes } = this;
    for (let i = 0, j = 0; i < instances.length; i++) {
      const r = this.rotationView(i);
      for (let k = 0, end = j + jointCounts[i]; j < end; j++, k += 4) {
        const q = jointNodes[j]?.rotationQuaternion;
        if (q) q.set(r[k], r[k + 1], r[k + 2], r[k + 3]);
      }
    }
  }

  jumpAll() {
    for (const instance of this.instances) carryAcrossJump(instance);
  }
}

/** The codes a build finds again (diagnose), cleared before each build. */
const kRigCodes = ['rig-failed', 'springbones-missing', 'models-missing', 'model-not-found', 'entry-not-matched', 'no-chain-root',
  'unrooted-bones', 'no-chains', 'bone-not-matched'];

/** A value as an error message shows it: short, and never the engine's own object dump. */
const describeValue = (value) => {
  if (Array.isArray(value)) return `an array of ${value.length}`;
  if (value === null || typeof value !== 'object') return typeof value === 'string' ? JSON.stringify(value.slice(0, 40)) : String(value);
  return 'an object of another kind';
};

const isThenable = (value) => value !== null && (typeof value === 'object' || typeof value === 'function') && typeof value.then === 'function';

const kGravitySpaces = ['gltf', 'scene'];
const kNotAModule = 'SpringBoneSimulation: expected the springbones module (createSpringBones()) or a promise of it';
const isModule = (sb) => typeof sb?.loadRig === 'function' && typeof sb?.createScene === 'function';

export class SpringBoneSimulation {
  /**
   * @param sb the springbones module (createSpringBones()), a promise of it, or nothing: the
   *   simulation then starts the module itself when the first wearable is registered, once per
   *   page, shared by every simulation constructed without one. Wearables stay at rest until it
   *   is there.
   * @param options { gravityDirSpace: 'gltf' (default, the standard's reading, as three.js and
   *   every other runtime of springbones) | 'scene' (Decentraland's preview's: gravityDir in the
   *   Babylon scene's own axes) }
   */
  constructor(sb, options = {}) {
    if (options === null || typeof options !== 'object') throw new TypeError('SpringBoneSimulation: options must be an object');
    const space = options.gravityDirSpace ?? 'gltf';
    if (!kGravitySpaces.includes(space)) {
      throw new RangeError(`SpringBoneSimulation: gravityDirSpace must be one of ${kGravitySpaces.join(', ')}, got ${JSON.stringify(space)}`);
    }
    this._gravityInScene = space === 'scene';
    this._wearables = new Map();  // itemId -> RegisteredWearable
    this._stray = new Map();  // code + itemId -> warning, for calls naming no registered wearable
    this._copies = new FrameCopies();
    this._sb = null;
    this._moduleError = null;
    this._sbScene = null;
    this._scene = null;  // the Babylon scene start() hooked
    this._observer = null;
    this._mirrored = true;
    this._jumpPending = false;
    this._frameMs = null;  // the engine's last frame time and its seconds (see _step)
    this._frameSeconds = null;
    this._watchedGroups = new Set();
    this._watchedGroupCount = -1;
    this._onGroupPlay = () => {
      this._jumpPending = true;
    };
    this._frame = () => this._step();
    // Without a module, the page's: requested when the first wearable is registered (its GLB is
    // in by then, so the module's bytes never share the link with it; page_module.js).
    this._pageModule = sb === undefined || sb === null ? pageModule() : null;
    const module = sb ?? this._pageModule.promise;
    if (isThenable(module)) {
      /**
       * Resolves once the module is there and every wearable registered so far has its rig;
       * rejects when the module fails to load (each wearable also warns, see `warnings`).
       */
      this.ready = Promise.resolve(module).then(
        (m) => (isModule(m) ? this._useModule(m) : this._moduleFailed(new TypeError(kNotAModule))),
        (error) => this._moduleFailed(error));
      this.ready.catch(() => {});  // a page that never awaits it gets no unhandled rejection
    } else {
      this._useModule(module);
      this.ready = Promise.resolve();
    }
  }

  /** The springbones module once it is there, else null. */
  get springBones() {
    return this._sb;
  }

  /**
   * Every problem that leaves a registered wearable's hair still (or part of it), and every call
   * that named no registered wearable: { code, itemId, message } with the fix in the message.
   * Each is also one console warning per wearable. Rebuilt on each read.
   */
  get warnings() {
    const out = [];
    for (const wearable of this._wearables.values()) out.push(...wearable.problems.values());
    out.push(...this._stray.values());
    return out;
  }

  _useModule(sb) {
    if (!isModule(sb)) throw new TypeError(kNotAModule);
    this._sb = sb;
    for (const wearable of this._wearables.values()) this._build(wearable);
    this._membersChanged();
  }

  _moduleFailed(error) {
    this._moduleError = error;
    for (const wearable of this._wearables.values()) this._reportModuleError(wearable);
    throw error;
  }

  _reportModuleError(wearable) {
    wearable.report(failureDiagnostic(this._moduleError, true));
  }

  /** Builds a wearable's rig; what the core rejects becomes a warning, the wearable stays at rest. */
  _build(wearable, options) {
    try {
      wearable.build(this._sb, options);
      if (this._inertia !== undefined) wearable.instance?.setInertia(this._inertia);
      return true;
    } catch (error) {
      wearable.error = error;
      for (const code of kRigCodes) wearable.problems.delete(code);
      wearable.report(failureDiagnostic(error, false));
      return false;
    }
  }

  /**
   * Registers a wearable's container (after container.addAllToScene(), before its animation
   * starts: its current pose is taken as the rest pose). `itemId` is any string (the preview
   * passes the wearable's URN). `springBonesParams`: the models entry (node name -> parameters),
   * as the preview passes it; the whole springBones (the entry under itemId, else its only
   * entry, else a `springbones-ambiguous` warning); or { springBones, entity, bodyShape } /
   * { springBones, contentHash } / { springBones, glb }; left out, the springBones the loader
   * extension was given for this file, else no chains until updateParams gives it some. A
   * container loaded with the extension is read by the file's own node list rather than from its
   * Babylon nodes. Registering an itemId again replaces the earlier registration. Metadata the
   * core rejects is a warning (see `warnings`), never a throw.
   * @throws TypeError for arguments of the wrong kind
   */
  registerWearable(scene, container, itemId, springBonesParams) {
    if (scene === null || typeof scene !== 'object' || typeof scene.getEngine !== 'function') {
      throw new TypeError('registerWearable: scene must be a Babylon Scene');
    }
    if (typeof itemId !== 'string' || itemId === '') throw new TypeError('registerWearable: itemId must be a non-empty string');
    this._pageModule?.start();
    const loaded = springBonesOf(container);  // the loader extension's node list, when it ran
    const metadata = springBonesParams === undefined && loaded?.metadata
      ? { springBones: loaded.metadata.springBones, options: { ...loaded.metadata.options }, key: loaded.metadata.options.contentHash ?? null }
      : resolveMetadata(itemId, springBonesParams);
    const earlier = this._wearables.get(itemId);
    if (earlier) {
      earlier.dispose();  // first, so its joints are back at rest when the container is read
      this._wearables.delete(itemId);
      this._membersChanged();
    }
    const skeleton = loaded ? { nodes: loaded.nodes, gltf: loaded.gltf } : readWearableSkeleton(container);
    this._stray.delete(itemId);
    const wearable = new RegisteredWearable(this, scene, container, itemId, skeleton, metadata);
    if (metadata.problem) wearable.report(diagnostic(metadata.problem.code, metadata.problem.facts));
    if (this._sb) {
      this._build(wearable);
    } else if (this._moduleError) {
      this._reportModuleError(wearable);
    }
    this._wearables.set(itemId, wearable);
    this._membersChanged();
  }

  /**
   * The Builder's live tuning: `params` (node name -> parameters, the whole entry) becomes the
   * wearable's models entry, each name's fields merged over its previous ones. The chains keep
   * their motion through it: joints that stay simulated carry their state over
   * (instance.carryFrom), an added chain starts from the pose it is drawn in, a removed chain
   * goes back to its rest rotation before the next frame. By the standard's rules an entry starts
   * a chain only with isRoot: true. An itemId that is not registered (never, or no longer after
   * dispose) does nothing and warns once (`unknown-item`).
   * @throws TypeError for params that are not an object
   */
  updateParams(itemId, params) {
    if (params === null || typeof params !== 'object' || Array.isArray(params)) {
      throw new TypeError('updateParams: params must be an object of node name -> parameters');
    }
    const wearable = this._wearables.get(itemId);
    if (!wearable) {
      this._reportStray(itemId, 'updateParams');
      return;
    }
    const key = wearable.metadata.key ?? String(itemId);
    const { springBones, options } = liveEdit(wearable.metadata.springBones, key, wearable.metadata.options, params);
    const before = wearable.metadata;
    wearable.metadata = { ...before, springBones, options, key };
    wearable.problems.delete('springbones-ambiguous');  // the entry is named now
    if (this._sb && !this._build(wearable, { carry: true })) {
      wearable.metadata = before;  // the previous rig keeps running
      return;
    }
    this._membersChanged();
  }

  /** unknown-item for a call that named no registered wearable: once per id. */
  _reportStray(itemId, call) {
    const key = String(itemId);
    if (this._stray.has(key)) return;
    const found = diagnostic('unknown-item', { call, itemId: key });
    this._stray.set(key, Object.freeze({ ...found, itemId: key }));
    consoleReporter(() => `wearable ${key}`)(found);
  }

  /** Steps every registered wearable once per frame, before each render of `scene`. Idempotent. */
  start(scene) {
    if (this._observer) return;
    if (scene === null || typeof scene !== 'object' || !scene.onBeforeRenderObservable) {
      throw new TypeError('start: scene must be a Babylon Scene');
    }
    this._scene = scene;
    this._mirrored = isMirroredScene(scene);
    this._observer = scene.onBeforeRenderObservable.add(this._frame);
  }

  /**
   * Forgets every wearable's motion (or only itemId's): the next frame starts at rest under the
   * current drivers. For an avatar swap.
   */
  reset(itemId) {
    for (const wearable of this._selected(itemId, 'reset')) wearable.instance?.reset();
  }

  /**
   * Brings every wearable's springs (or only itemId's) to rest in the avatar's current pose
   * without rendering (instance.settle): for thumbnails, turntables and emote starts. Returns the
   * most steps one of them ran (0 before the module is there).
   * @param seconds at most this long (default 2, in [0, 60])
   * @throws RangeError for seconds out of range
   */
  settle(itemId, seconds) {
    const settling = this._selected(itemId, 'settle').filter((wearable) => wearable.instance);
    if (settling.length === 0) return 0;
    this._copies.readDrivers(this._mirrored);
    let most = 0;
    for (const wearable of settling) most = Math.max(most, wearable.instance.settle(seconds));
    this._copies.writeRotations();
    return most;
  }

  /**
   * Holds joint `joint` (an index into rigOf(itemId).joints) of a wearable toward `point`, a point
   * of Babylon's world ({x, y, z} or [x, y, z]), as far as its chain reaches (instance.grab): call
   * it every frame of a drag, then release(itemId). Nothing before the module is there.
   * An itemId not registered does nothing and warns once (`unknown-item`).
   * @throws TypeError for a point that is not three numbers (checked before it is mirrored into
   *   the glTF's space); RangeError for a joint out of range or a non-finite point
   */
  grab(itemId, joint, point) {
    if (typeof itemId !== 'string') throw new TypeError('grab: itemId must be a string');
    const p = Array.isArray(point) ? point : [point?.x, point?.y, point?.z];
    if (p.length !== 3 || !p.every((v) => typeof v === 'number')) {
      throw new TypeError(`grab: point must be [x, y, z] or {x, y, z}, three numbers in Babylon's world, got ${describeValue(point)}`);
    }
    const [wearable] = this._selected(itemId, 'grab');
    if (!wearable?.instance) return;
    wearable.instance.grab(joint, [this._mirrored ? -p[0] : p[0], p[1], p[2]]);
  }

  /** Lets go of what grab() holds, on every wearable (or itemId's): the hair swings back. */
  release(itemId) {
    for (const wearable of this._selected(itemId, 'release')) wearable.instance?.release();
  }

  /**
   * Tells the simulation that the avatar (every wearable, or only itemId's) moves discontinuously
   * before the next frame: a teleport, a jump cut. The hair is carried across it instead of
   * whipping after it. An animation group starting to play does this by itself.
   */
  jump(itemId) {
    for (const wearable of this._selected(itemId, 'jump')) if (wearable.instance) carryAcrossJump(wearable.instance);
  }

  /**
   * Wind on every wearable, those registered later too (scene.setWind's argument: {direction,
   * strength, gustFrequency?, seed?}, the direction in the glTF's space as gravityDir is; null for
   * none). Before the module is there it is kept and checked when the module comes.
   * @throws TypeError / RangeError for a bad wind once the module is there
   */
  setWind(wind) {
    if (this._sb) this._sceneFor().setWind(wind);
    this._wind = wind;
  }

  /**
   * How much of the avatar's own motion the hair feels (instance.setInertia): 1, the default, all
   * of it; 0 none (as in a vehicle or on a moving platform). On every wearable now and later.
   * @throws RangeError for a value outside [0, 1]
   */
  setInertia(value) {
    if (!(typeof value === 'number' && value >= 0 && value <= 1)) {
      throw new RangeError(`setInertia: value must be a number in [0, 1], got ${value}`);
    }
    for (const wearable of this._wearables.values()) wearable.instance?.setInertia(value);
    this._inertia = value;
  }

  /** The rig of a registered wearable (null before the module is there or on a load error). */
  rigOf(itemId) {
    return this._wearables.get(itemId)?.rig ?? null;
  }

  /**
   * Stops stepping, puts the joints back at rest and frees every rig and instance. The simulation
   * can be registered and started again afterwards (the preview disposes on every wearable swap).
   * `scene`, as the preview passes it, is optional: the frame hook comes off the scene start() was
   * given, whichever Babylon scene is named.
   * @throws TypeError for a scene argument that is not a Babylon Scene (before anything changes)
   */
  dispose(scene) {
    if (scene !== undefined && scene !== null && typeof scene?.onBeforeRenderObservable?.remove !== 'function') {
      throw new TypeError(`dispose: scene must be a Babylon Scene or left out, got ${describeValue(scene)}`);
    }
    // The hook is on the scene start() was given, whichever scene the page names here.
    if (this._observer) this._scene.onBeforeRenderObservable.remove(this._observer);
    this._observer = null;
    this._scene = null;
    for (const group of this._watchedGroups) group.onAnimationGroupPlayObservable.removeCallback(this._onGroupPlay);
    this._watchedGroups.clear();
    this._watchedGroupCount = -1;
    this._jumpPending = false;
    for (const wearable of this._wearables.values()) wearable.dispose();
    this._wearables.clear();
    this._stray.clear();
    this._copies.set([]);
    this._sbScene?.dispose();
    this._sbScene = null;  // made again by the next registration
  }

  /** Every wearable, or itemId's; an id not registered warns once (`unknown-item`) and selects none. */
  _selected(itemId, where) {
    if (itemId === undefined) return [...this._wearables.values()];
    const wearable = this._wearables.get(itemId);
    if (wearable) return [wearable];
    this._reportStray(itemId, where);
    return [];
  }

  /** Rebuilds the springbones scene's members and the flat per-frame arrays. */
  _membersChanged() {
    if (!this._sb) return;
    const scene = this._sceneFor();
    const members = [...this._wearables.values()].filter((w) => w.instance);
    for (const w of members) scene.add(w.instance);  // disposed instances left by themselves
    this._copies.set(members);
  }

  /** The springbones scene, made when first needed (and again after dispose), with the wind set. */
  _sceneFor() {
    if (this._sbScene === null) {
      this._sbScene = this._sb.createScene();
      if (this._wind !== undefined) this._sbScene.setWind(this._wind);
    }
    return this._sbScene;
  }

  /**
   * Subscribes to every animation group of the scene, once; runs only when their number changes.
   * A group starting to play snaps the avatar to its first pose: the next frame carries the
   * chains across (carryAcrossJump), as the preview re-seeds its chains there.
   */
  _watchAnimationGroups(scene) {
    const groups = scene.animationGroups;
    if (groups.length === this._watchedGroupCount) return;
    this._watchedGroupCount = groups.length;
    for (const group of groups) {
      if (this._watchedGroups.has(group)) continue;
      this._watchedGroups.add(group);
      group.onAnimationGroupPlayObservable.add(this._onGroupPlay);
      // A group made and started since the last frame started before anyone listened.
      if (group.isPlaying) this._jumpPending = true;
    }
  }

  _step() {
    const scene = this._scene;
    this._watchAnimationGroups(scene);
    if (!this._sbScene || this._copies.instances.length === 0) {
      this._jumpPending = false;
      return;
    }
    const ms = scene.getEngine().getDeltaTime();
    if (ms !== this._frameMs) {
      // Kept for the next frame: a frame time that does not change is not divided (and boxed) again.
      this._frameMs = ms;
      this._frameSeconds = Number.isFinite(ms) ? ms / 1000 : 0;
    }
    this._copies.readDrivers(this._mirrored);
    if (this._jumpPending) {
      this._jumpPending = false;
      this._copies.jumpAll();
    }
    this._sbScene.step(this._frameSeconds);
    this._copies.writeRotations();
  }
}
