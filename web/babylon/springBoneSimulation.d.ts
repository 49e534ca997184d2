// Types of the Babylon.js drop-in (springBoneSimulation.js). Babylon is not imported: the
// parameters are described by the few members the class uses, which Babylon 4.2's `babylonjs`
// and the current `@babylonjs/core` both have, so a consumer of either type-checks.
import type { ColliderOptions, ColliderPreset, Instance, InstanceOptions, LoadOptions, Rig, SetCollidersOptions, SpringBoneEntry, SpringBones, SpringBonesData, Warning, WindOptions } from '../springbones.js';
import type { Diagnostic, DiagnosticCode } from '../wearable/diagnostics.js';

export type { Diagnostic, DiagnosticCode };

/** A Babylon TransformNode (or mesh), as a collider follows it: its world matrix. */
export interface BabylonTransformNodeLike {
  name: string;
  computeWorldMatrix(force?: boolean): unknown;
  getWorldMatrix(): { m: ArrayLike<number> };
}

/** A collider for simulation.setColliders: as loadRig's, its `node` a name or any TransformNode to follow. */
export interface BabylonColliderOptions extends Omit<ColliderOptions, 'node'> {
  node: string | BabylonTransformNodeLike;
}

/** A Babylon Scene, as the simulation uses it. */
export interface BabylonSceneLike {
  getEngine(): { getDeltaTime(): number };
  useRightHandedSystem: boolean;
  onBeforeRenderObservable: { add(callback: (...args: any[]) => void): unknown; remove(observer: any): boolean };
  animationGroups: readonly unknown[];
  getTransformNodeByName(name: string): unknown;
}

/** A Babylon AssetContainer (a loaded GLB), as the simulation reads it. */
export interface BabylonAssetContainerLike {
  transformNodes: readonly unknown[];
  meshes: readonly unknown[];
}

/** A models entry: node name -> parameters, as `springBones.models[hash]`. */
export type SpringBonesModelEntry = Record<string, SpringBoneEntry>;

/**
 * The whole springBones with loadRig's options, handed to loadRig as they are (the three.js
 * plugin's option object: colliders, limits, hitRadius, jump thresholds), and createInstance's
 * options under `instance`.
 */
export type SpringBonesWithHashOptions = {
  springBones: SpringBonesData | object | string | null;
  /** 'dcl-body': measured on the avatar in the scene (the skeleton with the most bones outside
   *  the wearable's container), unless `avatarBones` are given. */
  colliders?: readonly ColliderOptions[] | ColliderPreset;
  avatarBones?: LoadOptions['avatarBones'];
  hitRadius?: number;
  limits?: LoadOptions['limits'];
  jumpDistance?: number;
  jumpAngle?: number;
  instance?: InstanceOptions;
} & (
  | { contentHash: string }
  | { entity: object | string; bodyShape: string }
  | { glb: Uint8Array | ArrayBuffer }
);

/** How gravityDir is read: the standard's glTF space (default) or the Babylon scene's axes (the preview's). */
export type GravityDirSpace = 'gltf' | 'scene';

export interface SpringBoneSimulationOptions {
  /**
   * 'gltf' (default): gravityDir in the glTF's space, as three.js and every springbones runtime
   * read it; in a left-handed scene [1, 0, 0] leans toward the scene's -X. 'scene': in the
   * Babylon scene's own axes, as Decentraland's preview reads it ([1, 0, 0] leans toward +X).
   */
  gravityDirSpace?: GravityDirSpace;
}

/**
 * Why a registered wearable's hair (or part of it) stays still, or a call named no wearable: the
 * codes of docs/diagnostics.md, the same as the three.js adapter's.
 */
export type SpringBoneSimulationWarningCode = DiagnosticCode;

export interface SpringBoneSimulationWarning extends Diagnostic {
  /** The item id the warning is about (registerWearable's, or the one a call named). */
  readonly itemId: string;
}

/**
 * The spring bones of every registered wearable, stepped before each render of the scene, all in
 * one scene.step of springbones: the surface of Decentraland's wearable-preview class. None of
 * the preview's four methods throws for metadata or ids: what leaves hair still is one console
 * warning per wearable and an entry in `warnings`.
 */
export class SpringBoneSimulation {
  /**
   * @param sb the springbones module, a promise of it, or nothing (null / undefined): the
   *   simulation then starts the module itself (createSpringBones()) when the first wearable is
   *   registered (the page has that GLB by then: the module's download never shares the link with
   *   it), once per page, shared by every simulation constructed without one. Wearables stay at
   *   rest until the module is there.
   * @throws TypeError for a value that is not the module; RangeError for a bad gravityDirSpace
   */
  constructor(sb?: SpringBones | PromiseLike<SpringBones> | null, options?: SpringBoneSimulationOptions);
  /**
   * Resolves once the module is there and every wearable registered so far has its rig; rejects
   * when the module fails to load (each wearable also warns `module-failed`). Without a
   * module given, it waits for the first registerWearable, which starts the module.
   */
  readonly ready: Promise<void>;
  /** The springbones module once it is there, else null. */
  readonly springBones: SpringBones | null;
  /**
   * What leaves registered wearables' hair still, and calls that named no registered wearable,
   * each with its fix; each was also one console warning. Read anew on each access.
   */
  readonly warnings: readonly SpringBoneSimulationWarning[];
  /**
   * Registers a wearable's container (after addAllToScene, before its animation moves it: the
   * current pose is the rest pose). `itemId`: any non-empty string (the preview passes the
   * wearable's URN). `springBonesParams`: the models entry (as the preview passes it); the whole
   * springBones (its entry under itemId, else its only entry, else the warning
   * `springbones-ambiguous`); or the springBones with hash options; left out: the loader
   * extension's, else no chains until updateParams. Registering an itemId again replaces it.
   * @throws TypeError for arguments of the wrong kind (metadata the core rejects is a warning)
   */
  registerWearable(
    scene: BabylonSceneLike,
    container: BabylonAssetContainerLike,
    itemId: string,
    springBonesParams?: SpringBonesModelEntry | SpringBonesData | SpringBonesWithHashOptions | null,
  ): void;
  /**
   * The Builder's live tuning: `params` (the whole entry) becomes the wearable's models entry,
   * each name's fields merged over its previous ones. The chains keep their motion (joints that
   * stay simulated carry their state over); an added chain starts from the pose it is drawn in; a
   * removed chain goes back to rest before the next frame. An itemId not registered (or after
   * dispose) does nothing and warns once (`unknown-item`).
   * @throws TypeError for params that are not an object
   */
  updateParams(itemId: string, params: SpringBonesModelEntry): void;
  /**
   * Replaces a registered wearable's colliders (its rig's included) from the next frame on
   * (instance.setColliders): an array or 'dcl-body', null or [] for none. A collider's `node` is a
   * name (a rig driver, an avatar bone, a node of the wearable or the scene) or any TransformNode
   * (a hat, a hand, another wearable's node), whose world matrix each frame copies, in the glTF's
   * space, after the drivers'. For 'dcl-body', `scale` resizes and `omit` leaves out shapes,
   * measured on the avatar in the scene unless `avatarBones` is given. Kept across updateParams;
   * before the module is there, applied when it comes. Returns the instance's warnings, each also
   * in `warnings` with a fix; [] before the module is there. An itemId not registered does nothing
   * and warns once (`unknown-item`).
   * @throws TypeError / RangeError / SpringBonesError for a bad collider (`setColliders: ...`),
   *   before anything changes
   */
  setColliders(itemId: string, colliders: readonly BabylonColliderOptions[] | ColliderPreset | null, options?: SetCollidersOptions): readonly Warning[];
  /** Steps every registered wearable before each render of `scene`. Idempotent. */
  start(scene: BabylonSceneLike): void;
  /**
   * Stops, puts the joints back at rest, frees every rig and instance. The simulation can be
   * registered and started again afterwards. The frame hook comes off the scene start() was
   * given, whichever scene is passed.
   * @throws TypeError for a value that is not a Babylon scene (before anything changes)
   */
  dispose(scene?: BabylonSceneLike): void;
  /** Forgets the motion of every wearable (or itemId's): the next frame starts at rest. */
  reset(itemId?: string): void;
  /**
   * The springs of every wearable (or itemId's) at rest in the avatar's current pose, without
   * rendering (instance.settle): thumbnails, turntables, emote starts. Returns the most steps one
   * of them ran; 0 before the module is there.
   * @param seconds at most this long (default 2, in [0, 60]); RangeError outside
   */
  settle(itemId?: string, seconds?: number): number;
  /**
   * Holds joint `joint` (an index into rigOf(itemId).joints) toward a point of Babylon's world,
   * as far as its chain reaches, colliders still holding (instance.grab): call it every frame of
   * a drag. Nothing before the module is there; an itemId not registered warns `unknown-item`.
   * @throws TypeError for a point that is not three numbers (checked before it is mirrored);
   *   RangeError for a joint out of range or a non-finite point
   */
  grab(itemId: string, joint: number, point: { x: number; y: number; z: number } | readonly number[]): void;
  /** Lets go (every wearable, or itemId's): the hair swings back from where it is. */
  release(itemId?: string): void;
  /** The avatar moves discontinuously before the next frame (a teleport): carry the hair across. */
  jump(itemId?: string): void;
  /**
   * Wind on every wearable, those registered later too (the direction in the glTF's space, as
   * gravityDir); null for none. Kept until the module is there, checked then.
   * @throws TypeError / RangeError for a bad wind once the module is there
   */
  setWind(wind: WindOptions | null): void;
  /**
   * How much of the avatar's own motion the hair feels (instance.setInertia), in [0, 1]: 1 (the
   * default) all of it, 0 none, as in a vehicle. On every wearable, those registered later too.
   * @throws RangeError for a value outside [0, 1]
   */
  setInertia(value: number): void;
  /** The rig of a registered wearable; null before the module is there or after a load error. */
  rigOf(itemId: string): Rig | null;
}

/** Carries an instance across a jump of its drivers: instance.jump() where the core has it, else reset(). */
export function carryAcrossJump(instance: Instance): void;
