// three.js adapter for springbones: wears a loaded wearable on a loaded avatar the way
// Decentraland assembles avatars (ADR-57: a wearable carries the armature bones it needs and is
// matched to the avatar by bone name), then drives its spring bones with a springbones rig.
//
//   const attachment = attachWearable(avatar.scene, wearableGltf, rig);
//   // every frame, after the animation mixer and avatar.scene.updateMatrixWorld():
//   attachment.update(dt);
//   // or, not waiting for the module: worn and drawn now, simulated once the rig is there
//   const attachment = attachWearable(avatar.scene, wearableGltf, sbPromise.then((sb) => sb.loadRig(...)));
//   // or, for many avatars, one call into WebAssembly for all of them:
//   const group = new SpringBonesGroup(springBones);  group.add(attachment);  ...  group.update(dt);
//
// Per frame: each driver's `matrixWorld` goes into the instance's driver matrices, the instance
// steps, and each joint's local rotation is written into its Object3D's quaternion. No allocation
// per frame. The rotations are written into the quaternion's fields (_x, _y, _z, _w) rather than
// with Quaternion.set(), which would fire the onChange callback that recomputes Object3D.rotation
// (an Euler, with trigonometry) for every joint every frame; a simulated joint's `.rotation` is
// therefore stale until attachment.syncEulers() — read `.quaternion`. The joints' matrix and
// matrixWorld are left to three.js's updateMatrixWorld (web/three/README.md says why, with numbers).
//
// `three` is a peer dependency (imported as 'three'); this module only uses springbones' public
// JavaScript API (rig.joints, rig.drivers, rig.createInstance, createScene, instance.driverMatrices
// / step / rotations / reset / dispose), never the WebAssembly glue.
import { BufferAttribute, BufferGeometry, Color, LineBasicMaterial, LineSegments, Object3D, Skeleton } from 'three';
import { AnimationStartWatch } from './animationStarts.js';
import { boneNotMatched, consoleReporter, diagnostic, failureDiagnostic, rigDiagnostics } from '../wearable/diagnostics.js';
import { carryMotion, checkOptionKeys } from '../wearable/rig_life.js';
import { restBonesFromInverseBinds } from '../wearable/avatar_bones.js';
import { colliderDiagnostics, collidersWithFrames, frameFollowers, withMeasuredBones } from '../wearable/collider_followers.js';
import { FrameCopyLists } from '../wearable/frame_copies.js';
import { isSpringBoneName } from '../wearable/spring_bone_name.js';

/** The codes of setColliders' warnings: replaced by each call (web/wearable/diagnostics.js). */
const kColliderCodes = ['collider-invalid', 'collider-on-spring-bone', 'body-collider-skipped', 'collider-not-followed'];

/** Symbol of the option with which SpringBonesWearable.wear() hands its context to attachWearable. */
export const kWearableContext = Symbol('springbones.wearableContext');

/** Whether `value` is a promise (or any thenable) rather than the thing itself. */
export const isThenable = (value) => typeof value?.then === 'function';

// The privates of SpringBonesAttachment and SpringBonesGroup that the other classes of this module
// reach (FrameCopies and the group read an attachment's lists; an attachment moves itself to the
// end of its group): set by each class's static block.
let attachmentPrivates;
let groupPrivates;

/** Whether the attachment was disposed of (for SpringBonesWearable, springBonesLoaderPlugin.js). */
export const attachmentDisposed = (attachment) => attachmentPrivates.disposed(attachment);

/** The glTF name of an object: GLTFLoader keeps it in userData.name (object.name is sanitized). */
const gltfName = (object) => object.userData?.name ?? object.name;

// Avatar armatures and their rest bones, computed once per avatar root before anything is attached
// to it, so bones (and skins) a wearable adds are never taken for the avatar's by the next wearable.
const armatureCache = new WeakMap();
const restBonesCache = new WeakMap();

/**
 * The avatar's armature as a map from glTF node name to object: every bone of the avatar's
 * skinned meshes and every ancestor of those bones below `avatarRoot` (e.g. `Armature`). Computed
 * on first use and cached per root.
 */
export function avatarArmature(avatarRoot) {
  let map = armatureCache.get(avatarRoot);
  if (map) return map;
  map = new Map();
  const add = (object) => {
    const name = gltfName(object);
    if (name && !map.has(name)) map.set(name, object);
  };
  const joints = [];
  avatarRoot.traverse((object) => {
    if (!object.isSkinnedMesh) return;
    const { bones, boneInverses } = object.skeleton;
    bones.forEach((bone, i) => {
      for (let o = bone; o && o !== avatarRoot; o = o.parent) add(o);
      if (boneInverses[i]) joints.push({ name: gltfName(bone), inverseBind: boneInverses[i].elements });
    });
  });
  if (map.size === 0) avatarRoot.traverse((o) => { if (o.isBone) add(o); });  // no skinned mesh
  armatureCache.set(avatarRoot, map);
  restBonesCache.set(avatarRoot, restBonesFromInverseBinds(joints));
  return map;
}

/**
 * The avatar's bones with their rest world matrices, as loadRig's `avatarBones` (glTF node name ->
 * 16 numbers, column-major): the inverse of each joint's inverse bind matrix in the avatar's
 * skinned meshes (web/wearable/avatar_bones.js), so the rest pose whatever the avatar is playing,
 * in the avatar file's own space. Null for an avatar without skins. Read with avatarArmature,
 * before anything is attached to the root, and cached per root. For a page that loads the rig
 * itself: `sb.loadRig(glb, springBones, { colliders: 'dcl-body', avatarBones: avatarRestBones(avatar.scene) })`.
 */
export function avatarRestBones(avatarRoot) {
  if (!avatarRoot?.isObject3D) throw new TypeError('avatarRestBones: avatarRoot must be an Object3D');
  avatarArmature(avatarRoot);
  return restBonesCache.get(avatarRoot);
}

/**
 * The Object3D of every glTF node of a loaded GLB, indexed like the file's `nodes` array (the
 * indices rig.joints[].node and rig.drivers[].node use). `gltf` is GLTFLoader's result; pass
 * `root` when attaching a clone of gltf.scene (SkeletonUtils.clone): the clone has the same shape,
 * so its objects are found by walking both trees side by side.
 */
export function wearableNodes(gltf, root = gltf.scene) {
  const nodes = [];
  const associations = gltf.parser?.associations;
  if (!associations) throw new TypeError('wearableNodes: expected a GLTFLoader result ({ scene, parser })');
  const walk = (original, copy) => {
    const index = associations.get(original)?.nodes;
    if (index !== undefined) nodes[index] = copy;
    if (original.children.length !== copy.children.length) {
      throw new Error('wearableNodes: root is not a clone of gltf.scene (different shapes)');
    }
    for (let i = 0; i < original.children.length; i++) walk(original.children[i], copy.children[i]);
  };
  walk(gltf.scene, root);
  return nodes;
}

/** A matrixWorld's 16 elements into `m` at `o` (nothing for null: no object); 16 statements, no loop. */
function copyMatrix(e, m, o) {
  if (e === null) return;
  m[o] = e[0]; m[o + 1] = e[1]; m[o + 2] = e[2]; m[o + 3] = e[3];
  m[o + 4] = e[4]; m[o + 5] = e[5]; m[o + 6] = e[6]; m[o + 7] = e[7];
  m[o + 8] = e[8]; m[o + 9] = e[9]; m[o + 10] = e[10]; m[o + 11] = e[11];
  m[o + 12] = e[12]; m[o + 13] = e[13]; m[o + 14] = e[14]; m[o + 15] = e[15];
}

/**
 * The per-frame copies between three.js and springbones for a list of attachments (one attachment
 * on its own, or a group's): each driver's matrixWorld into its instance's driverMatrices, and each
 * instance's rotations into its joints' quaternions (the kept views: web/wearable/frame_copies.js).
 * Allocation-free per frame.
 *
 * Shaped by measurements (web/three/README.md, "Flat loops, kept views"): the copies are
 * memory-bound, since every driver matrix is its own small array and every quaternion its own
 * object with each field a separately boxed double, scattered over three.js's heap. So one flat
 * loop runs over all members' drivers (and one over all joints) instead of a loop per attachment,
 * and the 16 elements of a matrix are copied by 16 statements rather than an inner loop. All 16
 * elements are copied, so a non-affine matrixWorld reaches the core, which checks for it.
 */
class FrameCopies extends FrameCopyLists {
  /** Takes the attachments' current instances and objects; call whenever they change. */
  setMembers(attachments) {
    this.setCounts(attachments.map((a) => a.instance), attachments.map((a) => attachmentPrivates.driverElements(a).length),
      attachments.map((a) => attachmentPrivates.quaternions(a).length), attachments.map((a) => attachmentPrivates.frameElements(a).length));
    this.driverElements = attachments.flatMap((a) => attachmentPrivates.driverElements(a));  // null: no object
    this.frameElements = attachments.flatMap((a) => attachmentPrivates.frameElements(a));  // setColliders' followed objects
    this.quaternions = attachments.flatMap((a) => attachmentPrivates.quaternions(a));
  }

  readDrivers() {
    const { instances, driverCounts, driverElements, frameCounts, frameElements } = this;
    for (let i = 0, d = 0; i < instances.length; i++) {
      const m = this.driverView(i);
      for (let o = 0, end = d + driverCounts[i]; d < end; d++, o += 16) copyMatrix(driverElements[d], m, o);
    }
    // The frames of colliders setColliders put on objects (a hat, another wearable's node): the
    // object's matrixWorld into frameMatrices, as a driver's.
    for (let i = 0, f = 0; i < instances.length; i++) {
      if (frameCounts[i] === 0) continue;
      const m = this.frameView(i);
      for (let o = 0, end = f + frameCounts[i]; f < end; f++, o += 16) copyMatrix(frameElements[f], m, o);
    }
  }

  /**
   * Writes the quaternions' fields only: Quaternion.set() would fire onChange, which recomputes
   * the joint's Euler `.rotation` with trigonometry for every joint every frame; `.rotation` is
   * therefore stale until attachment.syncEulers(). (A getter converting on read was tried:
   * redefining `rotation` on the joints turns them into dictionary-mode objects and made
   * three.js's updateMatrixWorld 1.6x slower for the whole tree.)
   * With `active` (a scene's flags, one per member), members with a 0 are skipped: their
   * instance held its pose, which their joints already show.
   */
  writeRotations(active = null) {
    const { instances, jointCounts, quaternions } = this;
    for (let i = 0, j = 0; i < instances.length; i++) {
      const count = jointCounts[i];
      if (active !== null && active[i] === 0) {
        j += count;
        continue;
      }
      const r = this.rotationView(i);
      for (let k = 0, end = j + count; j < end; j++, k += 4) {
        const q = quaternions[j];
        q._x = r[k];
        q._y = r[k + 1];
        q._z = r[k + 2];
        q._w = r[k + 3];
      }
    }
  }
}

/**
 * A wearable worn by an avatar and simulated by one springbones instance. Made by attachWearable.
 */
export class SpringBonesAttachment {
  #context; #report; #armatureObjects; #unmatchedBones; #moved; #restQuaternions;
  #instanceOptions; #group; #animationStarts; #copies; #quaternions; #driverElements;
  #disposed; #colliders; #frameElements;

  static {
    attachmentPrivates = {
      driverElements: (attachment) => attachment.#driverElements,
      frameElements: (attachment) => attachment.#frameElements,
      quaternions: (attachment) => attachment.#quaternions,
      group: (attachment) => attachment.#group,
      setGroup: (attachment, group) => { attachment.#group = group; },
      disposed: (attachment) => attachment.#disposed,
      noteAnimationStarts: (attachment) => attachment.#noteAnimationStarts(),
    };
  }

  /** @private use attachWearable */
  constructor(avatarRoot, wearableRoot, nodeObjects, rig, options, meshes = [], moved = [], armatureObjects = new Set(), unmatchedBones = new Set()) {
    this.avatarRoot = avatarRoot;
    this.wearableRoot = wearableRoot;
    /** Every glTF node of the wearable (index = glTF node index), after matching: a node the
     *  avatar also has is replaced by the avatar's object. */
    this.nodes = nodeObjects;
    /** The wearable's skinned meshes, now bound to the avatar's bones. */
    this.meshes = meshes;
    /** Problems found while attaching ({ code, message, fix, path }): nodes without an object,
     *  and every reason the spring bones stay at rest (docs/diagnostics.md). */
    this.warnings = [];  // rebuilt by setRig
    // Static-hair warnings go to the console once per code: per wearable when wear() made this
    // attachment (the wearable's reporter), else per attachment; options.onWarning replaces it.
    const context = options[kWearableContext] ?? null;
    this.#context = context;
    this.#report = typeof options.onWarning === 'function' ? options.onWarning
      : context?.report ?? consoleReporter(() => `wearable ${this.rig?.contentHash || (gltfName(wearableRoot) || '(unnamed)')}`);
    this.#armatureObjects = armatureObjects;  // the avatar's bones, for bone-not-matched
    this.#unmatchedBones = unmatchedBones;  // the wearable's bones no avatar bone matched
    this.#moved = moved;  // [object, previous parent], for detach
    this.#restQuaternions = new Map();  // joint object -> its rest quaternion (x, y, z, w)
    this.#instanceOptions = options.instance;
    this.#group = null;  // the SpringBonesGroup stepping this attachment, if any
    this.#animationStarts = null;  // an AnimationStartWatch (watchAnimations)
    this.#copies = new FrameCopies();  // readDrivers / writeRotations for this attachment alone
    this.rig = null;
    this.instance = null;
    /** Object3D per rig joint (its rotation is written) and per driver (its matrixWorld is read). */
    this.jointObjects = [];
    this.tailObjects = [];
    this.driverObjects = [];
    this.#quaternions = [];
    this.#driverElements = [];
    this.#colliders = null;  // the last setColliders call ({ colliders, options }), kept for a new rig
    this.#frameElements = [];  // matrixWorld.elements of the object each of the instance's frames follows
    this.#disposed = false;
    /** What a rig given as a promise rejected with (or its setRig threw), else null. */
    this.error = null;
    if (isThenable(rig)) {
      // Worn and drawn now, at rest; simulated from the first update after the rig arrives, whose
      // step puts every tail at rest under that frame's drivers (docs/semantics.md): the pose
      // drawn until then, so nothing jumps. A rejection surfaces once, through `ready`.
      this.ready = Promise.resolve(rig).then((arrived) => {
        if (!this.#disposed) this.setRig(arrived);
        return this;
      }).catch((error) => {
        this.error = error;
        const warning = this.#context?.failure() ?? failureDiagnostic(error, ['module-load-failed', 'module-not-found'].includes(error?.code));
        this.warnings.push(warning);
        this.#report(warning);
        throw error;
      });
      // Said on the console above: an application that does not catch `ready` gets the warning,
      // not an unhandled rejection (which ends a Node process).
      this.ready.catch(() => {});
    } else {
      this.setRig(rig);
      this.ready = Promise.resolve(this);
    }
  }

  /**
   * The reasons this rig leaves the spring bones at rest (web/wearable/diagnostics.js): what the
   * wearable's metadata says (from wear(), which knows it; else only what the rig and the nodes
   * show), and drivers that no bone of the avatar matched (they hang from the avatar root).
   */
  #diagnose(rig) {
    const found = this.#context?.diagnose(rig)
      ?? rigDiagnostics({ rig, entry: undefined, nodes: this.nodes.map((o) => ({ name: o ? gltfName(o) : '' })) });
    // A driver follows the avatar when the way up from it reaches an avatar bone through the
    // wearable's own helper nodes only: a bone of the wearable's armature on that way had no avatar
    // bone of its name (it follows its parent, not the avatar's bone), and reaching the avatar root
    // means nothing of the avatar moves it.
    const bones = new Set();
    const drivers = new Set();
    this.driverObjects.forEach((object, index) => {
      if (!object) return;
      let o = object;
      let missed = false;
      for (; o && o !== this.avatarRoot && !this.#armatureObjects.has(o); o = o.parent) {
        if (this.#unmatchedBones.has(o)) {
          bones.add(gltfName(o));
          missed = true;
        }
      }
      if (!o || o === this.avatarRoot) {
        bones.add(rig.drivers[index].name);
        missed = true;
      }
      if (missed) drivers.add(index);
    });
    const unmatched = boneNotMatched(rig, drivers, [...bones]);
    if (unmatched) found.push(unmatched);
    for (const warning of found) {
      this.warnings.push(warning);
      this.#report(warning);
    }
  }

  /**
   * Replaces the instance's colliders (the rig's included) from the next update on
   * (instance.setColliders): `colliders` as loadRig's option takes them, an array or 'dcl-body',
   * null or [] for none, where a collider's `node` is a name (a rig driver, a bone of the avatar, a
   * node of the wearable or of the scene) or any Object3D (a hat, a hand, another wearable's
   * node): every update() then copies that object's matrixWorld for it, after the drivers'.
   * `options` { scale?, omit?, avatarBones? }: for 'dcl-body', every shape's radius times `scale`
   * and the shapes named in `omit` left out, measured on the avatar's bones (avatarRestBones)
   * unless `avatarBones` is given. Kept across setRig; before a rig given as a promise arrives, it
   * is applied when it does. Returns the instance's warnings (each also reported, as the
   * attachment's other warnings, with a fix: docs/diagnostics.md); [] before the rig arrives.
   * @throws TypeError / RangeError / SpringBonesError for a bad collider, as instance.setColliders
   *   (messages starting `setColliders:`), before anything changes
   */
  setColliders(colliders, options) {
    const previous = this.#colliders;
    this.#colliders = { colliders, options };
    if (this.instance === null) {
      try {
        this.#collidersForInstance();  // the objects' part is checked now; the rest when the rig arrives
      } catch (error) {
        this.#colliders = previous;
        throw error;
      }
      return Object.freeze([]);
    }
    let warnings;
    try {
      warnings = this.#applyColliders();
    } catch (error) {
      this.#colliders = previous;
      throw error;
    }
    this.#copies.setMembers([this]);
    if (this.#group) groupPrivates.membersChanged(this.#group);
    return warnings;
  }

  /** The kept setColliders call as the instance takes it, and the objects its frames follow. */
  #collidersForInstance() {
    const { colliders, options } = this.#colliders;
    const engine = { isObject: (value) => value?.isObject3D === true, nameOf: gltfName, driverNames: this.rig?.drivers.map((d) => d.name) ?? [] };
    const prepared = collidersWithFrames('setColliders', colliders, engine);
    return { ...prepared, options: withMeasuredBones(colliders, options, avatarRestBones(this.avatarRoot)) };
  }

  /** Applies the kept setColliders call to the instance; its warnings, reported. */
  #applyColliders() {
    const { colliders, options, followed } = this.#collidersForInstance();
    const warnings = this.instance.setColliders(colliders, options);
    const byName = (name) => this.nodes.find((o) => o && gltfName(o) === name) ?? this.avatarRoot.getObjectByName(name) ?? null;
    const { objects, missing } = frameFollowers(this.instance.frameNames, followed, byName);
    this.#frameElements = objects.map((o) => (o ? o.matrixWorld.elements : null));
    const kept = this.warnings.filter((w) => !kColliderCodes.includes(w.code));
    const found = colliderDiagnostics(warnings, missing);
    this.warnings = [...kept, ...found];
    for (const warning of found) this.#report(warning);
    return warnings;
  }

  /** Whether update() simulates: false while a rig given as a promise has not arrived. */
  get simulating() {
    return this.instance !== null;
  }

  /**
   * Switches to another rig of the same GLB (e.g. the same file loaded with edited metadata): a
   * new instance takes the current one's motion over (instance.carryFrom, as the Babylon
   * drop-in's updateParams does: joints both rigs simulate keep swinging, new ones start from
   * where they are drawn; `carry: false` starts every chain at rest instead), joints the new rig
   * does not simulate go back to their rest rotation, and the old instance is disposed of. The rig
   * is not owned: the caller disposes of it.
   */
  setRig(rig, { carry = true } = {}) {
    if (!rig || !Array.isArray(rig.joints) || !Array.isArray(rig.drivers)) {
      throw new TypeError('setRig: expected a springbones rig (with joints and drivers)');
    }
    const instance = rig.createInstance(this.#instanceOptions);  // throws before anything changes
    if (this.#group) {
      try {
        this.#group.scene.add(instance);  // e.g. a rig of another springbones module throws
      } catch (error) {
        instance.dispose();
        throw error;
      }
    }
    const previous = this.jointObjects;
    const previousInstance = this.instance;
    this.instance = instance;
    this.rig = rig;
    this.warnings = [];
    const find = (index, what, name) => {
      const object = this.nodes[index];
      if (!object) this.warnings.push(diagnostic('node-not-found', { what, name, index }));
      return object ?? null;
    };
    this.jointObjects = rig.joints.map((j) => find(j.node, 'joint', j.name));
    this.tailObjects = rig.joints.map((j) => this.nodes[j.tailNode] ?? null);
    // A driver that is no node of the wearable (node -1: a collider on an avatar bone, such as the
    // 'dcl-body' shapes loadRig measured on the avatar's bones, avatarBones) is the avatar's object
    // of that name, as the core's rule has it.
    const avatarObject = (d) => (d.node < 0 && d.name ? this.avatarRoot.getObjectByName(d.name) ?? null : null);
    this.driverObjects = rig.drivers.map((d) => avatarObject(d) ?? find(d.node, 'driver', d.name));
    this.#diagnose(rig);
    for (const object of this.jointObjects) {
      if (object && !this.#restQuaternions.has(object)) {
        const q = object.quaternion;
        this.#restQuaternions.set(object, [q.x, q.y, q.z, q.w]);
      }
    }
    const current = new Set(this.jointObjects);
    for (const object of previous) {
      // fromArray fires onChange, so the released joint's .rotation is in step again
      if (object && !current.has(object)) object.quaternion.fromArray(this.#restQuaternions.get(object));
    }
    // The per-frame loops touch only these arrays: the joints' Quaternion objects (a joint without
    // an object writes into a spare Object3D's: a bare `new Quaternion()` has another hidden class,
    // without the own onChange callback, and would make the write loop polymorphic) and the
    // drivers' matrixWorld.elements arrays (Matrix4 keeps its array for life; a missing driver
    // keeps the rest world matrix the instance starts with). Reaching through object.quaternion
    // each frame cost 3x more (cache misses).
    this.#quaternions = this.jointObjects.map((o) => (o ? o.quaternion : new Object3D().quaternion));
    this.#driverElements = this.driverObjects.map((o) => (o ? o.matrixWorld.elements : null));
    if (carry) {
      carryMotion(instance, previousInstance, (next) => {
        const m = next.driverMatrices;
        this.#driverElements.forEach((e, d) => e && m.set(e, 16 * d));
      });
    }
    previousInstance?.dispose();  // also takes it out of the group's scene
    this.#frameElements = [];
    if (this.#colliders !== null) this.#applyColliders();  // the page's colliders outlive a rig swap
    this.#copies.setMembers([this]);
    if (this.#group) groupPrivates.moveToEnd(this.#group, this);  // the new instance took the scene's last slot
    // Start from the rest pose (the rig's rotations before the first step), or the carried one.
    this.writeRotations();
  }

  /**
   * One frame: reads the drivers' matrixWorld (call avatarRoot.updateMatrixWorld() — or the
   * scene's — after animating and before this), steps by dt seconds and writes the joints'
   * quaternions. The joints' matrixWorld is refreshed by the next updateMatrixWorld (the renderer
   * does it). Allocation-free. An attachment in a SpringBonesGroup is stepped by group.update():
   * calling this too would step it twice.
   */
  update(dt) {
    if (this.instance === null) return;  // no rig yet: the joints keep the pose drawn at rest
    this.readDrivers();
    this.instance.step(dt);
    this.writeRotations();
  }

  /**
   * Copies each driver's matrixWorld into the instance (a driver without an object is skipped);
   * an animation that started since the last frame is announced to it as a jump.
   */
  readDrivers() {
    this.#noteAnimationStarts();
    this.#copies.readDrivers();
  }

  /**
   * Treats every action of `mixer` that starts as a jump (instance.jump()): the chains are carried
   * across the pose change instead of whipping. null stops watching. attachWearable's `mixer`
   * option calls this.
   */
  watchAnimations(mixer) {
    this.#animationStarts = mixer ? new AnimationStartWatch(mixer) : null;
  }

  #noteAnimationStarts() {
    if (this.#animationStarts?.started()) this.instance.jump();
  }

  /**
   * Writes the instance's rotations into the joints' quaternions, fields only (see FrameCopies):
   * `.rotation` is stale until syncEulers().
   */
  writeRotations() {
    this.#copies.writeRotations();
  }

  /**
   * Brings the joints' `.rotation` (Euler) back in step with their quaternions: the per-frame
   * writes leave it behind (see writeRotations). Only for code that reads `.rotation` of a
   * simulated joint (an inspector, a serializer): three.js's rendering, skinning, clone() and
   * glTF export use the quaternion. Allocation-free.
   */
  syncEulers() {
    for (const object of this.jointObjects) {
      if (object) object.rotation.setFromQuaternion(object.quaternion, undefined, false);  // no onChange
    }
  }

  /** Forgets the motion (teleports, avatar swaps): the next update starts from rest. */
  reset() {
    if (this.instance !== null) this.instance.reset();
  }

  /**
   * Brings the springs to rest in the avatar's current pose without rendering (instance.settle):
   * reads the drivers' matrixWorld (update world matrices first), settles and writes the joints.
   * For thumbnails, turntables and emote starts. Returns the steps it ran (0 before the rig arrives).
   */
  settle(seconds) {
    if (this.instance === null) return 0;
    // An animation that started before this is the pose settled in, not a jump after it.
    this.#animationStarts?.started();
    this.#copies.readDrivers();
    const steps = this.instance.settle(seconds);
    this.writeRotations();
    return steps;
  }

  /**
   * Disposes of the instance (update() then throws the API's 'disposed' error) and, with detach
   * (the default), takes the wearable's objects off the avatar, restores the joints' rest
   * rotations and frees the re-bound skeletons' bone textures. The rig, geometries and materials
   * are the caller's to dispose of.
   */
  dispose({ detach = true } = {}) {
    if (this.#group) this.#group.remove(this);
    this.#disposed = true;  // a rig still on its way is not used
    this.syncEulers();  // the joints keep their pose (detach: false) with a current .rotation
    if (this.instance !== null) this.instance.dispose();
    if (detach) {
      for (const [object, rest] of this.#restQuaternions) object.quaternion.fromArray(rest);
      for (const [object, parent] of this.#moved) {
        object.removeFromParent();
        if (parent) parent.add(object);
      }
      this.#moved.length = 0;
      for (const mesh of this.meshes) mesh.skeleton.dispose();
    }
  }
}

/**
 * Steps many attachments with one call into WebAssembly: update(dt) reads every attachment's
 * drivers, runs one springbones scene.step for all their instances and writes every attachment's
 * rotations. Per-instance step() calls cost a JS -> WebAssembly transition and a scheduling pass
 * each; the scene also gives the whole crowd one distance budget (scene.setBudget).
 */
export class SpringBonesGroup {
  #copies; #rootElements; #waiting;

  static {
    groupPrivates = {
      moveToEnd: (group, attachment) => group.#moveToEnd(attachment),
      membersChanged: (group) => group.#membersChanged(),
    };
  }

  /**
   * springBones: the module from createSpringBones(). The group owns the springbones scene it
   * creates (`this.scene`, for setBudget / isActive), not the attachments.
   */
  constructor(springBones) {
    if (typeof springBones?.createScene !== 'function') {
      throw new TypeError('SpringBonesGroup: expected the springbones module (the result of createSpringBones())');
    }
    this.scene = springBones.createScene();
    /** The attachments, in the scene's slot order (scene.positions[3 * i] is attachments[i]'s). */
    this.attachments = [];
    this.#copies = new FrameCopies();  // every attachment's drivers and joints, in one flat list
    this.#rootElements = [];  // each attachment's avatarRoot.matrixWorld.elements, for positions
    this.#waiting = [];  // added before their rig arrived: not in the scene yet
  }

  /** Adds an attachment (adding it again does nothing); an attachment belongs to one group. */
  add(attachment) {
    if (!(attachment instanceof SpringBonesAttachment)) {
      throw new TypeError('SpringBonesGroup.add: expected an attachment from attachWearable()');
    }
    if (attachmentPrivates.group(attachment) === this) return;
    if (attachmentPrivates.group(attachment)) throw new Error('SpringBonesGroup.add: the attachment is in another group');
    if (attachment.instance === null) {
      // Its rig is on its way: setRig adds the instance to this scene when it arrives.
      if (attachmentPrivates.disposed(attachment)) throw new Error('SpringBonesGroup.add: the attachment is disposed of');
      attachmentPrivates.setGroup(attachment, this);
      this.#waiting.push(attachment);
      return;
    }
    this.scene.add(attachment.instance);  // throws for a disposed instance or another module's
    this.attachments.push(attachment);
    attachmentPrivates.setGroup(attachment, this);
    this.#membersChanged();
  }

  /** Takes an attachment out (it can then update() on its own); not in the group: nothing happens. */
  remove(attachment) {
    const waiting = this.#waiting.indexOf(attachment);
    if (waiting >= 0) {
      this.#waiting.splice(waiting, 1);
      attachmentPrivates.setGroup(attachment, null);
      return;
    }
    const index = this.attachments.indexOf(attachment);
    if (index < 0) return;
    if (!attachment.instance.disposed) this.scene.remove(attachment.instance);
    this.attachments.splice(index, 1);
    attachmentPrivates.setGroup(attachment, null);
    this.#membersChanged();
  }

  /**
   * One frame for every attachment: call after updating world matrices, as for
   * attachment.update(). Allocation-free.
   */
  update(dt) {
    this.readDrivers();
    this.scene.step(dt);
    this.writeRotations();
  }

  /**
   * The first part of update(): every attachment's drivers into its instance, and each avatar
   * root's world position into scene.positions (for the budget).
   */
  readDrivers() {
    const attachments = this.attachments;
    for (let i = 0; i < attachments.length; i++) attachmentPrivates.noteAnimationStarts(attachments[i]);
    this.#copies.readDrivers();
    const positions = this.scene.positions;  // a getter: the view survives memory growth
    const roots = this.#rootElements;
    for (let i = 0, p = 0; i < roots.length; i++, p += 3) {
      const e = roots[i];
      positions[p] = e[12];
      positions[p + 1] = e[13];
      positions[p + 2] = e[14];
    }
  }

  /**
   * The last part of update(): the rotations of every attachment the last step simulated into
   * its joints' quaternions. Attachments the budget held are not written: their joints keep the
   * pose written when they last stepped, which is the pose their instance holds (unless other
   * code, e.g. an animation mixer, writes those joints meanwhile).
   */
  writeRotations() {
    this.#copies.writeRotations(this.scene.active);
  }

  /**
   * attachment.settle(seconds) for every attachment (update world matrices first); returns the
   * most steps one of them ran.
   */
  settle(seconds) {
    let most = 0;
    for (const attachment of this.attachments) most = Math.max(most, attachment.settle(seconds));
    return most;
  }

  /** Frees the scene; the attachments stay usable on their own (their update()). */
  dispose() {
    for (const attachment of this.attachments) attachmentPrivates.setGroup(attachment, null);
    for (const attachment of this.#waiting) attachmentPrivates.setGroup(attachment, null);
    this.attachments = [];
    this.#waiting = [];
    this.#membersChanged();
    this.scene.dispose();
  }

  // setRig replaced the attachment's instance: the scene dropped the old one's slot (later slots
  // shift down) and appended the new one, so the attachment moves to the end here too.
  // An attachment added while its rig was on its way gets its first slot the same way.
  #moveToEnd(attachment) {
    const waiting = this.#waiting.indexOf(attachment);
    if (waiting >= 0) this.#waiting.splice(waiting, 1);
    const index = this.attachments.indexOf(attachment);
    if (index >= 0) this.attachments.splice(index, 1);
    this.attachments.push(attachment);
    this.#membersChanged();
  }

  // The attachments, their instances or their objects changed: rebuild the flat lists.
  #membersChanged() {
    this.#copies.setMembers(this.attachments);
    this.#rootElements = this.attachments.map((a) => a.avatarRoot.matrixWorld.elements);
  }
}

/**
 * Wears a loaded wearable on an avatar and creates its simulation.
 *
 * avatarRoot: the avatar's Object3D (its GLTF scene, or a clone), already in the scene or not.
 * wearable:   GLTFLoader's result for the wearable GLB ({ scene, parser }), or an Object3D with
 *             `options.nodes` (glTF node index -> Object3D, see wearableNodes) — for a clone.
 * rig:        the springbones rig loaded from the same GLB bytes (and its metadata).
 * options:    { nodes?: Object3D[], instance?: options for rig.createInstance,
 *               mixer?: the avatar's AnimationMixer, whose action starts become jumps,
 *               onWarning?: receives each reason the spring bones stay at rest, instead of the
 *               console (staticHair.js) }.
 *
 * Matching, as Decentraland's armature does: a wearable node whose glTF name is a node of the
 * avatar's armature (avatarArmature) *is* that avatar node; every other node (spring bones,
 * meshes) is moved, with its local transform, under the avatar's counterpart of its nearest
 * matched ancestor (the avatar root when there is none). The wearable's skinned meshes are re-bound
 * to the avatar's bones of the same names, with the wearable's own inverse bind matrices. The
 * wearable's objects can be attached once; to wear one item on several avatars, attach clones.
 */
export function attachWearable(avatarRoot, wearable, rig, options = {}) {
  if (!avatarRoot?.isObject3D) throw new TypeError('attachWearable: avatarRoot must be an Object3D');
  if (options === null || typeof options !== 'object') throw new TypeError('attachWearable: options must be an object');
  checkOptionKeys('attachWearable', options, ['nodes', 'instance', 'mixer', 'onWarning']);
  if (!isThenable(rig) && (!rig || !Array.isArray(rig.joints) || !Array.isArray(rig.drivers))) {
    throw new TypeError('attachWearable: rig must be a springbones rig (with joints and drivers) or a promise of one');
  }
  if (options.onWarning !== undefined && typeof options.onWarning !== 'function') {
    throw new TypeError('attachWearable: options.onWarning must be a function (it receives each warning)');
  }
  const wearableRoot = wearable?.isObject3D ? wearable : wearable?.scene;
  if (!wearableRoot?.isObject3D) throw new TypeError('attachWearable: wearable must be a GLTF result or an Object3D');
  const original = options.nodes ?? (wearable.parser ? wearableNodes(wearable) : null);
  if (!original) throw new TypeError('attachWearable: pass options.nodes with an Object3D wearable');

  const armature = avatarArmature(avatarRoot);
  const counterpart = (object) => {
    if (object.isSkinnedMesh) return null;
    const match = armature.get(gltfName(object));
    return match && match !== object ? match : null;
  };
  // Which wearable objects have a matched descendant (those are walked through, not moved).
  const hasMatch = new Set();
  wearableRoot.traverse((object) => {
    if (counterpart(object)) for (let o = object.parent; o && !hasMatch.has(o); o = o.parent) hasMatch.add(o);
  });
  const skinned = [];
  wearableRoot.traverse((o) => { if (o.isSkinnedMesh) skinned.push(o); });
  // The wearable's armature (its meshes' bones and their ancestors) that found no avatar bone of
  // its name, spring bones aside (they are the wearable's own): for the bone-not-matched warning.
  const unmatchedBones = new Set();
  for (const mesh of skinned) {
    for (const bone of mesh.skeleton.bones) {
      for (let o = bone; o && o !== wearableRoot; o = o.parent) {
        if (!counterpart(o) && !isSpringBoneName(gltfName(o))) unmatchedBones.add(o);
      }
    }
  }

  const moved = [];
  const visit = (node, target) => {
    for (const child of [...node.children]) {
      const match = counterpart(child);
      if (match) visit(child, match);
      else if (hasMatch.has(child)) visit(child, target);
      else {
        moved.push([child, child.parent]);
        target.add(child);  // keeps child.position/quaternion/scale: same local transform
      }
    }
  };
  visit(wearableRoot, avatarRoot);

  // Re-bind: same inverse bind matrices, avatar bones where the names match.
  for (const mesh of skinned) {
    const old = mesh.skeleton;
    const bones = old.bones.map((bone) => counterpart(bone) ?? bone);
    mesh.bind(new Skeleton(bones, old.boneInverses), mesh.bindMatrix);
    old.dispose();
    mesh.boundingSphere = null;  // recomputed from the avatar's pose on first use
    mesh.boundingBox = null;
  }

  const nodes = original.map((o) => (o ? counterpart(o) ?? o : o));
  const attachment = new SpringBonesAttachment(avatarRoot, wearableRoot, nodes, rig, options, skinned, moved, new Set(armature.values()), unmatchedBones);
  if (options.mixer) attachment.watchAnimations(options.mixer);
  return attachment;
}

/**
 * Draws an attachment's simulated bones as line segments (joint head to tail), one colour per
 * chain. Add it to the scene after the avatar; it follows the joints every frame.
 */
export class SpringBonesHelper extends LineSegments {
  constructor(attachment) {
    const geometry = new BufferGeometry();
    super(geometry, new LineBasicMaterial({ vertexColors: true, depthTest: false, depthWrite: false, transparent: true, toneMapped: false }));
    this.type = 'SpringBonesHelper';
    this.renderOrder = 999;
    this.matrixAutoUpdate = false;
    this.frustumCulled = false;
    this.attachment = attachment;
    this.rebuild();
  }

  /** Call after attachment.setRig(): the joint list may have changed. */
  rebuild() {
    const { jointObjects, rig } = this.attachment;
    const count = jointObjects.length;
    const colors = new Float32Array(count * 6);
    const color = new Color();
    const chains = [...new Set(rig.joints.map((j) => j.chain))];
    rig.joints.forEach((j, i) => {
      color.setHSL((chains.indexOf(j.chain) * 0.17 + 0.05) % 1, 1, 0.55);
      color.toArray(colors, i * 6);
      color.toArray(colors, i * 6 + 3);
    });
    this.geometry.setAttribute('position', new BufferAttribute(new Float32Array(count * 6), 3));
    this.geometry.setAttribute('color', new BufferAttribute(colors, 3));
  }

  updateMatrixWorld(force) {
    const jointObjects = this.attachment.jointObjects;  // per frame: plain reads, nothing allocated
    const tailObjects = this.attachment.tailObjects;
    const position = this.geometry.getAttribute('position');
    const p = position.array;
    for (let i = 0; i < jointObjects.length; i++) {
      const a = jointObjects[i]?.matrixWorld.elements;
      const b = tailObjects[i]?.matrixWorld.elements;
      if (!a || !b) continue;
      p[i * 6] = a[12]; p[i * 6 + 1] = a[13]; p[i * 6 + 2] = a[14];
      p[i * 6 + 3] = b[12]; p[i * 6 + 4] = b[13]; p[i * 6 + 5] = b[14];
    }
    position.needsUpdate = true;
    super.updateMatrixWorld(force);
  }

  dispose() {
    this.geometry.dispose();
    this.material.dispose();
  }
}
