// The three.js entry of the installed package in Node: GLTFLoader with SpringBonesLoaderPlugin
// (no renderer needed), worn on the sample avatar.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { test } from 'node:test';
import { Scene } from 'three';
import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';
import { createSpringBones } from 'springbones';
import { SpringBonesLoaderPlugin } from 'springbones/three';

const read = (name) => readFileSync(new URL(`../assets/${name}`, import.meta.url));

test('the loader plugin puts the rig on gltf.userData.springBones and wear() drives the hair', async () => {
  const sb = await createSpringBones();
  const entity = JSON.parse(read('hair_wearable.entity.json').toString('utf8'));
  const avatar = await new GLTFLoader().parseAsync(new Uint8Array(read('avatar.glb')).buffer, '');
  const loader = new GLTFLoader();
  loader.register((parser) => new SpringBonesLoaderPlugin(parser, {
    sb, springBones: entity.metadata.data.springBones, entity, bodyShape: 'BaseFemale' }));
  const gltf = await loader.parseAsync(new Uint8Array(read('hair_wearable.glb')).buffer, '');
  const wearable = gltf.userData.springBones;
  assert.equal(wearable.rig.joints.length, 15);

  const scene = new Scene();
  scene.add(avatar.scene);
  const worn = wearable.wear(avatar.scene);
  const ponytail = worn.jointObjects[0];
  assert.equal(ponytail.parent, avatar.scene.getObjectByName('Avatar_Head'));
  const rest = ponytail.quaternion.toArray();
  avatar.scene.getObjectByName('Avatar_Head').rotation.x = 0.6;
  for (let frame = 0; frame < 30; frame++) {
    scene.updateMatrixWorld();
    worn.update(1 / 60);
  }
  const moved = Math.max(...ponytail.quaternion.toArray().map((v, k) => Math.abs(v - rest[k])));
  assert.ok(moved > 0.05, `the ponytail swings: moved by ${moved}`);
  wearable.dispose();
  assert.equal(avatar.scene.getObjectByName('SpringBone_ponytail'), undefined);
});
