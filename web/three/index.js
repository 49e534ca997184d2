// The package's `springbones/three` entry: the three.js adapter and its GLTFLoader plugin.
export * from './springBonesThree.js';
export * from './springBonesLoaderPlugin.js';
