// The module as a promise (README "three.js"): attachWearable with a rig promise, the loader
// plugin with `sb` the unawaited createSpringBones(), and a SpringBonesGroup holding an attachment
// whose rig has not arrived. The wearable is worn and drawn at once; the springs take over on the
// first frame after the rig arrives, from the pose drawn until then; a rejection surfaces once.
import assert from 'node:assert/strict';
import { describe, test } from 'node:test';
import { AnimationMixer, Scene } from 'three';
import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';
import * as SkeletonUtils from 'three/examples/jsm/utils/SkeletonUtils.js';
import { loadSampleWearable } from '../wasm/sample_wearable.mjs';
import { SpringBonesGroup, attachWearable, wearableNodes } from '../../web/three/springBonesThree.js';
import { SpringBonesLoaderPlugin } from '../../web/three/springBonesLoaderPlugin.js';

const DT = 1 / 60;
const ONE_STEP = { stepHz: 60 };

const { sb, avatarGltf, wearableGltf, wearableBytes, metadata, rig } = await loadSampleWearable();

/** A promise and the functions that settle it, for arriving "later" at a chosen frame. */
function deferred() {
  let resolve, reject;
  const promise = new Promise((res, rej) => { resolve = res; reject = rej; });
  return { promise, resolve, reject };
}

/** A walking avatar in `scene` wearing a clone of the sample wearable with `rigOrPromise`. */
function walker(scene, rigOrPromise) {
  const avatarRoot = SkeletonUtils.clone(avatarGltf.scene);
  scene.add(avatarRoot);
  const wearable = SkeletonUtils.clone(wearableGltf.scene);
  const attachment = attachWearable(avatarRoot, wearable, rigOrPromise, { nodes: wearableNodes(wearableGltf, wearable), instance: ONE_STEP });
  const mixer = new AnimationMixer(avatarRoot);
  mixer.clipAction(avatarGltf.animations.find((c) => c.name === 'walk')).play();
  return { avatarRoot, attachment, mixer };
}

function animate(scene, walkers) {
  for (const w of walkers) w.mixer.update(DT);
  scene.updateMatrixWorld();
}

/** The joints' quaternions and world positions: what a renderer would draw. */
function drawn(scene, attachment) {
  scene.updateMatrixWorld();
  return attachment.jointObjects.map((o) => [...o.quaternion.toArray(), ...o.matrixWorld.elements.slice(12, 15)]);
}

/** The sample wearable's spring-bone joints, found by name in a worn clone (before any rig). */
const springJoints = (attachment) => rig.joints.map((j) => attachment.nodes[j.node]);

describe('attachWearable with a rig promise', () => {
  test('worn and drawn at once; simulated from the first frame after the rig arrives, as if attached then (no pop)', async () => {
    const scene = new Scene();
    const later = deferred();
    const pending = walker(scene, later.promise);
    const { attachment } = pending;
    assert.equal(attachment.simulating, false);
    assert.equal(attachment.instance, null);
    assert.ok(springJoints(attachment).every((o) => o && o.parent), 'the wearable is worn: its joints are in the avatar');
    const rest = springJoints(attachment).map((o) => o.quaternion.toArray());
    for (let f = 0; f < 20; f++) {
      animate(scene, [pending]);
      attachment.update(DT);  // nothing to simulate yet: the joints stay at rest
    }
    assert.deepEqual(springJoints(attachment).map((o) => o.quaternion.toArray()), rest);

    // The rig arrives; the next frame simulates. Beside it, an avatar in the very same pose
    // wearing the item with the rig given directly at that moment.
    later.resolve(rig);
    await attachment.ready;
    assert.equal(attachment.simulating, true);
    assert.equal(attachment.rig, rig);
    const before = drawn(scene, attachment);
    const direct = walker(scene, rig);
    direct.mixer.setTime(pending.mixer.time);
    scene.updateMatrixWorld();
    assert.deepEqual(drawn(scene, direct.attachment).map((p) => p.slice(0, 4)), before.map((p) => p.slice(0, 4)),
      'the late instance starts from the pose that was drawn: the rest rotations');
    let largestFirstChange = 0;
    for (let f = 0; f < 30; f++) {
      animate(scene, [pending, direct]);
      attachment.update(DT);
      direct.attachment.update(DT);
      assert.deepEqual(Array.from(attachment.instance.rotations), Array.from(direct.attachment.instance.rotations), `frame ${f}`);
      if (f === 0) {
        const after = drawn(scene, attachment);
        largestFirstChange = Math.max(...after.map((q, j) => Math.max(...q.slice(0, 4).map((x, k) => Math.abs(x - before[j][k])))));
      }
    }
    assert.ok(largestFirstChange < 0.05, `the first simulated frame turns a joint by at most a step's worth (${largestFirstChange})`);
    assert.ok(attachment.jointObjects.some((o) => Math.abs(o.quaternion.w) < 0.9999), 'and then the springs move');
    attachment.dispose();
    direct.attachment.dispose();
  });

  test('a rejected rig: ready rejects once with the error, update keeps the drawn pose and never throws', async () => {
    const scene = new Scene();
    const later = deferred();
    const { attachment, mixer } = walker(scene, later.promise);
    const rest = springJoints(attachment).map((o) => o.quaternion.toArray());
    const failure = new Error('the module did not load');
    later.reject(failure);
    await assert.rejects(attachment.ready, (e) => e === failure);
    assert.equal(attachment.error, failure);
    for (let f = 0; f < 5; f++) {
      mixer.update(DT);
      scene.updateMatrixWorld();
      attachment.update(DT);
    }
    assert.deepEqual(springJoints(attachment).map((o) => o.quaternion.toArray()), rest);
    attachment.dispose();
  });

  test('disposed of before the rig arrives: nothing is created when it does', async () => {
    const scene = new Scene();
    const later = deferred();
    const { attachment, avatarRoot } = walker(scene, later.promise);
    const children = avatarRoot.children.length;
    attachment.dispose();
    assert.ok(avatarRoot.children.length < children, 'detached');
    later.resolve(rig);
    await attachment.ready;
    assert.equal(attachment.instance, null);
  });

  test('a SpringBonesGroup takes an attachment before its rig arrives and steps it from then on', async () => {
    const scene = new Scene();
    const later = deferred();
    const ready = walker(scene, rig);
    const pending = walker(scene, later.promise);
    const group = new SpringBonesGroup(sb);
    group.add(ready.attachment);
    group.add(pending.attachment);
    assert.deepEqual(group.attachments, [ready.attachment]);
    assert.equal(group.scene.size, 1);
    animate(scene, [ready, pending]);
    group.update(DT);
    later.resolve(rig);
    await pending.attachment.ready;
    assert.deepEqual(group.attachments, [ready.attachment, pending.attachment]);
    assert.equal(group.scene.slotOf(pending.attachment.instance), 1);
    for (let f = 0; f < 10; f++) {
      animate(scene, [ready, pending]);
      group.update(DT);
    }
    const r = pending.attachment.instance.rotations;
    pending.attachment.jointObjects.forEach((o, j) => assert.deepEqual(o.quaternion.toArray(), Array.from(r.subarray(4 * j, 4 * j + 4))));
    assert.ok(pending.attachment.jointObjects.some((o) => Math.abs(o.quaternion.w) < 0.9999), 'simulated');
    group.dispose();
    ready.attachment.dispose();
    pending.attachment.dispose();
  });

  test('attachWearable still refuses what is neither a rig nor a promise', () => {
    const scene = new Scene();
    const avatarRoot = SkeletonUtils.clone(avatarGltf.scene);
    scene.add(avatarRoot);
    assert.throws(() => attachWearable(avatarRoot, wearableGltf, {}), /rig must be a springbones rig .* or a promise of one/);
  });
});

describe('SpringBonesLoaderPlugin with sb a promise', () => {
  async function load(sbPromise, extra = {}) {
    const loader = new GLTFLoader();
    loader.register((parser) => new SpringBonesLoaderPlugin(parser, { sb: sbPromise, springBones: metadata, contentHash: rig.contentHash, ...extra }));
    return loader.parseAsync(wearableBytes.slice().buffer, '');
  }

  test('the GLB loads and wears before the module resolves; the rig follows', async () => {
    const later = deferred();
    const gltf = await load(later.promise);  // resolves although the module has not
    const wearable = gltf.userData.springBones;
    assert.equal(wearable.rig, null);
    assert.deepEqual(wearable.warnings, []);
    const scene = new Scene();
    const avatarRoot = SkeletonUtils.clone(avatarGltf.scene);
    scene.add(avatarRoot);
    const worn = wearable.wear(avatarRoot);
    assert.equal(worn.simulating, false);
    worn.update(DT);
    later.resolve(sb);
    assert.equal(await wearable.ready, wearable);
    await worn.ready;
    assert.deepEqual(wearable.rig.joints, rig.joints);
    assert.equal(worn.rig, wearable.rig);
    scene.updateMatrixWorld();
    worn.update(DT);
    wearable.dispose();
    assert.equal(wearable.rig.disposed, true);
  });

  test('a module promise that rejects, or a rig error, rejects ready (the load itself succeeds)', async () => {
    const failure = new Error('no network');
    const gltf = await load(Promise.reject(failure));
    await assert.rejects(gltf.userData.springBones.ready, (e) => e === failure);
    assert.equal(gltf.userData.springBones.error, failure);
    const bad = await load(Promise.resolve(sb), { springBones: '{ not json' });
    await assert.rejects(bad.userData.springBones.ready, { name: 'SpringBonesError' });
    const notModule = await load(Promise.resolve({}));
    await assert.rejects(notModule.userData.springBones.ready, /resolved to something other than the springbones module/);
  });

  test('disposed of before the module resolves: the rig is disposed of when it arrives', async () => {
    const later = deferred();
    const wearable = (await load(later.promise)).userData.springBones;
    wearable.dispose();
    later.resolve(sb);
    await wearable.ready;
    assert.equal(wearable.rig, null);
  });
});
