// Decentraland's wearable-preview on its own Babylon, @babylonjs/core 4.2.2 (the ES-module
// package, bundled), with the import line of its SpringBoneSimulation changed to springbones/babylon
// and nothing else: the class constructed with no argument, wearables registered under their URN
// with the models entry, the Builder's updateParams, dispose and register again on a wearable swap.
// Babylon 4.2's ES modules do not load in Node as they are, so this file is bundled with esbuild
// first (tests/package/package.test.mjs), as the preview's bundler does, and the bundle runs here
// with the springbones .wasm copied next to it (where a page serves it).
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { test } from 'node:test';
import { Engine, FreeCamera, NullEngine, Quaternion, Scene, SceneLoader, Vector3 } from '@babylonjs/core';
import '@babylonjs/loaders/glTF/2.0/index.js';
import { SpringBoneSimulation } from 'springbones/babylon';  // was: import { SpringBoneSimulation } from './springBones'

const asset = (name) => new Uint8Array(readFileSync(new URL(`../assets/${name}`, import.meta.url)));
const springBones = JSON.parse(new TextDecoder().decode(asset('hair_wearable.metadata.json')));
const entity = JSON.parse(new TextDecoder().decode(asset('hair_wearable.entity.json')));
const [hash] = Object.keys(springBones.models);
const urn = entity.metadata.id;

function previewScene() {
  const engine = new NullEngine();
  engine.getDeltaTime = () => 1000 / 60;  // the wall clock would make the test depend on the machine
  const scene = new Scene(engine);
  new FreeCamera('camera', new Vector3(0, 1, -3), scene);
  return scene;
}

async function loadWearable(scene) {
  const url = `data:base64,${Buffer.from(asset('hair_wearable.glb')).toString('base64')}`;
  const container = await SceneLoader.LoadAssetContainerAsync('', url, scene, undefined, '.glb');
  container.addAllToScene();
  const node = (name) => container.transformNodes.find((n) => n.name === name);
  return { container, node };
}

const angle = (a, b) => 2 * Math.acos(Math.min(1, Math.abs(Quaternion.Dot(a, b)) / (a.length() * b.length())));

test('the bundle runs @babylonjs/core 4.2', () => {
  assert.equal(Engine.Version.split('.').slice(0, 2).join('.'), '4.2');
});

test('the preview\'s flow with only the import line changed: the hair swings, tuning does not restart it, a swap works', async () => {
  const scene = previewScene();
  const simulation = new SpringBoneSimulation();
  const first = await loadWearable(scene);
  simulation.registerWearable(scene, first.container, urn, springBones.models[hash]);
  simulation.start(scene);
  await simulation.ready;
  const head = first.node('Avatar_Head');
  const joint = first.node('SpringBone_ponytail_2');
  const rest = joint.rotationQuaternion.clone();
  let moved = 0;
  for (let f = 0; f < 60; f++) {
    head.position.x = 0.15 * Math.sin(f * 0.15);
    scene.render();
    moved = Math.max(moved, angle(joint.rotationQuaternion, rest));
  }
  assert.ok(moved > 0.02, `the ponytail swings (${moved} rad)`);
  // The Builder's push at an emote start: the same entry. The chains go on from where they are.
  const before = joint.rotationQuaternion.clone();
  const swing = angle(before, rest);
  simulation.updateParams(urn, springBones.models[hash]);
  head.position.x = 0.15 * Math.sin(60 * 0.15);
  scene.render();
  assert.ok(angle(joint.rotationQuaternion, before) < swing, 'no restart from rest');
  simulation.updateParams('urn:not-registered', {});  // warns, never throws
  assert.deepEqual(simulation.warnings.map((w) => w.code), ['unknown-item']);
  // A wearable swap: the scene's dispose observer disposes the simulation, the next render registers again.
  simulation.dispose(scene);
  const second = await loadWearable(scene);
  simulation.registerWearable(scene, second.container, urn, springBones.models[hash]);
  simulation.start(scene);
  const again = second.node('SpringBone_ponytail_2');
  const restAgain = again.rotationQuaternion.clone();
  moved = 0;
  for (let f = 0; f < 60; f++) {
    second.node('Avatar_Head').position.x = 0.15 * Math.sin(f * 0.15);
    scene.render();
    moved = Math.max(moved, angle(again.rotationQuaternion, restAgain));
  }
  assert.ok(moved > 0.02, `after the swap too (${moved} rad)`);
  simulation.dispose(scene);
});
