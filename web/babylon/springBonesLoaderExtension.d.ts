// Types of the Babylon.js glTF loader extension (springBonesLoaderExtension.js). Babylon is not
// imported: the loader and its class are described by the members the extension uses, which
// Babylon 4.2's `babylonjs-loaders` and the current `@babylonjs/loaders` both have.
import type { ColliderOptions, ColliderPreset, Rig, SpringBones, SpringBonesData, SpringBonesError } from '../springbones.js';

export const kSpringBonesExtensionName: 'springbones';

/** Options of the extension: the module, and optionally the springBones and which entry. */
export interface SpringBonesLoaderExtensionOptions {
  /** The springbones module; needed when springBones is given. */
  sb?: SpringBones;
  /** The wearable's data.springBones; left out, only the node list is attached. */
  springBones?: SpringBonesData | object | string | null;
  contentHash?: string;
  entity?: object | string;
  bodyShape?: string;
  /** The GLB's bytes: the entry under their content hash. */
  glb?: Uint8Array | ArrayBuffer;
  colliders?: readonly ColliderOptions[] | ColliderPreset;
  hitRadius?: number;
}

/** Babylon's GLTFLoader class (BABYLON.GLTF2.GLTFLoader or @babylonjs/loaders' GLTFLoader). */
export interface BabylonGLTFLoaderClassLike {
  RegisterExtension(name: string, factory: (loader: any) => any): void;
  UnregisterExtension(name: string): boolean;
}

/** What the extension puts on the loaded root mesh's metadata.springBones. */
export class SpringBonesLoadedWearable {
  /** The Babylon node of each glTF node index (null where the loader made none). */
  readonly nodes: readonly unknown[];
  /** The file's nodes as a glTF document ({asset, scene, scenes, nodes}): what loadRig reads. */
  readonly gltf: { asset: { version: string }; nodes: object[]; [key: string]: unknown };
  /** `gltf` as JSON text, made when read. */
  readonly gltfText: string;
  /** The rig, when springBones was given and loaded; the caller disposes of it. */
  readonly rig: Rig | null;
  /** loadRig's error, when it threw (the file itself loaded). */
  readonly error: SpringBonesError | TypeError | null;
  /** The springBones and hash options the rig was loaded with; null without springBones. */
  readonly metadata: { springBones: object | string; options: Omit<SpringBonesLoaderExtensionOptions, 'sb' | 'springBones'> } | null;
  /** The rig's warnings (empty without a rig). */
  readonly warnings: Rig['warnings'];
}

/** The extension itself, as Babylon's loader drives it. */
export class SpringBonesLoaderExtension {
  constructor(loader: unknown, options?: SpringBonesLoaderExtensionOptions);
  readonly name: 'springbones';
  enabled: boolean;
  /** Puts the file's nodes (and rig) on the loaded root mesh. */
  onReady(): void;
  dispose(): void;
}

/**
 * Registers the extension for every glTF file loaded from now on (again: replaces the options).
 * Per load, Babylon 5+'s `extensionOptions: { springbones: {...} }` override them.
 * @throws TypeError for something that is not Babylon's GLTFLoader class
 */
export function registerSpringBonesLoaderExtension(GLTFLoader: BabylonGLTFLoaderClassLike, options?: SpringBonesLoaderExtensionOptions): void;
/** Removes it; true if it was registered. */
export function unregisterSpringBonesLoaderExtension(GLTFLoader: BabylonGLTFLoaderClassLike): boolean;
/** What the extension put on a loaded container (or its root mesh), or null. */
export function springBonesOf(containerOrRoot: { meshes: readonly unknown[] } | object | null | undefined): SpringBonesLoadedWearable | null;
