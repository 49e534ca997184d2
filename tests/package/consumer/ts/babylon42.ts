// Decentraland's wearable-preview as it type-checks against its own Babylon, @babylonjs/core
// 4.2.2 (the ES-module package) and TypeScript 5, with springbones/babylon in place of its
// SpringBoneSimulation: tsc --noEmit --strict (tsconfig.babylon42.json; Babylon's own .d.ts
// skipped, as the preview's build does). The calls are the preview's; the expected errors fail the
// check if the types ever let those mistakes through.
import { AssetContainer, Scene, SceneLoader } from '@babylonjs/core';
import { SpringBoneSimulation, type SpringBoneSimulationWarning } from 'springbones/babylon';

type SpringBoneParams = Record<string, { stiffness?: number; gravityPower?: number; gravityDir?: [number, number, number]; drag?: number; center?: string; isRoot?: boolean }>;

export async function render(scene: Scene, url: string, urn: string, params: SpringBoneParams | undefined): Promise<void> {
  const simulation = new SpringBoneSimulation();
  const container: AssetContainer = await SceneLoader.LoadAssetContainerAsync(url, '', scene);
  container.addAllToScene();
  simulation.registerWearable(scene, container, urn, params);
  simulation.start(scene);
  simulation.updateParams(urn, { SpringBone_hair: { stiffness: 1.5, isRoot: true } });
  // Colliders at run time on a TransformNode of this Babylon (a hat), and the body's shapes resized.
  simulation.setColliders(urn, [{ node: container.transformNodes[0], radius: 0.1 }]);
  simulation.setColliders(urn, 'dcl-body', { scale: 0.5 });
  scene.onDisposeObservable.addOnce(() => simulation.dispose(scene));
  const warnings: readonly SpringBoneSimulationWarning[] = simulation.warnings;
  console.log(warnings.map((w) => w.code));

  // @ts-expect-error the item id is a string (the wearable's URN)
  simulation.registerWearable(scene, container, 3, params);
  // @ts-expect-error a collider's node is a name or a TransformNode
  simulation.setColliders(urn, [{ node: 3, radius: 0.1 }]);
  // @ts-expect-error a parameter is a number, not a string
  simulation.updateParams(urn, { SpringBone_hair: { stiffness: 'stiff' } });
}
