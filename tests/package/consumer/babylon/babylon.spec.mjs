// A Node project using springbones/babylon from the installed package, with the Babylon.js it
// installed: Babylon 4.2's UMD build (`babylonjs` + `babylonjs-loaders`, what Decentraland's
// preview pins) or the current @babylonjs/core + @babylonjs/loaders, chosen by SPRINGBONES_BABYLON
// ('4.2' or 'current'). The sample wearable is loaded by Babylon's glTF loader on a NullEngine,
// registered with the drop-in class (and once through the loader extension) and swings with a
// moving head.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { fileURLToPath } from 'node:url';
import { test } from 'node:test';
import { createSpringBones } from 'springbones';
import { SpringBoneSimulation, registerSpringBonesLoaderExtension, springBonesOf } from 'springbones/babylon';

const require = createRequire(import.meta.url);
const asset = (name) => new Uint8Array(readFileSync(new URL(`../assets/${name}`, import.meta.url)));
const which = process.env.SPRINGBONES_BABYLON;

async function babylon() {
  if (which === '4.2') {
    const BABYLON = require('babylonjs');
    globalThis.BABYLON = BABYLON;
    require('babylonjs-loaders');
    const load = (scene, bytes) => BABYLON.SceneLoader.LoadAssetContainerAsync(
      '', `data:base64,${Buffer.from(bytes).toString('base64')}`, scene, undefined, '.glb');
    return { BABYLON, GLTFLoader: BABYLON.GLTF2.GLTFLoader, load };
  }
  const BABYLON = await import('@babylonjs/core');
  const { GLTFLoader } = await import('@babylonjs/loaders/glTF/2.0/index.js');
  const load = (scene, bytes) => BABYLON.LoadAssetContainerAsync(bytes, scene, { pluginExtension: '.glb' });
  return { BABYLON, GLTFLoader, load };
}

test('springbones/babylon resolves to the installed package', () => {
  const entry = fileURLToPath(import.meta.resolve('springbones/babylon'));
  assert.ok(entry.endsWith('/node_modules/springbones/web/babylon/index.js'), entry);
});

test(`Babylon ${which}: the sample's hair swings under a moving head, by the drop-in class and by the loader extension`, async () => {
  const { BABYLON, GLTFLoader, load } = await babylon();
  assert.equal(BABYLON.Engine.Version.split('.')[0], which === '4.2' ? '4' : '9');
  const sb = await createSpringBones();
  const springBones = JSON.parse(new TextDecoder().decode(asset('hair_wearable.metadata.json')));
  const [hash] = Object.keys(springBones.models);
  const engine = new BABYLON.NullEngine();
  engine.getDeltaTime = () => 1000 / 60;  // the wall clock would make the test depend on the machine
  const scene = new BABYLON.Scene(engine);
  new BABYLON.FreeCamera('camera', new BABYLON.Vector3(0, 1, -3), scene);

  const simulation = new SpringBoneSimulation(createSpringBones());  // a promise of the module works too
  const plain = await load(scene, asset('hair_wearable.glb'));
  plain.addAllToScene();
  simulation.registerWearable(scene, plain, hash, springBones.models[hash]);
  registerSpringBonesLoaderExtension(GLTFLoader, { sb, springBones, contentHash: hash });
  const extended = await load(scene, asset('hair_wearable.glb'));
  extended.addAllToScene();
  assert.equal(springBonesOf(extended).rig.joints.length, 15);
  simulation.registerWearable(scene, extended, 'extended');
  simulation.start(scene);
  await simulation.ready;

  const nodes = (container, name) => container.transformNodes.find((n) => n.name === name);
  const joints = [plain, extended].map((c) => nodes(c, 'SpringBone_ponytail_2'));
  const rest = joints[0].rotationQuaternion.clone();
  let moved = 0;
  for (let f = 0; f < 60; f++) {
    for (const c of [plain, extended]) nodes(c, 'Avatar_Head').position.x = 0.15 * Math.sin(f * 0.15);
    scene.render();
    moved = Math.max(moved, Math.abs(joints[0].rotationQuaternion.w - rest.w) + Math.abs(joints[0].rotationQuaternion.z - rest.z));
    assert.ok(joints[0].rotationQuaternion.equalsWithEpsilon(joints[1].rotationQuaternion, 1e-7), 'both ways, the same rotations');
  }
  assert.ok(moved > 1e-3, `the ponytail swings (${moved})`);
  simulation.dispose(scene);
  springBonesOf(extended).rig.dispose();
});
