// The package's `springbones/babylon` entry: the drop-in SpringBoneSimulation for Babylon.js and
// the glTF loader extension.
export * from './springBoneSimulation.js';
export * from './springBonesLoaderExtension.js';
