// Types of the Babylon.js drop-in (springBoneSimulation.js). Babylon is not imported: the
// parameters are described by the few members the class uses, which Babylon 4.2's `babylonjs`
// and the current `@babylonjs/core` both have, so a consumer of either type-checks.
import type { ColliderOptions, ColliderPreset, Instance, Rig, SpringBoneEntry, SpringBones, SpringBonesData, WindOptions } from '../springbones.js';

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

/** The whole springBones with loadRig's choice of entry (and its colliders and jump thresholds). */
export type SpringBonesWithHashOptions = {
  springBones: SpringBonesData | object | null;
  colliders?: readonly ColliderOptions[] | ColliderPreset;
  hitRadius?: number;
  jumpDistance?: number;
  jumpAngle?: number;
} & (
  | { contentHash: string }
  | { entity: object | string; bodyShape: string }
  | { glb: Uint8Array | ArrayBuffer }
);

/**
 * The spring bones of every registered wearable, stepped before each render of the scene, all in
 * one scene.step of springbones: the surface of Decentraland's wearable-preview class.
 */
export class SpringBoneSimulation {
  /**
   * @param sb the springbones module, or a promise of it (wearables registered before it resolves
   *   stay at rest until it does)
   */
  constructor(sb: SpringBones | PromiseLike<SpringBones>);
  /** Resolves once the module is there and every wearable registered so far has its rig. */
  readonly ready: Promise<void>;
  /**
   * Registers a wearable's container (after addAllToScene, before its animation moves it: the
   * current pose is the rest pose). `springBonesParams`: the models entry, the whole springBones
   * (the entry under itemId) or the springBones with hash options; left out: no chains until
   * updateParams. Registering an itemId again replaces it.
   * @throws TypeError for arguments of the wrong kind; SpringBonesError for metadata the core rejects
   */
  registerWearable(
    scene: BabylonSceneLike,
    container: BabylonAssetContainerLike,
    itemId: string,
    springBonesParams?: SpringBonesModelEntry | SpringBonesData | SpringBonesWithHashOptions | null,
  ): void;
  /**
   * The Builder's live tuning: `params` becomes the wearable's models entry at once (added chains
   * start, removed ones go back to rest; the chains restart from rest).
   * @throws Error for an itemId never registered; TypeError for params that are not an object
   */
  updateParams(itemId: string, params: SpringBonesModelEntry): void;
  /** Steps every registered wearable before each render of `scene`. Idempotent. */
  start(scene: BabylonSceneLike): void;
  /** Stops, puts the joints back at rest, frees every rig and instance. */
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
   * a drag. Nothing before the module is there.
   * @throws Error for an unregistered itemId; RangeError for a joint out of range or a non-finite point
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
  /** The rig of a registered wearable; null before the module is there or after a load error. */
  rigOf(itemId: string): Rig | null;
}

/** Carries an instance across a jump of its drivers: instance.jump() where the core has it, else reset(). */
export function carryAcrossJump(instance: Instance): void;
