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
// With loadRig's 'dcl-body' colliders, the body's shapes are measured on the avatar in the scene
// (avatarSkeleton.js: the skeleton with the whole armature, the body shape's in the preview) and
// ride on its bones; a wearable registered before the avatar is in the scene is measured again
// when a later registration or start() finds it.
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
import { avatarNode, avatarRestBones, findAvatarSkeleton } from './avatarSkeleton.js';
import { measuresOnAvatar, withAvatarBones } from '../wearable/avatar_bones.js';
import { boneNotMatched, consoleReporter, diagnostic, failureDiagnostic, rigDiagnostics } from '../wearable/diagnostics.js';
import { modelsEntry } from '../wearable/wearable_entry.js';
import { carryMotion, liveEdit, loadWearableRig } from '../wearable/rig_life.js';
import { FrameCopyLists } from '../wearable/frame_copies.js';
import { colliderDiagnostics, collidersWithFrames, frameFollowers, withMeasuredBones } from '../wearable/collider_followers.js';

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
  #console;

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
    this.frameNodes = [];  // the node each frame of the instance's setColliders colliders follows (or null)
    this.colliders = null;  // the last setColliders call ({ colliders, options }), kept for a new rig
    this.avatar = null;  // the avatar's skeleton the rig's body shapes were measured on, if any
    this.restRotations = new Map();  // joint node -> [x, y, z, w] as registered
    this.error = null;
    this.problems = new Map();  // code -> warning: what leaves this wearable's hair still, now
    this.#console = consoleReporter(() => `wearable ${itemId}`);  // once per code per registration
  }

  /** Records a diagnostic (web/wearable/diagnostics.js): in `warnings`, and once on the console. */
  report(found) {
    this.problems.set(found.code, Object.freeze({ ...found, itemId: this.itemId }));
    this.#console(found);
  }

  /** The Babylon node of each rig driver: by glTF index, or by name for a node outside the GLB. */
  findDriver(driver) {
    if (driver.node >= 0) return this.nodes[driver.node] ?? null;
    const own = this.nodes.find((n) => n?.name === driver.name);
    const avatar = this.avatar === null ? null : avatarNode(this.avatar, driver.name);
    return own ?? avatar ?? this.scene.getTransformNodeByName?.(driver.name) ?? null;
  }

  /** Whether the rig wants the avatar's bones ('dcl-body') and was built before one was in the scene. */
  waitsForAvatar() {
    return this.rig !== null && this.avatar === null && measuresOnAvatar(this.metadata.options) &&
      findAvatarSkeleton(this.scene, this.container) !== null;
  }

  /** The springBones as the core is to read it (gravityDir in the scene's space when asked). */
  springBonesForCore() {
    const { springBones } = this.metadata;
    return gravityInScene(this.simulation) && isMirroredScene(this.scene) ? mirroredGravity(springBones) : springBones;
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
    const avatar = measuresOnAvatar(this.metadata.options) ? findAvatarSkeleton(this.scene, this.container) : null;
    const options = withAvatarBones(this.metadata.options, avatar === null ? null : avatarRestBones(avatar));
    const rig = loadWearableRig(sb, this.gltf, this.springBonesForCore(), options);
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
    this.avatar = avatar;
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
    this.frameNodes = [];
    if (this.colliders !== null) this.applyColliders();  // the page's colliders outlive a rebuild
  }

  /** The kept setColliders call as the instance takes it, and the nodes its frames follow. */
  collidersForInstance() {
    const { colliders, options } = this.colliders;
    const engine = {
      // A Bone has both methods too, but its world matrix is the skeleton's space: pass its linked node.
      isObject: (value) => typeof value?.getWorldMatrix === 'function' && typeof value?.computeWorldMatrix === 'function' &&
        value.getClassName?.() !== 'Bone',
      nameOf: (node) => node.name,
      driverNames: this.rig?.drivers.map((d) => d.name) ?? [],
    };
    const prepared = collidersWithFrames('setColliders', colliders, engine);
    const avatar = colliders === 'dcl-body' ? this.avatar ?? findAvatarSkeleton(this.scene, this.container) : null;
    return { ...prepared, options: withMeasuredBones(colliders, options, avatar === null ? null : avatarRestBones(avatar)) };
  }

  /** Applies the kept setColliders call to the instance; returns its warnings, reported. */
  applyColliders() {
    const { colliders, options, followed } = this.collidersForInstance();
    const warnings = this.instance.setColliders(colliders, options);
    const avatar = this.avatar ?? findAvatarSkeleton(this.scene, this.container);
    const byName = (name) => this.nodes.find((n) => n?.name === name) ?? (avatar === null ? null : avatarNode(avatar, name)) ??
      this.scene.getTransformNodeByName?.(name) ?? null;
    const { objects, missing } = frameFollowers(this.instance.frameNames, followed, byName);
    this.frameNodes = objects;
    for (const code of kColliderCodes) this.problems.delete(code);
    for (const found of colliderDiagnostics(warnings, missing)) this.report(found);
    return warnings;
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
    this.frameNodes = [];
  }
}

/**
 * The per-frame copies for every wearable with an instance, in flat arrays rebuilt when the
 * members change (so a frame walks arrays and allocates nothing).
 */
class FrameCopies extends FrameCopyLists {
  set(wearables) {
    this.setCounts(wearables.map((w) => w.instance), wearables.map((w) => w.driverNodes.length), wearables.map((w) => w.jointNodes.length),
      wearables.map((w) => w.frameNodes.length));
    this.driverNodes = wearables.flatMap((w) => w.driverNodes);
    this.frameNodes = wearables.flatMap((w) => w.frameNodes);
    ({ nodes: this.recompute, force: this.forceRecompute } = nodesToRecompute([...this.driverNodes, ...this.frameNodes]));
    this.jointNodes = wearables.flatMap((w) => w.jointNodes);
  }

  /** Each driver's current world matrix into its instance, in the glTF's space. */
  readDrivers(mirrored) {
    const { instances, driverCounts, driverNodes, frameCounts, frameNodes, recompute, forceRecompute } = this;
    for (let i = 0; i < recompute.length; i++) recompute[i].computeWorldMatrix(forceRecompute);
    for (let i = 0, d = 0; i < instances.length; i++) {
      const view = this.driverView(i);
      for (let o = 0, end = d + driverCounts[i]; d < end; d++, o += 16) {
        const node = driverNodes[d];
        if (node !== null) copyWorldMatrix(node.getWorldMatrix().m, view, o, mirrored);
      }
    }
    // The frames of colliders setColliders put on nodes (a hat, another wearable's node), as drivers.
    for (let i = 0, f = 0; i < instances.length; i++) {
      if (frameCounts[i] === 0) continue;
      const view = this.frameView(i);
      for (let o = 0, end = f + frameCounts[i]; f < end; f++, o += 16) {
        const node = frameNodes[f];
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

/** The codes of setColliders' warnings, replaced by each call (web/wearable/diagnostics.js). */
const kColliderCodes = ['collider-invalid', 'collider-on-spring-bone', 'body-collider-skipped', 'collider-not-followed'];

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

// Whether a simulation reads gravityDir in the scene's axes: RegisteredWearable's reach into
// SpringBoneSimulation's privates, set by its static block.
let gravityInScene;

export class SpringBoneSimulation {
  #gravityInScene; #wearables; #stray; #copies; #sb; #moduleError;
  #sbScene; #scene; #observer; #mirrored; #jumpPending; #frameMs;
  #frameSeconds; #watchedGroups; #watchedGroupCount; #onGroupPlay; #frame; #pageModule;
  #inertia; #wind;

  static {
    gravityInScene = (simulation) => simulation.#gravityInScene;
  }

  /**
   * For the adapter's tests only, not API (not in the .d.ts): a registered wearable's internals by
   * item id (its springbones instance), and the springbones scene, which a test may replace with a
   * wrapper (tests/adapters/babylon_frame_heap.mjs).
   */
  get internalsForTests() {
    const simulation = this;
    return {
      wearable: (itemId) => simulation.#wearables.get(itemId),
      get sbScene() { return simulation.#sbScene; },
      set sbScene(scene) { simulation.#sbScene = scene; },
    };
  }

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
    this.#gravityInScene = space === 'scene';
    this.#wearables = new Map();  // itemId -> RegisteredWearable
    this.#stray = new Map();  // code + itemId -> warning, for calls naming no registered wearable
    this.#copies = new FrameCopies();
    this.#sb = null;
    this.#moduleError = null;
    this.#sbScene = null;
    this.#scene = null;  // the Babylon scene start() hooked
    this.#observer = null;
    this.#mirrored = true;
    this.#jumpPending = false;
    this.#frameMs = null;  // the engine's last frame time and its seconds (see #step)
    this.#frameSeconds = null;
    this.#watchedGroups = new Set();
    this.#watchedGroupCount = -1;
    this.#onGroupPlay = () => {
      this.#jumpPending = true;
    };
    this.#frame = () => this.#step();
    // Without a module, the page's: requested when the first wearable is registered (its GLB is
    // in by then, so the module's bytes never share the link with it; page_module.js).
    this.#pageModule = sb === undefined || sb === null ? pageModule() : null;
    const module = sb ?? this.#pageModule.promise;
    if (isThenable(module)) {
      /**
       * Resolves once the module is there and every wearable registered so far has its rig;
       * rejects when the module fails to load (each wearable also warns, see `warnings`).
       */
      this.ready = Promise.resolve(module).then(
        (m) => (isModule(m) ? this.#useModule(m) : this.#moduleFailed(new TypeError(kNotAModule))),
        (error) => this.#moduleFailed(error));
      this.ready.catch(() => {});  // a page that never awaits it gets no unhandled rejection
    } else {
      this.#useModule(module);
      this.ready = Promise.resolve();
    }
  }

  /** The springbones module once it is there, else null. */
  get springBones() {
    return this.#sb;
  }

  /**
   * Every problem that leaves a registered wearable's hair still (or part of it), and every call
   * that named no registered wearable: { code, itemId, message } with the fix in the message.
   * Each is also one console warning per wearable. Rebuilt on each read.
   */
  get warnings() {
    const out = [];
    for (const wearable of this.#wearables.values()) out.push(...wearable.problems.values());
    out.push(...this.#stray.values());
    return out;
  }

  #useModule(sb) {
    if (!isModule(sb)) throw new TypeError(kNotAModule);
    this.#sb = sb;
    for (const wearable of this.#wearables.values()) this.#build(wearable);
    this.#membersChanged();
  }

  #moduleFailed(error) {
    this.#moduleError = error;
    for (const wearable of this.#wearables.values()) this.#reportModuleError(wearable);
    throw error;
  }

  #reportModuleError(wearable) {
    wearable.report(failureDiagnostic(this.#moduleError, true));
  }

  /** Builds a wearable's rig; what the core rejects becomes a warning, the wearable stays at rest. */
  #build(wearable, options) {
    try {
      wearable.build(this.#sb, options);
      if (this.#inertia !== undefined) wearable.instance?.setInertia(this.#inertia);
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
    this.#pageModule?.start();
    const loaded = springBonesOf(container);  // the loader extension's node list, when it ran
    const metadata = springBonesParams === undefined && loaded?.metadata
      ? { springBones: loaded.metadata.springBones, options: { ...loaded.metadata.options }, key: loaded.metadata.options.contentHash ?? null }
      : resolveMetadata(itemId, springBonesParams);
    const earlier = this.#wearables.get(itemId);
    if (earlier) {
      earlier.dispose();  // first, so its joints are back at rest when the container is read
      this.#wearables.delete(itemId);
      this.#membersChanged();
    }
    const skeleton = loaded ? { nodes: loaded.nodes, gltf: loaded.gltf } : readWearableSkeleton(container);
    this.#stray.delete(itemId);
    const wearable = new RegisteredWearable(this, scene, container, itemId, skeleton, metadata);
    if (metadata.problem) wearable.report(diagnostic(metadata.problem.code, metadata.problem.facts));
    if (this.#sb) {
      this.#build(wearable);
    } else if (this.#moduleError) {
      this.#reportModuleError(wearable);
    }
    this.#wearables.set(itemId, wearable);
    this.#measureOnAvatar();
    this.#membersChanged();
  }

  /**
   * Builds again, keeping their motion, the wearables whose body shapes wait for an avatar that is
   * in the scene now (the preview adds each GLB and registers it in turn, the body shape perhaps
   * after the hair). Returns whether one was built again.
   */
  #measureOnAvatar() {
    if (!this.#sb) return false;
    let built = false;
    for (const wearable of this.#wearables.values()) {
      if (wearable.waitsForAvatar()) built = this.#build(wearable, { carry: true }) || built;
    }
    return built;
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
    const wearable = this.#wearables.get(itemId);
    if (!wearable) {
      this.#reportStray(itemId, 'updateParams');
      return;
    }
    const key = wearable.metadata.key ?? String(itemId);
    const { springBones, options } = liveEdit(wearable.metadata.springBones, key, wearable.metadata.options, params);
    const before = wearable.metadata;
    wearable.metadata = { ...before, springBones, options, key };
    wearable.problems.delete('springbones-ambiguous');  // the entry is named now
    if (this.#sb && !this.#build(wearable, { carry: true })) {
      wearable.metadata = before;  // the previous rig keeps running
      return;
    }
    this.#membersChanged();
  }

  /**
   * Replaces a registered wearable's colliders (its rig's included) from the next frame on
   * (instance.setColliders): `colliders` as loadRig's option takes them, an array or 'dcl-body',
   * null or [] for none, where a collider's `node` is a name (a rig driver, a bone of the avatar, a
   * node of the wearable or of the scene) or any TransformNode (a hat, a hand, another wearable's
   * node): each frame then copies that node's world matrix for it, in the glTF's space, after the
   * drivers'. `options` { scale?, omit?, avatarBones? }: for 'dcl-body', every shape's radius
   * times `scale` and the shapes named in `omit` left out, measured on the avatar in the scene
   * unless `avatarBones` is given. Kept across updateParams and rebuilds; before the module is
   * there, applied when it comes. Returns the instance's warnings (each also in `warnings`, with a
   * fix: docs/diagnostics.md); [] before the module is there. An itemId that is not registered
   * does nothing and warns once (`unknown-item`).
   * @throws TypeError / RangeError / SpringBonesError for a bad collider, as instance.setColliders
   *   (messages starting `setColliders:`), before anything changes
   */
  setColliders(itemId, colliders, options) {
    const wearable = this.#wearables.get(itemId);
    if (!wearable) {
      this.#reportStray(itemId, 'setColliders');
      return Object.freeze([]);
    }
    const previous = wearable.colliders;
    wearable.colliders = { colliders, options };
    try {
      if (!wearable.instance) {
        wearable.collidersForInstance();  // the nodes' part is checked now; the rest when the rig comes
        return Object.freeze([]);
      }
      const warnings = wearable.applyColliders();
      this.#membersChanged();
      return warnings;
    } catch (error) {
      wearable.colliders = previous;
      throw error;
    }
  }

  /** unknown-item for a call that named no registered wearable: once per id. */
  #reportStray(itemId, call) {
    const key = String(itemId);
    if (this.#stray.has(key)) return;
    const found = diagnostic('unknown-item', { call, itemId: key });
    this.#stray.set(key, Object.freeze({ ...found, itemId: key }));
    consoleReporter(() => `wearable ${key}`)(found);
  }

  /** Steps every registered wearable once per frame, before each render of `scene`. Idempotent. */
  start(scene) {
    if (this.#observer) return;
    if (scene === null || typeof scene !== 'object' || !scene.onBeforeRenderObservable) {
      throw new TypeError('start: scene must be a Babylon Scene');
    }
    this.#scene = scene;
    this.#mirrored = isMirroredScene(scene);
    this.#observer = scene.onBeforeRenderObservable.add(this.#frame);
    if (this.#measureOnAvatar()) this.#membersChanged();
  }

  /**
   * Forgets every wearable's motion (or only itemId's): the next frame starts at rest under the
   * current drivers. For an avatar swap.
   */
  reset(itemId) {
    for (const wearable of this.#selected(itemId, 'reset')) wearable.instance?.reset();
  }

  /**
   * Brings every wearable's springs (or only itemId's) to rest in the avatar's current pose
   * without rendering (instance.settle): for thumbnails, turntables and emote starts. Returns the
   * most steps one of them ran (0 before the module is there).
   * @param seconds at most this long (default 2, in [0, 60])
   * @throws RangeError for seconds out of range
   */
  settle(itemId, seconds) {
    const settling = this.#selected(itemId, 'settle').filter((wearable) => wearable.instance);
    if (settling.length === 0) return 0;
    this.#copies.readDrivers(this.#mirrored);
    let most = 0;
    for (const wearable of settling) most = Math.max(most, wearable.instance.settle(seconds));
    this.#copies.writeRotations();
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
    const [wearable] = this.#selected(itemId, 'grab');
    if (!wearable?.instance) return;
    wearable.instance.grab(joint, [this.#mirrored ? -p[0] : p[0], p[1], p[2]]);
  }

  /** Lets go of what grab() holds, on every wearable (or itemId's): the hair swings back. */
  release(itemId) {
    for (const wearable of this.#selected(itemId, 'release')) wearable.instance?.release();
  }

  /**
   * Tells the simulation that the avatar (every wearable, or only itemId's) moves discontinuously
   * before the next frame: a teleport, a jump cut. The hair is carried across it instead of
   * whipping after it. An animation group starting to play does this by itself.
   */
  jump(itemId) {
    for (const wearable of this.#selected(itemId, 'jump')) if (wearable.instance) carryAcrossJump(wearable.instance);
  }

  /**
   * Wind on every wearable, those registered later too (scene.setWind's argument: {direction,
   * strength, gustFrequency?, seed?}, the direction in the glTF's space as gravityDir is; null for
   * none). Before the module is there it is kept and checked when the module comes.
   * @throws TypeError / RangeError for a bad wind once the module is there
   */
  setWind(wind) {
    if (this.#sb) this.#sceneFor().setWind(wind);
    this.#wind = wind;
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
    for (const wearable of this.#wearables.values()) wearable.instance?.setInertia(value);
    this.#inertia = value;
  }

  /** The rig of a registered wearable (null before the module is there or on a load error). */
  rigOf(itemId) {
    return this.#wearables.get(itemId)?.rig ?? null;
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
    if (this.#observer) this.#scene.onBeforeRenderObservable.remove(this.#observer);
    this.#observer = null;
    this.#scene = null;
    for (const group of this.#watchedGroups) group.onAnimationGroupPlayObservable.removeCallback(this.#onGroupPlay);
    this.#watchedGroups.clear();
    this.#watchedGroupCount = -1;
    this.#jumpPending = false;
    for (const wearable of this.#wearables.values()) wearable.dispose();
    this.#wearables.clear();
    this.#stray.clear();
    this.#copies.set([]);
    this.#sbScene?.dispose();
    this.#sbScene = null;  // made again by the next registration
  }

  /** Every wearable, or itemId's; an id not registered warns once (`unknown-item`) and selects none. */
  #selected(itemId, where) {
    if (itemId === undefined) return [...this.#wearables.values()];
    const wearable = this.#wearables.get(itemId);
    if (wearable) return [wearable];
    this.#reportStray(itemId, where);
    return [];
  }

  /** Rebuilds the springbones scene's members and the flat per-frame arrays. */
  #membersChanged() {
    if (!this.#sb) return;
    const scene = this.#sceneFor();
    const members = [...this.#wearables.values()].filter((w) => w.instance);
    for (const w of members) scene.add(w.instance);  // disposed instances left by themselves
    this.#copies.set(members);
  }

  /** The springbones scene, made when first needed (and again after dispose), with the wind set. */
  #sceneFor() {
    if (this.#sbScene === null) {
      this.#sbScene = this.#sb.createScene();
      if (this.#wind !== undefined) this.#sbScene.setWind(this.#wind);
    }
    return this.#sbScene;
  }

  /**
   * Subscribes to every animation group of the scene, once; runs only when their number changes.
   * A group starting to play snaps the avatar to its first pose: the next frame carries the
   * chains across (carryAcrossJump), as the preview re-seeds its chains there.
   */
  #watchAnimationGroups(scene) {
    const groups = scene.animationGroups;
    if (groups.length === this.#watchedGroupCount) return;
    this.#watchedGroupCount = groups.length;
    for (const group of groups) {
      if (this.#watchedGroups.has(group)) continue;
      this.#watchedGroups.add(group);
      group.onAnimationGroupPlayObservable.add(this.#onGroupPlay);
      // A group made and started since the last frame started before anyone listened.
      if (group.isPlaying) this.#jumpPending = true;
    }
  }

  #step() {
    const scene = this.#scene;
    this.#watchAnimationGroups(scene);
    if (!this.#sbScene || this.#copies.instances.length === 0) {
      this.#jumpPending = false;
      return;
    }
    const ms = scene.getEngine().getDeltaTime();
    if (ms !== this.#frameMs) {
      // Kept for the next frame: a frame time that does not change is not divided (and boxed) again.
      this.#frameMs = ms;
      this.#frameSeconds = Number.isFinite(ms) ? ms / 1000 : 0;
    }
    this.#copies.readDrivers(this.#mirrored);
    if (this.#jumpPending) {
      this.#jumpPending = false;
      this.#copies.jumpAll();
    }
    this.#sbScene.step(this.#frameSeconds);
    this.#copies.writeRotations();
  }
}
