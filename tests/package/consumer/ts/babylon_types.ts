// springbones/babylon's .d.ts on their own (no Babylon installed: they describe Babylon's objects
// by the members they use), checked by tsconfig.json with skipLibCheck off. babylon.ts checks them
// against the real @babylonjs/core (tsconfig.babylon.json, where Babylon's own .d.ts, which name
// WebGPU types a WebGL page does not install, are skipped).
import type { SpringBones } from 'springbones';
import {
  SpringBoneSimulation, carryAcrossJump, kSpringBonesExtensionName, registerSpringBonesLoaderExtension,
  type BabylonAssetContainerLike, type BabylonSceneLike, type SpringBonesModelEntry,
} from 'springbones/babylon';

export function register(sb: SpringBones, scene: BabylonSceneLike, container: BabylonAssetContainerLike): string {
  const simulation = new SpringBoneSimulation(sb);
  const entry: SpringBonesModelEntry = { SpringBone_a: { stiffness: 1, isRoot: true } };
  simulation.registerWearable(scene, container, 'hash', entry);
  // @ts-expect-error a models entry's parameters are numbers
  simulation.registerWearable(scene, container, 'hash', { SpringBone_a: { drag: 'much' } });
  // @ts-expect-error with hash options, springBones is required
  simulation.registerWearable(scene, container, 'hash', { contentHash: 'x' });
  registerSpringBonesLoaderExtension({ RegisterExtension: () => undefined, UnregisterExtension: () => true }, { sb });
  const instance = simulation.rigOf('hash')?.createInstance();
  if (instance) carryAcrossJump(instance);
  return kSpringBonesExtensionName;
}
