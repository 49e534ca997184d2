// attachment.setColliders in the three.js adapter (issue 40): a collider following an Object3D
// that belongs to neither the wearable nor the avatar (a "hat") pushes the ponytail out of it
// once the hat moves into the hair; no call leaves the motion as it was; 'dcl-body' resized per
// attachment changes the motion; a bad collider is an error naming it.
import assert from 'node:assert/strict';
import { describe, test } from 'node:test';
import { AnimationMixer, Object3D, Scene, Vector3 } from 'three';
import * as SkeletonUtils from 'three/examples/jsm/utils/SkeletonUtils.js';
import { loadSampleWearable } from '../wasm/sample_wearable.mjs';
import { SpringBonesGroup, attachWearable, wearableNodes } from '../../web/three/springBonesThree.js';

const { sb, avatarGltf, wearableGltf, rig } = await loadSampleWearable();

/** A fresh avatar in a scene, wearing a fresh clone of the sample wearable; warnings collected. */
function wornSample() {
  const scene = new Scene();
  const avatarRoot = SkeletonUtils.clone(avatarGltf.scene);
  scene.add(avatarRoot);
  const wearable = SkeletonUtils.clone(wearableGltf.scene);
  const said = [];
  const attachment = attachWearable(avatarRoot, wearable, rig, { nodes: wearableNodes(wearableGltf, wearable), onWarning: (w) => said.push(w) });
  scene.updateMatrixWorld();
  return { scene, avatarRoot, attachment, said };
}

/** The world positions of every joint's tail that has an object (the ponytail and the side locks). */
const tails = (attachment) => attachment.tailObjects.filter(Boolean).map((o) => o.getWorldPosition(new Vector3()));

/** Runs `frames` frames of the avatar walking. */
function walk(scene, avatarRoot, attachments, frames) {
  const mixer = new AnimationMixer(avatarRoot);
  mixer.clipAction(avatarGltf.animations.find((c) => c.name === 'walk')).play();
  for (let f = 0; f < frames; f++) {
    mixer.update(1 / 60);
    scene.updateMatrixWorld();
    for (const attachment of attachments) attachment.update(1 / 60);
  }
}

describe('attachment.setColliders', () => {
  test('a sphere following a hat that moves into the hair pushes every tail out of it', () => {
    const { scene, attachment, said } = wornSample();
    const hat = new Object3D();
    hat.name = 'hat';
    hat.position.set(1, 0, 0);  // far from the hair
    scene.add(hat);
    scene.updateMatrixWorld();
    // The hat's centre goes on the lowest tail, straight below its joint, the pushing's hardest case:
    // the VRM step pushes the tail to the sphere and then back to its length from the joint, which
    // leaves it 1.2 mm inside at this radius (0.5 mm at 0.03 m, 4 mm at 0.06 m).
    const radius = 0.04;
    const warnings = attachment.setColliders([{ node: hat, radius }]);
    assert.deepEqual(warnings, []);
    assert.deepEqual(attachment.instance.frameNames, ['hat']);
    for (let f = 0; f < 30; f++) attachment.update(1 / 60);
    // Into the hair: the ponytail's last tail at rest, so the hat's sphere swallows the hair's end.
    const target = tails(attachment).reduce((low, p) => (p.y < low.y ? p : low));
    hat.position.copy(target);
    scene.updateMatrixWorld();
    const inside = tails(attachment).filter((p) => p.distanceTo(hat.position) < radius).length;
    assert.ok(inside > 0, 'before the next frames, the hat holds a tail');
    for (let f = 0; f < 120; f++) {
      scene.updateMatrixWorld();
      attachment.update(1 / 60);
    }
    scene.updateMatrixWorld();
    const center = hat.getWorldPosition(new Vector3());
    const closest = Math.min(...tails(attachment).map((p) => p.distanceTo(center)));
    assert.ok(closest > radius - 2e-3, `the closest tail is ${closest} m from the hat's centre (radius ${radius})`);
    const written = Array.from(attachment.instance.frameMatrices);
    assert.deepEqual(written, Array.from(Float32Array.from(hat.matrixWorld.elements)), 'the hat\'s matrixWorld, as the last update read it');
    assert.deepEqual(said, []);
  });

  test('without a setColliders call, or with none given, the rotations are bit for bit those of the plain instance', () => {
    const plain = wornSample();
    const none = wornSample();
    none.attachment.setColliders(null);
    const bare = rig.createInstance();
    const mixer = new AnimationMixer(plain.avatarRoot);
    mixer.clipAction(avatarGltf.animations.find((c) => c.name === 'walk')).play();
    const mixerNone = new AnimationMixer(none.avatarRoot);
    mixerNone.clipAction(avatarGltf.animations.find((c) => c.name === 'walk')).play();
    for (let f = 0; f < 120; f++) {
      mixer.update(1 / 60);
      mixerNone.update(1 / 60);
      plain.scene.updateMatrixWorld();
      none.scene.updateMatrixWorld();
      plain.attachment.driverObjects.forEach((o, d) => bare.driverMatrices.set(o.matrixWorld.elements, 16 * d));
      bare.step(1 / 60);
      plain.attachment.update(1 / 60);
      none.attachment.update(1 / 60);
    }
    assert.deepEqual(Array.from(plain.attachment.instance.rotations), Array.from(bare.rotations));
    assert.deepEqual(Array.from(none.attachment.instance.rotations), Array.from(bare.rotations), 'no colliders: the sample rig has none');
    assert.ok(bare.rotations.some((v, i) => i % 4 !== 3 && Math.abs(v) > 1e-3), 'the hair moved');
    bare.dispose();
  });

  test("dcl-body at scale 2 moves the hair otherwise than at scale 1 (the sample's hair reaches no body shape at 1 or below), measured on the avatar's bones", () => {
    const double = wornSample();
    const full = wornSample();
    const warnings = full.attachment.setColliders('dcl-body');
    assert.ok(warnings.every((w) => w.code !== 'body-collider-skipped'), 'every body shape found its bones');
    double.attachment.setColliders('dcl-body', { scale: 2 });
    assert.ok(full.attachment.instance.frameNames.includes('Avatar_Neck'), 'the body shapes the rig has no driver for ride on the avatar\'s bones');
    assert.deepEqual(full.said, [], 'and each found its bone');
    walk(double.scene, double.avatarRoot, [double.attachment], 180);
    walk(full.scene, full.avatarRoot, [full.attachment], 180);
    const a = double.attachment.instance.rotations;
    const b = full.attachment.instance.rotations;
    const most = a.reduce((m, v, i) => Math.max(m, Math.abs(v - b[i])), 0);
    assert.ok(most > 1e-3, `the rotations differ by at most ${most}`);
  });

  test('a collider whose node is neither a name nor an Object3D is a TypeError naming it; nothing changes', () => {
    const { attachment } = wornSample();
    assert.throws(() => attachment.setColliders([{ node: 'Avatar_Head', radius: 0.1 }, { node: 42, radius: 0.1 }]), {
      name: 'TypeError',
      message: 'setColliders: colliders[1].node must be a node name (a string) or an object of the engine\'s scene (three.js: an Object3D; Babylon: a TransformNode), got 42',
    });
    assert.throws(() => attachment.setColliders([{ node: new Object3D(), radius: -1 }]), /^RangeError: setColliders: colliders\[0\]\.radius/);
    assert.deepEqual(attachment.instance.frameNames, []);
  });

  test('a name found nowhere is collider-not-followed; kept across setRig', () => {
    const { attachment, said } = wornSample();
    attachment.setColliders([{ node: 'no such node', radius: 0.1 }]);
    assert.deepEqual(said.map((w) => w.code), ['collider-not-followed']);
    assert.ok(attachment.warnings.some((w) => w.code === 'collider-not-followed'));
    const hat = new Object3D();
    attachment.setColliders([{ node: hat, radius: 0.1 }]);
    assert.ok(!attachment.warnings.some((w) => w.code === 'collider-not-followed'), 'replaced by the next call');
    const before = attachment.instance;
    attachment.setRig(rig);
    assert.notEqual(attachment.instance, before);
    assert.deepEqual(attachment.instance.frameNames, ['object'], 'an unnamed object gets a name of its own');
  });

  test('in a SpringBonesGroup, the frames are copied by group.update: the same rotations as alone', () => {
    const alone = wornSample();
    const grouped = wornSample();
    const group = new SpringBonesGroup(sb);
    group.add(grouped.attachment);
    const hats = [alone, grouped].map(({ scene, attachment }) => {
      const hat = new Object3D();
      scene.add(hat);
      attachment.setColliders([{ node: hat, radius: 0.04 }]);
      return hat;
    });
    const target = tails(alone.attachment).reduce((low, p) => (p.y < low.y ? p : low));
    for (let f = 0; f < 60; f++) {
      for (const hat of hats) hat.position.set(target.x, target.y, target.z + 0.1 * Math.sin(f * 0.1));
      alone.scene.updateMatrixWorld();
      grouped.scene.updateMatrixWorld();
      alone.attachment.update(1 / 60);
      group.update(1 / 60);
    }
    assert.deepEqual(Array.from(grouped.attachment.instance.frameMatrices), Array.from(alone.attachment.instance.frameMatrices));
    assert.deepEqual(Array.from(grouped.attachment.instance.rotations), Array.from(alone.attachment.instance.rotations));
    assert.deepEqual(Array.from(grouped.attachment.instance.frameMatrices), Array.from(Float32Array.from(hats[1].matrixWorld.elements)),
      'group.update copied the hat\'s last matrixWorld');
    group.dispose();
  });
});
