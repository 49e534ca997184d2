// A TypeScript consumer of springbones/babylon with the current @babylonjs/core, checked with
// tsc --noEmit --strict (tsconfig.babylon.json; Babylon's own .d.ts skipped: they name WebGPU types
// a WebGL page does not install). The expected errors fail the check if the types ever let those
// mistakes through (or are missing: an `any` accepts everything).
import { AssetContainer, LoadAssetContainerAsync, Scene } from '@babylonjs/core';
import { GLTFLoader } from '@babylonjs/loaders/glTF/2.0/index.js';
import { createSpringBones, type Rig } from 'springbones';
import {
  SpringBoneSimulation, registerSpringBonesLoaderExtension, springBonesOf, type SpringBonesLoadedWearable,
} from 'springbones/babylon';

export async function preview(scene: Scene, url: string, entity: object, itemHash: string): Promise<void> {
  const simulation = new SpringBoneSimulation(createSpringBones());
  const sb = await createSpringBones();
  registerSpringBonesLoaderExtension(GLTFLoader, { sb, springBones: null });
  const container: AssetContainer = await LoadAssetContainerAsync(url, scene);
  container.addAllToScene();
  const loaded: SpringBonesLoadedWearable | null = springBonesOf(container);
  simulation.registerWearable(scene, container, itemHash, { SpringBone_hair: { stiffness: 1, isRoot: true } });
  simulation.registerWearable(scene, container, 'b', { springBones: { version: 1, models: {} }, entity, bodyShape: 'BaseMale' });
  simulation.updateParams(itemHash, { SpringBone_hair: { drag: 0.4, gravityDir: [1, 0, 0] } });
  simulation.start(scene);
  await simulation.ready;
  const rig: Rig | null = simulation.rigOf(itemHash);
  simulation.jump();
  simulation.reset(itemHash);
  console.log(loaded?.gltfText.length, rig?.joints.length);
  simulation.dispose(scene);

  // @ts-expect-error itemId is a string
  simulation.updateParams(3, {});
  // @ts-expect-error a parameter is a number, not a string
  simulation.updateParams(itemHash, { SpringBone_hair: { stiffness: 'stiff' } });
  // The preview's own call: no module (the class starts it), and what it says when hair stays still.
  const dropIn = new SpringBoneSimulation();
  const codes: string[] = dropIn.warnings.map((w) => `${w.code} ${w.itemId}: ${w.message}`);
  console.log(codes, new SpringBoneSimulation(null, { gravityDirSpace: 'scene' }).springBones);
  // @ts-expect-error gravityDirSpace is 'gltf' or 'scene'
  new SpringBoneSimulation(null, { gravityDirSpace: 'babylon' });
}
