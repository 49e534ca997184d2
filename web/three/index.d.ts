// Types of the package's `springbones/three` entry (index.js).
export * from './springBonesThree.js';
export * from './springBonesLoaderPlugin.js';
