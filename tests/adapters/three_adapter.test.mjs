// The three.js adapter (web/three/springBonesThree.js) in Node: three.js without a renderer, the
// WebAssembly module through the public JS API, the demo's sample avatar and hair wearable.
import assert from 'node:assert/strict';
import { describe, test } from 'node:test';
import { AnimationMixer, Group, Matrix4, Quaternion, Scene, Vector3 } from 'three';
import * as SkeletonUtils from 'three/examples/jsm/utils/SkeletonUtils.js';
import { loadSampleWearable } from '../wasm/sample_wearable.mjs';
import { SpringBonesHelper, attachWearable, avatarArmature, wearableNodes } from '../../web/three/springBonesThree.js';


const { sb, avatarGltf, wearableGltf, wearableBytes, metadata, rig } = await loadSampleWearable();

/** A fresh avatar in a scene, wearing a fresh clone of the sample wearable. */
function wornSample({ scene = new Scene(), avatar = null } = {}) {
  const avatarRoot = avatar ?? SkeletonUtils.clone(avatarGltf.scene);
  if (!avatarRoot.parent) scene.add(avatarRoot);
  const wearable = SkeletonUtils.clone(wearableGltf.scene);
  const attachment = attachWearable(avatarRoot, wearable, rig, { nodes: wearableNodes(wearableGltf, wearable) });
  scene.updateMatrixWorld();
  return { scene, avatarRoot, wearable, attachment };
}

const byName = (object, name) => object.getObjectByName(name);
const maxAbsDiff = (a, b) => a.reduce((m, v, i) => Math.max(m, Math.abs(v - b[i])), 0);

describe('attachWearable', () => {
  test('re-binds the wearable meshes to the avatar bones of the same name', () => {
    const { avatarRoot, attachment } = wornSample();
    const head = byName(avatarRoot, 'Avatar_Head');
    assert.equal(attachment.meshes.length, 2);  // hair, earrings
    for (const mesh of attachment.meshes) {
      assert.equal(mesh.parent, avatarRoot, 'the mesh now lives in the avatar');
      const bones = mesh.skeleton.bones;
      assert.equal(bones.find((b) => b.name === 'Avatar_Head'), head);
      assert.equal(bones.find((b) => b.name === 'Avatar_Hips'), byName(avatarRoot, 'Avatar_Hips'));
      for (const bone of bones) {
        // every bone is part of the avatar's hierarchy now
        let o = bone;
        while (o && o !== avatarRoot) o = o.parent;
        assert.equal(o, avatarRoot, `${bone.name} is under the avatar`);
      }
    }
  });

  test('adds the spring bones under the matching avatar bone with their local transform', () => {
    const { avatarRoot, wearable, attachment } = wornSample();
    const head = byName(avatarRoot, 'Avatar_Head');
    const ponytail = attachment.jointObjects[0];
    assert.equal(ponytail.name, 'SpringBone_ponytail');
    assert.equal(ponytail.parent, head);
    assert.deepEqual(ponytail.position.toArray(), [0, 17, -9], 'centimetres in the head frame, as in the GLB');
    // world position: the head at 1.6 m, the root 17 cm above it and 9 cm behind
    const p = ponytail.getWorldPosition(new Vector3());
    assert.ok(p.distanceTo(new Vector3(0, 1.77, -0.09)) < 1e-5, `ponytail root at ${p.toArray()}`);
    // the wearable's own armature copy is left behind, out of the avatar
    assert.ok(byName(wearable, 'Avatar_Head'), 'the wearable keeps its Avatar_Head copy');
    assert.equal(attachment.driverObjects.map((o) => o.name).join(), 'Avatar_Head,Avatar_Hips');
    assert.equal(attachment.driverObjects[0], head, 'drivers are the avatar bones');
    assert.deepEqual(attachment.warnings, []);
  });

  test('the skinned hair follows the avatar head', () => {
    const { scene, avatarRoot, attachment } = wornSample();
    const hair = attachment.meshes.find((m) => m.name === 'Hair');
    const before = hair.getVertexPosition(0, new Vector3()).applyMatrix4(hair.matrixWorld);
    const head = byName(avatarRoot, 'Avatar_Head');
    head.position.x += 10;  // 10 cm in the neck's frame (the armature scale is 0.01)
    scene.updateMatrixWorld();
    const after = hair.getVertexPosition(0, new Vector3()).applyMatrix4(hair.matrixWorld);
    assert.ok(Math.abs(after.x - before.x - 0.1) < 1e-4, `moved by ${after.x - before.x} m`);
  });

  test('avatarArmature is computed once: a second wearable never matches the first one\'s bones', () => {
    const { scene, avatarRoot, attachment: first } = wornSample();
    const armature = avatarArmature(avatarRoot);
    assert.equal(armature.size, 63, '62 bones + Armature');
    assert.ok(!armature.has('SpringBone_ponytail'));
    const { attachment: second } = wornSample({ scene, avatar: avatarRoot });
    assert.notEqual(second.jointObjects[0], first.jointObjects[0]);
    assert.equal(second.jointObjects[0].parent, byName(avatarRoot, 'Avatar_Head'));
  });

  test('rejects what is not an avatar, a wearable or a rig', () => {
    assert.throws(() => attachWearable({}, wearableGltf, rig), TypeError);
    assert.throws(() => attachWearable(new Group(), wearableGltf, {}), TypeError);
    assert.throws(() => attachWearable(new Group(), new Group(), rig), /options\.nodes/);
  });
});

describe('SpringBonesAttachment.update', () => {
  test('starts at the rest pose and writes the instance rotations into the joints', () => {
    const { attachment } = wornSample();
    for (const o of attachment.jointObjects) assert.deepEqual(o.quaternion.toArray(), [0, 0, 0, 1]);
    attachment.update(1 / 60);
    const r = attachment.instance.rotations;
    attachment.jointObjects.forEach((o, j) => {
      assert.deepEqual(o.quaternion.toArray(), Array.from(r.subarray(j * 4, j * 4 + 4)));
    });
    assert.ok(r.some((v, i) => i % 4 !== 3 && v !== 0), 'gravity bends something in the first frame');
  });

  test('must not fire the quaternion onChange callback (no Euler sync per joint)', () => {
    const { attachment } = wornSample();
    let calls = 0;
    for (const o of attachment.jointObjects) o.quaternion._onChange(() => { calls += 1; });
    for (let f = 0; f < 10; f++) attachment.update(1 / 60);
    assert.equal(calls, 0);
  });

  test('copies each driver\'s matrixWorld into the instance', () => {
    const { scene, avatarRoot, attachment } = wornSample();
    avatarRoot.position.set(1, 2, 3);
    avatarRoot.rotation.y = 0.5;
    scene.updateMatrixWorld();
    attachment.update(1 / 60);
    attachment.driverObjects.forEach((o, d) => {
      const written = Array.from(attachment.instance.driverMatrices.subarray(d * 16, d * 16 + 16));
      assert.ok(maxAbsDiff(written, o.matrixWorld.elements) < 1e-6, `driver ${o.name}`);
    });
  });

  test('the hair swings while the avatar walks, keeps its length, and hangs down when it stops', () => {
    const { scene, avatarRoot, attachment } = wornSample();
    const mixer = new AnimationMixer(avatarRoot);
    const walk = mixer.clipAction(avatarGltf.animations.find((c) => c.name === 'walk')).play();
    const tip = byName(avatarRoot, 'SpringBone_ponytail_tip');
    const base = byName(avatarRoot, 'SpringBone_ponytail_4');
    const restLength = 0.06;
    const samples = [];
    for (let f = 0; f < 240; f++) {
      mixer.update(1 / 60);
      scene.updateMatrixWorld();
      attachment.update(1 / 60);
      scene.updateMatrixWorld();
      if (f % 20 === 0) samples.push(Array.from(attachment.instance.rotations));
      const length = tip.getWorldPosition(new Vector3()).distanceTo(base.getWorldPosition(new Vector3()));
      assert.ok(Math.abs(length - restLength) < 1e-4, `last ponytail bone is ${length} m long`);
    }
    for (let i = 1; i < samples.length; i++) assert.ok(maxAbsDiff(samples[i - 1], samples[i]) > 1e-3, 'moving');

    walk.stop();
    for (let f = 0; f < 600; f++) {
      scene.updateMatrixWorld();
      attachment.update(1 / 60);
    }
    const settled = Array.from(attachment.instance.rotations);
    scene.updateMatrixWorld();
    attachment.update(1 / 60);
    assert.ok(maxAbsDiff(settled, attachment.instance.rotations) < 1e-5, 'settled');
  });

  test('several avatars are independent', () => {
    const scene = new Scene();
    const a = wornSample({ scene });
    const b = wornSample({ scene });
    b.avatarRoot.position.x = 2;
    for (let f = 0; f < 60; f++) {
      scene.updateMatrixWorld();
      a.attachment.update(1 / 60);
      b.attachment.update(1 / 60);
    }
    assert.ok(maxAbsDiff(a.attachment.instance.rotations, b.attachment.instance.rotations) < 1e-5, 'same pose, same result');
    for (let f = 0; f < 30; f++) {
      a.avatarRoot.rotation.y += 0.1;  // only a turns
      scene.updateMatrixWorld();
      a.attachment.update(1 / 60);
      b.attachment.update(1 / 60);
    }
    assert.ok(maxAbsDiff(a.attachment.instance.rotations, b.attachment.instance.rotations) > 1e-2, 'a turned, b did not');
  });
});

describe('setRig, reset, dispose', () => {
  test('setRig switches parameters and puts joints no longer simulated back at rest', () => {
    const { scene, attachment } = wornSample();
    for (let f = 0; f < 30; f++) {
      scene.updateMatrixWorld();
      attachment.update(1 / 60);
    }
    const lock = attachment.jointObjects.find((o) => o.name === 'hair_springbone_l');
    assert.notDeepEqual(lock.quaternion.toArray(), [0, 0, 0, 1], 'gravity bends the side lock');
    const [hash] = Object.keys(metadata.models);
    const ponytailOnly = { version: 1, models: { [hash]: { SpringBone_ponytail: metadata.models[hash].SpringBone_ponytail } } };
    const smaller = sb.loadRig(wearableBytes, ponytailOnly);
    attachment.setRig(smaller);
    assert.equal(attachment.jointObjects.length, 5);
    assert.deepEqual(lock.quaternion.toArray(), [0, 0, 0, 1]);
    scene.updateMatrixWorld();
    attachment.update(1 / 60);
    assert.throws(() => attachment.setRig({}), TypeError);
    assert.equal(attachment.rig, smaller, 'a failed setRig changes nothing');
    attachment.dispose();
    smaller.dispose();
  });

  test('reset forgets the motion: the next frame is a fresh start', () => {
    const scene = new Scene();
    const moved = wornSample({ scene });
    for (let f = 0; f < 60; f++) {
      moved.avatarRoot.rotation.y += 0.1;
      scene.updateMatrixWorld();
      moved.attachment.update(1 / 60);
    }
    moved.avatarRoot.position.x = 5;  // a teleport
    const fresh = wornSample({ scene });
    fresh.avatarRoot.position.copy(moved.avatarRoot.position);
    fresh.avatarRoot.rotation.copy(moved.avatarRoot.rotation);
    scene.updateMatrixWorld();
    moved.attachment.reset();
    moved.attachment.update(1 / 60);
    fresh.attachment.update(1 / 60);
    assert.ok(maxAbsDiff(moved.attachment.instance.rotations, fresh.attachment.instance.rotations) < 1e-6);
  });

  test('dispose takes the wearable off the avatar and frees the instance', () => {
    const { avatarRoot, attachment } = wornSample();
    const head = byName(avatarRoot, 'Avatar_Head');
    const instance = attachment.instance;
    attachment.dispose();
    assert.equal(instance.disposed, true);
    assert.throws(() => attachment.update(1 / 60), { name: 'SpringBonesError', code: 'disposed' });
    assert.equal(head.children.length, 0);
    assert.ok(!avatarRoot.children.some((c) => c.isSkinnedMesh && c.name === 'Hair'));
  });
});

test('SpringBonesHelper draws one segment per joint, from the joint to its tail', () => {
  const { scene, attachment } = wornSample();
  const helper = new SpringBonesHelper(attachment);
  scene.add(helper);
  scene.updateMatrixWorld();
  const p = helper.geometry.getAttribute('position').array;
  assert.equal(p.length, 15 * 6);
  const head = attachment.jointObjects[0].getWorldPosition(new Vector3());
  const tail = attachment.tailObjects[0].getWorldPosition(new Vector3());
  assert.ok(head.distanceTo(new Vector3(p[0], p[1], p[2])) < 1e-6);
  assert.ok(tail.distanceTo(new Vector3(p[3], p[4], p[5])) < 1e-6);
  helper.dispose();
});

test('Matrix4.elements keeps its array (the adapter caches it)', () => {
  const m = new Matrix4();
  const elements = m.elements;
  m.copy(new Matrix4().makeTranslation(1, 2, 3)).multiply(new Matrix4().makeRotationX(1)).invert();
  m.compose(new Vector3(1, 2, 3), new Quaternion(), new Vector3(1, 1, 1));
  assert.equal(m.elements, elements);
});
