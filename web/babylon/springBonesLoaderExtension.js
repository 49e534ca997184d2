// A Babylon.js glTF loader extension for springbones, registered the way Babylon's own extensions
// and its VRM loaders register theirs (GLTFLoader.RegisterExtension), for pages that load
// wearables with SceneLoader rather than handing containers to the drop-in class:
//
//   registerSpringBonesLoaderExtension(BABYLON.GLTF2.GLTFLoader, { sb, springBones, entity, bodyShape });
//   const container = await BABYLON.SceneLoader.LoadAssetContainerAsync(url, '', scene);
//   const wearable = springBonesOf(container);   // { nodes, rig, warnings, error }
//   simulation.registerWearable(scene, container, itemId);   // uses the file's own node list
//
// When the loader is ready, the extension reads the file's glTF JSON (the nodes' names, hierarchy
// and rest transforms, by glTF index) and the Babylon node the loader made for each, and puts
// them on the loaded root mesh (`metadata.springBones`), which the container holds. With
// `springBones` in its options it also loads the rig (sb.loadRig on that JSON, with loadRig's
// hash options: the models are keyed by the GLB's content hash, which a loader extension never
// sees the bytes of). Per load, Babylon 5+'s loader options override the registered ones:
// `pluginOptions: { gltf: { extensionOptions: { springbones: { springBones, contentHash } } } }`.
//
// Babylon is not imported: the GLTFLoader class is passed in, so this serves Babylon 4.2's UMD
// build (BABYLON.GLTF2.GLTFLoader) and @babylonjs/loaders alike.
import { loadWearableRig } from '../wearable/rig_life.js';

export const kSpringBonesExtensionName = 'springbones';

/** The glTF node fields the core reads (the loader's node objects also carry its own state). */
const kNodeFields = ['name', 'children', 'translation', 'rotation', 'scale', 'matrix'];

/** What the extension puts on a loaded file: see springBonesOf. */
export class SpringBonesLoadedWearable {
  constructor(nodes, gltf) {
    /** The Babylon node of each glTF node index (null where the loader made none). */
    this.nodes = nodes;
    /** The file's nodes as a glTF document (no meshes, accessors or buffers): what loadRig reads. */
    this.gltf = gltf;
    /** The rig, when springBones was given; the caller disposes of it. */
    this.rig = null;
    /** loadRig's error, when it threw (the file itself loaded). */
    this.error = null;
    /** The springBones and hash options the rig was loaded with (null without springBones). */
    this.metadata = null;
  }

  /** `gltf` as JSON text, made when read. */
  get gltfText() {
    return JSON.stringify(this.gltf);
  }

  /** The rig's warnings (an empty list without a rig). */
  get warnings() {
    return this.rig ? this.rig.warnings : [];
  }
}

export class SpringBonesLoaderExtension {
  #loader; #options;

  /**
   * @param loader Babylon's GLTFLoader (the instance the factory receives)
   * @param options { sb, springBones?, entity?, bodyShape?, contentHash?, glb?, colliders?, hitRadius? }
   */
  constructor(loader, options = {}) {
    this.name = kSpringBonesExtensionName;
    this.enabled = true;
    this.#loader = loader;
    this.#options = options;
  }

  /** The loaded file's nodes (and rig) onto its root mesh, once Babylon has made the nodes. */
  onReady() {
    const loader = this.#loader;
    const gltf = loader.gltf;
    const root = loader.rootBabylonMesh;
    if (!gltf || !root) return;
    const gltfNodes = gltf.nodes ?? [];
    const nodes = gltfNodes.map((node) => node._babylonTransformNode ?? null);
    const document = {
      asset: { version: '2.0' },
      scene: gltf.scene ?? 0,
      scenes: (gltf.scenes ?? []).map((scene) => ({ nodes: scene.nodes ?? [] })),
      nodes: gltfNodes.map((node) => Object.fromEntries(kNodeFields.filter((k) => node[k] !== undefined).map((k) => [k, node[k]]))),
    };
    const wearable = new SpringBonesLoadedWearable(nodes, document);
    const options = { ...this.#options, ...(loader.parent?.extensionOptions?.[kSpringBonesExtensionName] ?? {}) };
    const { sb, springBones, ...hashOptions } = options;
    delete hashOptions.enabled;
    if (springBones !== undefined && springBones !== null) {
      wearable.metadata = { springBones, options: hashOptions };
      try {
        if (typeof sb?.loadRig !== 'function') throw new TypeError('springbones loader extension: options.sb must be the springbones module');
        wearable.rig = loadWearableRig(sb, document, springBones, hashOptions);
      } catch (error) {
        wearable.error = error;
      }
    }
    root.metadata = { ...(root.metadata ?? {}), springBones: wearable };
  }

  dispose() {
    this.#loader = null;
  }
}

/**
 * Registers the extension on Babylon's GLTFLoader class, for every glTF file loaded from now on
 * (again: the options are replaced). `options.springBones` is left out for a page that only wants
 * the node list (and gives the parameters to registerWearable).
 */
export function registerSpringBonesLoaderExtension(GLTFLoader, options = {}) {
  if (typeof GLTFLoader?.RegisterExtension !== 'function') {
    throw new TypeError('registerSpringBonesLoaderExtension: expected Babylon\'s GLTFLoader class (BABYLON.GLTF2.GLTFLoader or @babylonjs/loaders\' GLTFLoader)');
  }
  if (options === null || typeof options !== 'object') throw new TypeError('registerSpringBonesLoaderExtension: options must be an object');
  GLTFLoader.UnregisterExtension?.(kSpringBonesExtensionName);
  GLTFLoader.RegisterExtension(kSpringBonesExtensionName, (loader) => new SpringBonesLoaderExtension(loader, options));
}

/** Removes the extension from Babylon's GLTFLoader class. */
export function unregisterSpringBonesLoaderExtension(GLTFLoader) {
  return GLTFLoader.UnregisterExtension(kSpringBonesExtensionName);
}

/** What the extension put on a loaded container (or a root node), or null. */
export function springBonesOf(containerOrRoot) {
  const candidates = containerOrRoot?.meshes ?? [containerOrRoot];
  for (const node of candidates) {
    const found = node?.metadata?.springBones;
    if (found && Array.isArray(found.nodes) && typeof found.gltf === 'object') return found;
  }
  return null;
}
