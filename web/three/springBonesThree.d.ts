// Types of the three.js adapter (springBonesThree.js). `three` is a peer dependency.
import type { AnimationMixer, LineSegments, Object3D, SkinnedMesh } from 'three';
import type { GLTF } from 'three/examples/jsm/loaders/GLTFLoader.js';
import type { ColliderOptions, ColliderPreset, Instance, InstanceOptions, Rig, Scene, SetCollidersOptions, SpringBones, Warning } from '../springbones.js';
import type { Diagnostic, DiagnosticCode } from '../wearable/diagnostics.js';

export type { Diagnostic, DiagnosticCode };

/** A collider for attachment.setColliders: as loadRig's, its `node` a name or any Object3D to follow. */
export interface ThreeColliderOptions extends Omit<ColliderOptions, 'node'> {
  node: string | Object3D;
}

/**
 * The avatar's armature by glTF node name: every bone of its skinned meshes and their ancestors
 * below `avatarRoot` (e.g. `Armature`). Computed on first use and cached per root, so bones that
 * attached wearables add are never matched by later wearables.
 */
export function avatarArmature(avatarRoot: Object3D): Map<string, Object3D>;

/**
 * The avatar's bones with their rest world matrices, as loadRig's `avatarBones` (glTF node name ->
 * 16 numbers, column-major): the inverse of each joint's inverse bind matrix in the avatar's
 * skinned meshes, so the rest pose whatever the avatar plays, in the avatar file's own space.
 * Null for an avatar without skins. Read with avatarArmature and cached per root. The plugin's
 * wear() passes them itself with `colliders: 'dcl-body'`.
 * @throws TypeError when avatarRoot is not an Object3D
 */
export function avatarRestBones(avatarRoot: Object3D): Record<string, number[]> | null;

/**
 * The Object3D of every glTF node of a loaded GLB, indexed like its `nodes` array (the indices in
 * rig.joints[].node and rig.drivers[].node). Pass `root`, a SkeletonUtils.clone of gltf.scene, to
 * get the clone's objects instead.
 * @throws TypeError without gltf.parser; Error when root is not shaped like gltf.scene
 */
export function wearableNodes(gltf: GLTF, root?: Object3D): Array<Object3D | undefined>;

export interface AttachOptions {
  /** glTF node index -> Object3D of the wearable being attached (see wearableNodes). Required
   *  when `wearable` is an Object3D (a clone) rather than the GLTFLoader result. */
  nodes?: Array<Object3D | undefined>;
  /** Options of rig.createInstance (stepHz, maxSubsteps, jumpDistance, ...). */
  instance?: InstanceOptions;
  /** The avatar's AnimationMixer: an action starting is a jump (attachment.watchAnimations). */
  mixer?: AnimationMixer;
  /**
   * Receives each reason the spring bones stay at rest (a StaticHairWarning), instead of the
   * console. Default: console.warn once per code for this attachment (once per wearable for the
   * attachments a SpringBonesWearable's wear() makes).
   */
  onWarning?: (warning: StaticHairWarning) => void;
}

/**
 * Why a worn wearable's spring bones stay at rest (docs/diagnostics.md: every code, its message
 * and fix, the same in the Babylon drop-in): each is written to the console once (see
 * AttachOptions.onWarning) and listed in the attachment's and the loaded wearable's `warnings`.
 */
export type StaticHairWarning = Diagnostic;

/** A joint or driver of the rig without a three.js object: skipped, the others simulate. */
export type NodeNotFoundWarning = Diagnostic & { readonly code: 'node-not-found' };

export type AttachWarning = NodeNotFoundWarning | StaticHairWarning;

/** Whether `value` is a promise (any thenable) rather than the thing itself. */
export function isThenable(value: unknown): value is PromiseLike<unknown>;

/**
 * A wearable worn by an avatar and simulated by one springbones instance. Made with a rig promise,
 * it is worn (and can be drawn) at once and simulates from the first update after the rig
 * arrives; until then rig and instance are null and update() does nothing.
 */
export class SpringBonesAttachment {
  private constructor();
  readonly avatarRoot: Object3D;
  readonly wearableRoot: Object3D;
  /** glTF node index -> object after matching (an avatar bone where the names match). */
  readonly nodes: ReadonlyArray<Object3D | undefined>;
  /** The wearable's skinned meshes, re-bound to the avatar's bones and moved into the avatar. */
  readonly meshes: readonly SkinnedMesh[];
  /**
   * Nodes without an object, and every reason the spring bones stay at rest (StaticHairWarning);
   * rebuilt by setRig. An attachment whose rig promise rejected lists `module-failed` or
   * `rig-failed`.
   */
  readonly warnings: readonly AttachWarning[];
  /**
   * The rig. Typed for the attachment that simulates: made with a rig promise, it is null until
   * `ready` resolves (check `simulating`).
   */
  readonly rig: Rig;
  /** The instance; null, like rig, until `ready` resolves for an attachment made with a promise. */
  readonly instance: Instance;
  /** Whether update() simulates (false while the rig promise is pending or after it rejected). */
  readonly simulating: boolean;
  /**
   * Resolves to this attachment once it simulates (at once for a rig given directly); rejects,
   * once, with what the rig promise rejected with. update() never throws that error. The failure
   * is also written to the console (a StaticHairWarning), so an application that does not catch
   * `ready` gets a warning, never an unhandled rejection.
   */
  readonly ready: Promise<SpringBonesAttachment>;
  /** What the rig promise rejected with (or setting the arrived rig threw), else null. */
  readonly error: unknown;
  /** Per rig.joints entry: the object whose quaternion is written (null if not found). */
  readonly jointObjects: ReadonlyArray<Object3D | null>;
  /** Per rig.joints entry: the joint's tail object (for drawing). */
  readonly tailObjects: ReadonlyArray<Object3D | null>;
  /** Per rig.drivers entry: the object whose matrixWorld is read (null if not found). */
  readonly driverObjects: ReadonlyArray<Object3D | null>;

  /**
   * One frame of dt seconds. Call after animating and updating world matrices
   * (avatarRoot.updateMatrixWorld() or the scene's); reads each driver's matrixWorld, steps, and
   * writes each joint's quaternion fields (_x, _y, _z, _w: no onChange, so `.rotation` is not
   * kept in sync; see syncEulers). The joints' matrix and matrixWorld are refreshed by the next
   * updateMatrixWorld (the renderer's). Allocation-free. An attachment in a SpringBonesGroup is
   * stepped by group.update(); calling this as well would step it twice. Before a rig promise
   * resolves it does nothing: the joints keep the pose drawn at rest, and the first step after
   * the rig arrives starts from that pose under the frame's drivers.
   */
  update(dt: number): void;
  /**
   * The first part of update(): drivers' matrixWorld into the instance (a driver without an object
   * is skipped: its matrix in instance.driverMatrices is kept).
   * @throws SpringBonesError 'disposed' once the instance is disposed of
   */
  readDrivers(): void;
  /**
   * The last part of update(): the instance's rotations into the joints' quaternions (fields).
   * @throws SpringBonesError 'disposed' once the instance is disposed of
   */
  writeRotations(): void;
  /**
   * Brings the joints' `.rotation` (Euler) in step with their quaternions, for code that reads
   * `.rotation` of a simulated joint; rendering, skinning, clone() and glTF export use the
   * quaternion. dispose() does it too. Allocation-free.
   */
  syncEulers(): void;
  /** Forgets the motion (avatar swap); nothing before the rig arrives. A teleport is a jump (instance.jump()). */
  reset(): void;
  /**
   * The springs at rest in the avatar's current pose, without rendering (instance.settle): reads
   * the drivers' matrixWorld (update world matrices first), settles, writes the joints. Returns
   * the steps it ran; 0 before the rig arrives.
   * @param seconds at most this long (default 2, in [0, 60])
   */
  settle(seconds?: number): number;
  /**
   * Every action of `mixer` that becomes active is announced to the instance as a jump
   * (instance.jump()) on the next update, so an animation start carries the chains instead of
   * whipping them. null stops watching. Allocation-free per frame.
   */
  watchAnimations(mixer: AnimationMixer | null): void;
  /**
   * Switches to another rig of the same GLB (edited metadata): a new instance takes the current
   * one's motion over (instance.carryFrom: joints both rigs simulate keep swinging; `carry:
   * false` starts from rest instead), joints the new rig does not simulate go back to their rest
   * rotation. The rig stays the caller's to dispose of.
   * @throws TypeError for a non-rig, or rig.createInstance's errors; nothing changes then
   */
  setRig(rig: Rig, options?: { carry?: boolean }): void;
  /**
   * Replaces the instance's colliders (the rig's included) from the next update() on
   * (instance.setColliders): an array or 'dcl-body', null or [] for none. A collider's `node` is a
   * name (a rig driver, an avatar bone, a node of the wearable or the scene) or any Object3D (a
   * hat, a hand, another wearable's node), whose matrixWorld each update() copies after the
   * drivers'. For 'dcl-body', `scale` resizes and `omit` leaves out shapes, measured on the
   * avatar's bones unless `avatarBones` is given. Kept across setRig; before a promised rig
   * arrives, applied when it does. Returns the instance's warnings, each also reported with a fix
   * (docs/diagnostics.md); [] before the rig arrives.
   * @throws TypeError / RangeError / SpringBonesError for a bad collider (`setColliders: ...`),
   *   before anything changes
   */
  setColliders(colliders: readonly ThreeColliderOptions[] | ColliderPreset | null, options?: SetCollidersOptions): readonly Warning[];
  /**
   * Disposes of the instance (update() then throws SpringBonesError 'disposed'); with detach
   * (default true) also takes the wearable's objects off the avatar, restores the joints' rest
   * rotations and frees the re-bound skeletons' bone textures. Does not dispose of the rig,
   * geometries or materials.
   */
  dispose(options?: { detach?: boolean }): void;
}

/**
 * Wears `wearable` on the avatar: wearable nodes named like a node of the avatar's armature are
 * that avatar node; the others (spring bones, meshes) move, with their local transforms, under the
 * avatar counterpart of their nearest matched ancestor; skinned meshes are re-bound to the avatar
 * bones of the same names with the wearable's inverse bind matrices. Creates the rig's instance.
 * A wearable's objects can be worn once: for several avatars, attach SkeletonUtils clones.
 * `rig` may be a promise of the rig (e.g. `sbPromise.then((sb) => sb.loadRig(...))`): the wearable
 * is worn now and simulated from the first update after it resolves (see SpringBonesAttachment).
 * @throws TypeError for arguments of the wrong kind (an onWarning that is not a function too)
 */
export function attachWearable(
  avatarRoot: Object3D,
  wearable: GLTF | Object3D,
  rig: Rig | PromiseLike<Rig>,
  options?: AttachOptions,
): SpringBonesAttachment;

/**
 * Many attachments stepped with one call into WebAssembly: update(dt) reads every attachment's
 * drivers, runs one springbones scene.step for all of their instances (the scene's distance budget
 * applies, with each avatar root's world position) and writes the rotations of every attachment
 * that step simulated.
 */
export class SpringBonesGroup {
  /**
   * @param springBones the module from createSpringBones(); the group creates and owns a scene
   * @throws TypeError for anything else
   */
  constructor(springBones: SpringBones);
  /** The group's springbones scene: setBudget(), isActive(), positions. */
  readonly scene: Scene;
  /** The attachments in the scene's slot order (setRig moves an attachment to the end). */
  readonly attachments: readonly SpringBonesAttachment[];
  /**
   * Adds an attachment; adding it again does nothing. An attachment whose rig promise is pending
   * joins the scene (and `attachments`, at the end) when its rig arrives.
   * @throws TypeError for a non-attachment or another module's; Error when it is in another
   * group; SpringBonesError 'disposed' for a disposed attachment
   */
  add(attachment: SpringBonesAttachment): void;
  /** Takes an attachment out (it can update() on its own again). Not in the group: nothing. */
  remove(attachment: SpringBonesAttachment): void;
  /**
   * One frame of dt seconds for every attachment; call after updating world matrices, as for
   * attachment.update(). Allocation-free. Equals readDrivers(), scene.step(dt), writeRotations().
   */
  update(dt: number): void;
  /**
   * The first part of update(): every attachment's drivers into its instance, and each avatar
   * root's world position into scene.positions (for the budget).
   * @throws SpringBonesError 'disposed' after dispose(), or when an attachment's instance is
   */
  readDrivers(): void;
  /**
   * The last part of update(): the rotations of every attachment the last step simulated into its
   * joints' quaternions. Attachments the budget held (scene.active 0) are skipped: their joints
   * keep the pose written when they last stepped, the pose their instance holds (unless other
   * code, e.g. an animation mixer, writes those joints meanwhile).
   * @throws SpringBonesError 'disposed' when an attachment's instance is disposed of
   */
  writeRotations(): void;
  /**
   * attachment.settle(seconds) for every attachment in the group (update world matrices first);
   * returns the most steps one of them ran.
   */
  settle(seconds?: number): number;
  /** Frees the scene; the attachments are not disposed of and can update() on their own. */
  dispose(): void;
}

/** The simulated bones of an attachment as coloured line segments (one colour per chain). */
export class SpringBonesHelper extends LineSegments {
  constructor(attachment: SpringBonesAttachment);
  readonly attachment: SpringBonesAttachment;
  /** Call after attachment.setRig(): the joint list may have changed. */
  rebuild(): void;
  dispose(): void;
}
