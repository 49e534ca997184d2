// The GLTFLoader plugin (web/three/springBonesLoaderPlugin.js) in Node: the rig arrives on
// gltf.userData.springBones with each way of naming the models entry, wear() attaches clones that
// the rig drives, and bad options or metadata fail the load with the API's errors.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { before, describe, test } from 'node:test';
import { Scene } from 'three';
import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';
import * as SkeletonUtils from 'three/examples/jsm/utils/SkeletonUtils.js';
import { loadSampleWearable } from '../wasm/sample_wearable.mjs';
import { SpringBonesError } from '../../web/springbones.js';
import { SpringBonesLoaderPlugin, SpringBonesWearable, springBonesOf } from '../../web/three/index.js';

const assets = new URL('../../web/demo/assets/', import.meta.url);
const entity = JSON.parse(readFileSync(new URL('hair_wearable.entity.json', assets), 'utf8'));
const bodyShape = 'urn:decentraland:off-chain:base-avatars:BaseMale';

let sb;
let avatarGltf;
let wearableBytes;
let metadata;
let rig;  // loaded from the bytes with sb.loadRig, for comparison

before(async () => {
  ({ sb, avatarGltf, wearableBytes, metadata, rig } = await loadSampleWearable());
});

/** Parses the sample wearable with the plugin registered with these options. */
async function loadWithPlugin(options) {
  const loader = new GLTFLoader();
  loader.register((parser) => new SpringBonesLoaderPlugin(parser, { sb, ...options }));
  return loader.parseAsync(wearableBytes.slice().buffer, '');
}

describe('SpringBonesLoaderPlugin', () => {
  test('the bytes, the content hash or the entity give the rig sb.loadRig gives', async () => {
    const hash = rig.contentHash;
    for (const options of [
      { springBones: metadata, glb: wearableBytes },
      { springBones: metadata, contentHash: hash },
      { springBones: entity.metadata.data.springBones, entity, bodyShape },
    ]) {
      const gltf = await loadWithPlugin(options);
      const wearable = gltf.userData.springBones;
      assert.ok(wearable instanceof SpringBonesWearable);
      assert.equal(wearable.rig.contentHash, hash);
      assert.equal(wearable.rig.joints.length, 15);
      assert.deepEqual(wearable.rig.joints, rig.joints);
      assert.deepEqual(wearable.rig.drivers, rig.drivers);
      assert.deepEqual(wearable.warnings, []);
      wearable.dispose();
      assert.equal(wearable.rig.disposed, true);
    }
  });

  test("colliders: 'dcl-body' passes through to loadRig; the GLB's missing bones are no warning (wear() measures on the avatar)", async () => {
    const gltf = await loadWithPlugin({ springBones: metadata, glb: wearableBytes, colliders: 'dcl-body', hitRadius: 0.01 });
    const wearable = gltf.userData.springBones;
    const direct = sb.loadRig(wearableBytes, metadata, { colliders: 'dcl-body', hitRadius: 0.01 });
    assert.equal(wearable.rig.colliders.length, 4);
    assert.deepEqual(wearable.rig.colliders, direct.colliders);
    assert.deepEqual(wearable.rig.warnings.map((w) => w.code), ['body-collider-skipped']);
    assert.deepEqual(wearable.warnings, []);  // tests/adapters/three_avatar_bones.test.mjs wears it
    direct.dispose();
    wearable.dispose();
  });

  test('springBonesOf(gltf) is gltf.userData.springBones, or null for a file loaded without the plugin', async () => {
    const gltf = await loadWithPlugin({ springBones: metadata, contentHash: 'bafkreianothermodel' });
    assert.ok(springBonesOf(gltf) instanceof SpringBonesWearable);
    assert.equal(springBonesOf(gltf), gltf.userData.springBones);
    const plain = await new GLTFLoader().parseAsync(new Uint8Array(readFileSync(new URL('../../web/demo/assets/hair_wearable.glb', import.meta.url))).buffer, '');
    assert.equal(springBonesOf(plain), null);
    assert.equal(springBonesOf({ userData: { springBones: { wear: () => null } } }), null, 'only the plugin\'s wearable');
    gltf.userData.springBones.dispose();
  });

  test('another GLB\'s hash loads no chains, with the rig\'s model-not-found warning', async () => {
    const gltf = await loadWithPlugin({ springBones: metadata, contentHash: 'bafkreianothermodel' });
    const wearable = gltf.userData.springBones;
    assert.equal(wearable.rig.joints.length, 0);
    assert.deepEqual(wearable.warnings.map((w) => w.code), ['model-not-found']);
    wearable.dispose();
  });

  test('springBones without a way to its models entry is a TypeError that fails the load', async () => {
    await assert.rejects(loadWithPlugin({ springBones: metadata }), (error) =>
      error instanceof TypeError && /contentHash, entity \+ bodyShape, or glb/.test(error.message));
    await assert.rejects(loadWithPlugin({ springBones: metadata, glb: wearableBytes, stepHz: 30 }),
        (error) => error instanceof TypeError && /unknown option 'stepHz'/.test(error.message));
    await assert.rejects(loadWithPlugin({ sb: 42, springBones: metadata, glb: wearableBytes }), /options.sb must be the springbones module/);
  });

  test('without sb, the page\'s module starts at the first wear(), not before, and drives the clone', async () => {
    const loader = new GLTFLoader();
    loader.register((parser) => new SpringBonesLoaderPlugin(parser, { springBones: entity.metadata.data.springBones, entity, bodyShape }));
    const wearable = (await loader.parseAsync(wearableBytes.slice().buffer, '')).userData.springBones;
    let settled = false;
    wearable.ready.then(() => { settled = true; }, () => { settled = true; });
    // Nothing has asked for the module yet: however long the page waits, no rig comes.
    for (let i = 0; i < 20; i++) await new Promise((resolve) => setImmediate(resolve));
    assert.equal(settled, false, 'no module before the first wear()');
    assert.equal(wearable.rig, null);
    const avatar = SkeletonUtils.clone(avatarGltf.scene);
    const attachment = wearable.wear(avatar);
    await wearable.ready;
    assert.deepEqual(wearable.rig.joints, rig.joints);
    await attachment.ready;
    assert.equal(attachment.simulating, true);
    const joint = attachment.jointObjects[0];
    const before = joint.quaternion.clone();
    avatar.getObjectByName('Avatar_Head').rotation.z = 0.8;
    for (let frame = 0; frame < 30; frame++) {
      avatar.updateMatrixWorld(true);
      attachment.update(1 / 60);
    }
    assert.ok(joint.quaternion.angleTo(before) > 0.05, `the turned head's ponytail moved by ${joint.quaternion.angleTo(before)}`);
    wearable.dispose();
  });

  test('broken metadata fails the load with the API\'s SpringBonesError', async () => {
    await assert.rejects(loadWithPlugin({ springBones: '{"version": 1, "models": ', glb: wearableBytes }),
        (error) => error instanceof SpringBonesError && error.code === 'metadata-bad-json');
  });

  test('wear() attaches a clone that the rig drives; dispose() takes every clone off', async () => {
    const gltf = await loadWithPlugin({ springBones: metadata, glb: wearableBytes });
    const wearable = gltf.userData.springBones;
    const scene = new Scene();
    const avatars = [SkeletonUtils.clone(avatarGltf.scene), SkeletonUtils.clone(avatarGltf.scene)];
    scene.add(...avatars);
    const worn = avatars.map((avatar) => wearable.wear(avatar));
    assert.deepEqual(wearable.attachments, worn);
    assert.notEqual(worn[0].jointObjects[0], worn[1].jointObjects[0], 'each avatar wears its own clone');
    assert.equal(worn[0].jointObjects[0].parent, avatars[0].getObjectByName('Avatar_Head'));
    assert.equal(gltf.scene.getObjectByName('SpringBone_ponytail').parent.name, 'Avatar_Head',
        'gltf.scene stays whole, a template for the next wear()');
    assert.notEqual(gltf.scene.getObjectByName('SpringBone_ponytail'), worn[0].jointObjects[0]);

    // Turn the first avatar's head: both ponytails swing (gravity), but apart: each clone has its
    // own instance, driven by its own avatar.
    const rest = worn[0].jointObjects[0].quaternion.toArray();
    avatars[0].getObjectByName('Avatar_Head').rotation.z = 0.8;
    for (let frame = 0; frame < 30; frame++) {
      scene.updateMatrixWorld();
      for (const w of worn) w.update(1 / 60);
    }
    const [turned, still] = worn.map((w) => w.jointObjects[0].quaternion.toArray());
    const apart = (a, b) => Math.max(...a.map((v, k) => Math.abs(v - b[k])));
    assert.ok(apart(turned, rest) > 0.05, `the turned head's ponytail moved by ${apart(turned, rest)}`);
    assert.ok(apart(turned, still) > 0.05, `the two ponytails differ by ${apart(turned, still)}`);

    wearable.dispose();
    assert.deepEqual(wearable.attachments, []);
    for (const avatar of avatars) assert.equal(avatar.getObjectByName('SpringBone_ponytail'), undefined);
    assert.equal(worn[0].instance.disposed, true);
    assert.equal(wearable.rig.disposed, true);
  });
});
