// The package's `springbones/babylon` entry: the drop-in SpringBoneSimulation for Babylon.js.
export * from './springBoneSimulation.js';
