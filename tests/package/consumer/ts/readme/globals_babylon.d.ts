// What the README's Babylon.js snippets take from the page around them (Decentraland's preview):
// a scene, a loaded container, the item's URN and springBones. package.test.mjs writes each
// snippet to a module of its own and checks it with tsc --strict; Babylon itself is not installed
// here, so its objects are described by what the snippets use of them.
type BabylonSpringBones = typeof import('springbones/babylon');
type SceneLike = import('springbones/babylon').BabylonSceneLike;
type ContainerLike = import('springbones/babylon').BabylonAssetContainerLike & { addAllToScene(): void };
type SpringBonesDataOfPage = import('springbones').SpringBonesData;

declare const SpringBoneSimulation: BabylonSpringBones['SpringBoneSimulation'];
declare const scene: SceneLike;
declare const container: ContainerLike;
declare const simulation: InstanceType<BabylonSpringBones['SpringBoneSimulation']>;
declare const urn: string;
declare const itemId: string;
declare const hash: string;
declare const url: string;
declare const wearableUrl: string;
declare const springBones: SpringBonesDataOfPage;
declare const editedEntry: import('springbones/babylon').SpringBonesModelEntry;
declare const entity: { metadata: { data: { springBones: SpringBonesDataOfPage } } };
declare const sb: import('springbones').SpringBones;
declare const SceneLoader: { LoadAssetContainerAsync(url: string, file: string, scene: SceneLike): Promise<ContainerLike> };
declare const BABYLON: {
  SceneLoader: typeof SceneLoader;
  GLTF2: { GLTFLoader: import('springbones/babylon').BabylonGLTFLoaderClassLike };
};
