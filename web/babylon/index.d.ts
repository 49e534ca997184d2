export * from './springBoneSimulation.js';
export * from './springBonesLoaderExtension.js';
