// springbones for Babylon.js: a drop-in for the `SpringBoneSimulation` class of Decentraland's
// wearable preview (the same four methods with the same arguments), constructed with the
// springbones module (or a promise of it), with the standard's rules from the core: roots by
// isRoot, branches, member overrides, tips, defaults and clamps, centers, colliders, fixed steps.
//
//   const simulation = new SpringBoneSimulation(sb);          // or createSpringBones() unresolved
//   container.addAllToScene();
//   simulation.registerWearable(scene, container, itemHash, springBones.models[itemHash]);
//   simulation.start(scene);                                   // one before-render step per frame
//   simulation.updateParams(itemHash, editedEntry);            // the Builder's live tuning
//   simulation.dispose(scene);
//
// A wearable is read from its container (wearableSkeleton.js): the glTF nodes Babylon's loader
// made, their rest transforms, in the glTF's space (handedness.js). Per frame, in the scene's
// before-render (after the animations moved the nodes): each driver's world matrix, made current
// (currentWorldMatrices.js), goes into its instance's driverMatrices (mirrored into the glTF's
// space), one scene.step(dt) steps every registered wearable, and each joint's rotation goes
// into its rotationQuaternion. No allocation per frame.
//
// Babylon itself is never imported: everything comes from the scene and containers passed in,
// so the same file serves Babylon 4.2 (its UMD build) and the current @babylonjs/core.
import { nodesToRecompute } from './currentWorldMatrices.js';
import { copyWorldMatrix, isMirroredScene } from './handedness.js';
import { entryAsSpringBones, resolveMetadata, rigOptions } from './wearableMetadata.js';
import { springBonesOf } from './springBonesLoaderExtension.js';
import { readWearableSkeleton } from './wearableSkeleton.js';

const kNoView = new Float32Array(0);

/**
 * The one place that carries an instance across a discontinuity of its drivers (an animation
 * group starting, an avatar teleporting): the core's instance.jump() keeps the chains' shape and
 * adds no velocity, where Decentraland's preview re-seeds them at rest.
 */
export function carryAcrossJump(instance) {
  instance.jump();
}

/** One registered wearable: its container's nodes, its rig and instance once the module is there. */
class RegisteredWearable {
  constructor(scene, container, itemId, skeleton, metadata) {
    this.scene = scene;
    this.container = container;
    this.itemId = itemId;
    this.nodes = skeleton.nodes;
    this.gltfBytes = new TextEncoder().encode(skeleton.gltfText);
    this.metadata = metadata;  // { springBones, options, key } (wearableMetadata.js)
    this.rig = null;
    this.instance = null;
    this.jointNodes = [];
    this.driverNodes = [];
    this.restRotations = new Map();  // joint node -> [x, y, z, w] as registered
    this.error = null;
  }

  /** The Babylon node of each rig driver: by glTF index, or by name for a node outside the GLB. */
  findDriver(driver) {
    if (driver.node >= 0) return this.nodes[driver.node] ?? null;
    const own = this.nodes.find((n) => n.name === driver.name);
    return own ?? this.scene.getTransformNodeByName?.(driver.name) ?? null;
  }

  /**
   * Builds a rig from the rest skeleton and the springBones at hand, and a new instance of it
   * (which starts at rest under the current drivers). Joints the previous rig moved and this one
   * does not go back to their rest rotation. Throws what loadRig throws, before changing anything.
   */
  build(sb, springBones, options) {
    const rig = sb.loadRig(this.gltfBytes, springBones, rigOptions(sb, options));
    let instance;
    try {
      instance = rig.createInstance();
    } catch (error) {
      rig.dispose();
      throw error;
    }
    const previous = this.jointNodes;
    this.release();
    this.rig = rig;
    this.instance = instance;
    if (rig.contentHash) this.metadata.key = rig.contentHash;
    this.jointNodes = rig.joints.map((j) => this.nodes[j.node] ?? null);
    this.driverNodes = rig.drivers.map((d) => this.findDriver(d));
    for (const node of this.jointNodes) {
      if (!node || this.restRotations.has(node)) continue;
      if (!node.rotationQuaternion) node.rotationQuaternion = node.rotation.toQuaternion();
      const q = node.rotationQuaternion;
      this.restRotations.set(node, [q.x, q.y, q.z, q.w]);
    }
    const current = new Set(this.jointNodes);
    for (const node of previous) {
      if (node && !current.has(node)) this.restoreRest(node);
    }
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
class FrameCopies {
  constructor() {
    this.set([]);
  }

  set(wearables) {
    this.instances = wearables.map((w) => w.instance);
    this.driverCounts = wearables.map((w) => w.driverNodes.length);
    this.jointCounts = wearables.map((w) => w.jointNodes.length);
    this.driverNodes = wearables.flatMap((w) => w.driverNodes);
    ({ nodes: this.recompute, force: this.forceRecompute } = nodesToRecompute(this.driverNodes));
    this.jointNodes = wearables.flatMap((w) => w.jointNodes);
    this.driverViews = wearables.map(() => kNoView);
    this.rotationViews = wearables.map(() => kNoView);
  }

  /** Each driver's current world matrix into its instance, in the glTF's space. */
  readDrivers(mirrored) {
    const { instances, driverCounts, driverViews, driverNodes, recompute, forceRecompute } = this;
    for (let i = 0; i < recompute.length; i++) recompute[i].computeWorldMatrix(forceRecompute);
    for (let i = 0, d = 0; i < instances.length; i++) {
      const count = driverCounts[i];
      let view = driverViews[i];
      // A view detaches when WebAssembly memory grows (its length drops to 0): fetch it again.
      if (view.length !== 16 * count) view = driverViews[i] = instances[i].driverMatrices;
      for (let o = 0, end = d + count; d < end; d++, o += 16) {
        const node = driverNodes[d];
        if (node !== null) copyWorldMatrix(node.getWorldMatrix().m, view, o, mirrored);
      }
    }
  }

  /** Each instance's rotations into its joints' rotationQuaternion (set() marks them dirty). */
  writeRotations() {
    const { instances, jointCounts, rotationViews, jointNodes } = this;
    for (let i = 0, j = 0; i < instances.length; i++) {
      const count = jointCounts[i];
      let r = rotationViews[i];
      if (r.length !== 4 * count) r = rotationViews[i] = instances[i].rotations;
      for (let k = 0, end = j + count; j < end; j++, k += 4) {
        const q = jointNodes[j]?.rotationQuaternion;
        if (q) q.set(r[k], r[k + 1], r[k + 2], r[k + 3]);
      }
    }
  }

  jumpAll() {
    for (const instance of this.instances) carryAcrossJump(instance);
  }
}

const isThenable = (value) => value !== null && (typeof value === 'object' || typeof value === 'function') && typeof value.then === 'function';

export class SpringBoneSimulation {
  /**
   * @param sb the springbones module (createSpringBones()), or a promise of it: wearables
   *   registered before it resolves stay at rest until it does, then their springs start.
   */
  constructor(sb) {
    this._wearables = new Map();  // itemId -> RegisteredWearable
    this._copies = new FrameCopies();
    this._sb = null;
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
    this._disposed = false;
    this._frame = () => this._step();
    if (isThenable(sb)) {
      /** Resolves once the module is there and every wearable registered so far has its rig. */
      this.ready = Promise.resolve(sb).then((module) => this._useModule(module));
      this.ready.catch(() => {});  // a page that never awaits it gets no unhandled rejection
    } else {
      this._useModule(sb);
      this.ready = Promise.resolve();
    }
  }

  _useModule(sb) {
    if (typeof sb?.loadRig !== 'function' || typeof sb?.createScene !== 'function') {
      throw new TypeError('SpringBoneSimulation: expected the springbones module (createSpringBones()) or a promise of it');
    }
    if (this._disposed) return;
    this._sb = sb;
    this._sbScene = sb.createScene();
    for (const wearable of this._wearables.values()) {
      try {
        wearable.build(sb, wearable.metadata.springBones, wearable.metadata.options);
      } catch (error) {
        wearable.error = error;  // registered before the module: reported here and on ready
        console.warn(`[springbones] ${wearable.itemId}: ${error.message}`);
      }
    }
    this._membersChanged();
    if (this._wind !== undefined) this._sbScene.setWind(this._wind);  // set before the module came
  }

  /**
   * Registers a wearable's container (after container.addAllToScene(), before its animation
   * starts: its current pose is taken as the rest pose). `springBonesParams`: the models entry
   * (node name -> parameters), the whole springBones (the entry under itemId), or
   * { springBones, entity, bodyShape } / { springBones, contentHash } / { springBones, glb };
   * left out, the springBones the loader extension was given for this file, else no chains until
   * updateParams gives it some. A container loaded with the extension is read by the file's own
   * node list rather than from its Babylon nodes. Registering an itemId
   * again replaces the earlier registration.
   * @throws TypeError for arguments of the wrong kind; SpringBonesError for metadata the core
   *   rejects (registered before the module is there: a console warning, and the wearable stays
   *   at rest)
   */
  registerWearable(scene, container, itemId, springBonesParams) {
    if (scene === null || typeof scene !== 'object' || typeof scene.getEngine !== 'function') {
      throw new TypeError('registerWearable: scene must be a Babylon Scene');
    }
    if (typeof itemId !== 'string' || itemId === '') throw new TypeError('registerWearable: itemId must be a non-empty string');
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
    const skeleton = loaded ? { nodes: loaded.nodes, gltfText: loaded.gltfText } : readWearableSkeleton(container);
    const wearable = new RegisteredWearable(scene, container, itemId, skeleton, metadata);
    if (this._sb) wearable.build(this._sb, metadata.springBones, metadata.options);
    this._wearables.set(itemId, wearable);
    this._membersChanged();
  }

  /**
   * The Builder's live tuning: `params` (node name -> parameters) becomes the wearable's models
   * entry. An added entry takes effect at once (by the standard's rules: a chain starts at an entry
   * with isRoot), a removed chain goes back to its rest pose; the chains restart from rest.
   * @throws Error for an itemId that was never registered; SpringBonesError for an entry the core rejects
   */
  updateParams(itemId, params) {
    const wearable = this._wearables.get(itemId);
    if (!wearable) throw new Error(`updateParams: no wearable registered as ${JSON.stringify(itemId)}`);
    if (params === null || typeof params !== 'object' || Array.isArray(params)) {
      throw new TypeError('updateParams: params must be an object of node name -> parameters');
    }
    const key = wearable.metadata.key ?? String(itemId);
    const springBones = entryAsSpringBones(key, params);
    const options = { ...wearable.metadata.options, contentHash: key };
    delete options.entity;
    delete options.bodyShape;
    delete options.glb;
    wearable.metadata = { springBones, options, key };
    if (this._sb) {
      wearable.build(this._sb, springBones, options);
      wearable.error = null;
      this._membersChanged();
    }
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
    for (const wearable of this._selected(itemId)) wearable.instance?.reset();
  }

  /**
   * Brings every wearable's springs (or only itemId's) to rest in the avatar's current pose
   * without rendering (instance.settle): for thumbnails, turntables and emote starts. Returns the
   * most steps one of them ran (0 before the module is there).
   * @param seconds at most this long (default 2, in [0, 60])
   * @throws RangeError for seconds out of range
   */
  settle(itemId, seconds) {
    const settling = this._selected(itemId).filter((wearable) => wearable.instance);
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
   * @throws Error for an itemId never registered; RangeError for a joint out of range or a
   *   non-finite point
   */
  grab(itemId, joint, point) {
    if (typeof itemId !== 'string') throw new TypeError('grab: itemId must be a string');
    const [wearable] = this._selected(itemId);
    if (!wearable.instance) return;
    const p = Array.isArray(point) ? point : [point?.x, point?.y, point?.z];
    wearable.instance.grab(joint, [this._mirrored ? -p[0] : p[0], p[1], p[2]]);
  }

  /** Lets go of what grab() holds, on every wearable (or itemId's): the hair swings back. */
  release(itemId) {
    for (const wearable of this._selected(itemId)) wearable.instance?.release();
  }

  /**
   * Tells the simulation that the avatar (every wearable, or only itemId's) moves discontinuously
   * before the next frame: a teleport, a jump cut. The hair is carried across it instead of
   * whipping after it. An animation group starting to play does this by itself.
   */
  jump(itemId) {
    for (const wearable of this._selected(itemId)) if (wearable.instance) carryAcrossJump(wearable.instance);
  }

  /**
   * Wind on every wearable, those registered later too (scene.setWind's argument: {direction,
   * strength, gustFrequency?, seed?}, the direction in the glTF's space as gravityDir is; null for
   * none). Before the module is there it is kept and checked when the module comes.
   * @throws TypeError / RangeError for a bad wind once the module is there
   */
  setWind(wind) {
    if (this._sbScene) {
      this._sbScene.setWind(wind);
    }
    this._wind = wind;
  }

  /** The rig of a registered wearable (null before the module is there or on a load error). */
  rigOf(itemId) {
    return this._wearables.get(itemId)?.rig ?? null;
  }

  /** Stops stepping, puts the joints back at rest and frees every rig and instance. */
  dispose(scene) {
    const hooked = scene ?? this._scene;
    if (this._observer && hooked) hooked.onBeforeRenderObservable.remove(this._observer);
    this._observer = null;
    this._scene = null;
    for (const group of this._watchedGroups) group.onAnimationGroupPlayObservable.removeCallback(this._onGroupPlay);
    this._watchedGroups.clear();
    this._watchedGroupCount = -1;
    for (const wearable of this._wearables.values()) wearable.dispose();
    this._wearables.clear();
    this._copies.set([]);
    this._sbScene?.dispose();
    this._sbScene = null;
    this._disposed = true;
  }

  _selected(itemId) {
    if (itemId === undefined) return [...this._wearables.values()];
    const wearable = this._wearables.get(itemId);
    if (!wearable) throw new Error(`no wearable registered as ${JSON.stringify(itemId)}`);
    return [wearable];
  }

  /** Rebuilds the springbones scene's members and the flat per-frame arrays. */
  _membersChanged() {
    if (!this._sbScene) return;
    const members = [...this._wearables.values()].filter((w) => w.instance);
    for (const w of members) this._sbScene.add(w.instance);  // disposed instances left by themselves
    this._copies.set(members);
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
