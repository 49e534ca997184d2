// What the README's three.js and JavaScript-API snippets take from the page around them: the
// page's own objects, typed as a three.js page has them. package.test.mjs writes each snippet to a
// module of its own (a snippet's own declarations shadow these) and checks it with tsc --strict.
type SpringBonesData = import('springbones').SpringBonesData;
type SpringBones = import('springbones').SpringBones;
type CatalystEntity = { metadata: { id: string; data: { springBones: SpringBonesData } } };

declare const entity: CatalystEntity;
declare const avatarUrl: string;
declare const wearableUrl: string;
declare const scene: import('three').Scene;
declare const renderer: import('three').WebGLRenderer;
declare const camera: import('three').PerspectiveCamera;
declare const timer: { update(): { getDelta(): number } };
declare const loader: import('three/examples/jsm/loaders/GLTFLoader.js').GLTFLoader;
declare const avatar: import('three/examples/jsm/loaders/GLTFLoader.js').GLTF;
declare const avatarGlb: Uint8Array<ArrayBuffer>;
declare const itemGlb: Uint8Array<ArrayBuffer>;
declare const itemMetadata: { data: { springBones: SpringBonesData } };
declare const glbBytes: Uint8Array;
declare const driverWorldMatrices: Float32Array;
declare const dt: number;
declare const sb: SpringBones;
declare const attachments: readonly import('springbones/three').SpringBonesAttachment[];
declare const mixers: readonly import('three').AnimationMixer[];
declare const AnimationMixer: typeof import('three').AnimationMixer;
declare function showError(error: unknown): void;
declare const worn: import('springbones/three').SpringBonesAttachment;
declare const hatGltf: import('three/examples/jsm/loaders/GLTFLoader.js').GLTF;
