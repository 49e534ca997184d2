// Types of the GLTFLoader plugin (springBonesLoaderPlugin.js). `three` is a peer dependency.
import type { Object3D } from 'three';
import type { GLTF, GLTFLoaderPlugin, GLTFParser } from 'three/examples/jsm/loaders/GLTFLoader.js';
import type { InstanceOptions, LoadOptions, Rig, SpringBoneEntry, SpringBones, SpringBonesData, Warning } from '../springbones.js';
import type { AttachOptions, SpringBonesAttachment, StaticHairWarning } from './springBonesThree.js';

/**
 * sb.loadRig's options (which models entry, colliders, limits, hitRadius, ...), handed to loadRig
 * as they are, and these.
 */
export type SpringBonesLoaderPluginOptions = LoadOptions & {
  /**
   * The module from createSpringBones(), or the promise of it, not awaited: the GLB then loads
   * without waiting for the module, and the rig follows (SpringBonesWearable.ready). Left out:
   * the page's module, which the plugin starts at the first wear() (the page has its GLBs by
   * then, so the module's download never shares the link with them) and shares with every
   * plugin and Babylon simulation given none.
   */
  sb?: SpringBones | PromiseLike<SpringBones>;
  /**
   * The wearable's data.springBones ({ version, models }: parameters are numbers), or its JSON
   * text; null or left out: no spring bones.
   */
  springBones?: SpringBonesData | string | null;
  /**
   * The bytes GLTFLoader parses, when the caller has neither contentHash nor the entity: the
   * models entry is then the one under these bytes' content hash. With contentHash or
   * entity + bodyShape the rig is read from the parser's glTF JSON and the bytes are not needed.
   */
  glb?: Uint8Array | ArrayBuffer;
  /**
   * Receives each reason the wearable's spring bones stay at rest, instead of the console.
   * Default: console.warn once per code for the wearable, however many avatars wear it.
   */
  onWarning?: (warning: StaticHairWarning) => void;
  /** rig.createInstance's options for every wear() (its own `instance` option overrides them). */
  instance?: InstanceOptions;
};

/**
 * Loads a wearable's spring-bone rig with the GLB:
 * `loader.register((parser) => new SpringBonesLoaderPlugin(parser, { springBones, entity, bodyShape }))`,
 * then `gltf.userData.springBones` is a SpringBonesWearable. Every file that loader loads gets
 * one, so load the avatar with a loader without the plugin.
 */
export class SpringBonesLoaderPlugin implements GLTFLoaderPlugin {
  /**
   * @throws TypeError for a non-parser, unknown options, an sb that is not the module, or springBones without
   * contentHash, entity + bodyShape or glb (the models are keyed by the GLB's content hash)
   */
  constructor(parser: GLTFParser, options: SpringBonesLoaderPluginOptions);
  readonly name: 'springbones';
  readonly parser: GLTFParser;
  readonly options: SpringBonesLoaderPluginOptions;
  /**
   * Puts a SpringBonesWearable on gltf.userData.springBones. With the module, the rig is loaded
   * now (sb.loadRig's errors reject the load); with its promise, the rig follows and its errors
   * reject the wearable's `ready`.
   */
  afterRoot(gltf: GLTF): Promise<void>;
}

/**
 * gltf.userData.springBones, typed: the SpringBonesWearable the plugin put on this GLTFLoader
 * result, or null (loaded without the plugin). three's GLTF type declares `userData` as
 * `Record<string, any>`, and TypeScript lets a declaration merge add members to an interface but
 * not narrow one it has, so `gltf.userData.springBones` itself stays `any` (as three-vrm's
 * `userData.vrm` does): read it through this to have its type checked.
 */
export function springBonesOf(gltf: GLTF): SpringBonesWearable | null;

/** What SpringBonesLoaderPlugin puts on gltf.userData.springBones. */
export class SpringBonesWearable {
  private constructor();
  readonly gltf: GLTF;
  /**
   * The rig, owned by the wearable: dispose() frees it. Typed as loaded: with `sb` given as a
   * promise, or left out, it is null until `ready` resolves. With `colliders: 'dcl-body'` (and no
   * `avatarBones`) each wear() runs a rig measured on its avatar's bones instead (one per
   * armature, also the wearable's to dispose of): `attachment.rig`.
   */
  readonly rig: Rig;
  /**
   * The rig's warnings, then the reasons the spring bones stay at rest that the rig does not list
   * itself (`no-chain-root`, `no-chains`, `module-failed`, `rig-failed`). Each of those reasons
   * (the rig's `model-not-found` and `models-missing` too) is written to the console once per
   * wearable (see the plugin's onWarning). None before the rig loads. With `colliders:
   * 'dcl-body'` measured at wear(), the rig's `body-collider-skipped` about the GLB's own bones is
   * left out: an avatar's missing bone is in its attachment's `rig.warnings`.
   */
  readonly warnings: readonly (Warning | StaticHairWarning)[];
  /**
   * Resolves to this wearable once its rig is loaded; rejects, once, with the module's or
   * loadRig's error (also written to the console, so leaving it uncaught is no unhandled
   * rejection).
   */
  readonly ready: Promise<SpringBonesWearable>;
  /** What loading the rig failed with (sb given as a promise), else null. */
  readonly error: unknown;
  /** The attachments wear() made that dispose() has not yet disposed of. */
  readonly attachments: readonly SpringBonesAttachment[];
  /**
   * Wears a clone of gltf.scene on the avatar (gltf.scene stays a template, so one load serves
   * many avatars) and returns the attachment; call its update(dt) every frame after the avatar's
   * world matrices are current, or add it to a SpringBonesGroup. Before the rig is loaded the
   * clone is worn at rest and simulates from the first update after the rig arrives.
   */
  wear(avatarRoot: Object3D, options?: Omit<AttachOptions, 'nodes'>): SpringBonesAttachment;
  /**
   * The Builder's live tuning, as the Babylon drop-in's updateParams: `params` (node name ->
   * parameters, the whole models entry) merged over the current entry, the rig loaded again, and
   * every attachment switched to it keeping its motion.
   * @throws TypeError for params that are not an object; Error before the rig is loaded or after
   *   dispose; loadRig's errors for the edited entry (nothing changes then)
   */
  updateParams(params: { readonly [nodeName: string]: SpringBoneEntry }): void;
  /** Disposes of the attachments (taking them off their avatars) and the rig; not the geometries or materials. */
  dispose(): void;
}
