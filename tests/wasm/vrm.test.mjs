// sb.loadVrm: VRMC_springBone 1.0 and VRM 0.x avatars into the same Rig interface as loadRig,
// stepped with both integrators; bad bytes are SpringBonesErrors.
import assert from 'node:assert/strict';
import { before, describe, test } from 'node:test';

import { createSpringBones, SpringBonesError } from '../../web/springbones.js';
import { swayDrivers } from '../../bin/sway.mjs';
import { fixture, springRig } from './helpers.mjs';

let sb;
before(async () => {
  sb = await createSpringBones();
});

function stepAndCheck(rig, options) {
  const instance = rig.createInstance(options);
  const rest = Float32Array.from(instance.driverMatrices);
  const first = Float32Array.from(instance.rotations);
  for (let k = 1; k <= 240; ++k) {
    swayDrivers(rest, instance.driverMatrices, k / 60);
    instance.step(k % 60 === 0 ? 0.25 : 1 / 60);
    const r = instance.rotations;
    for (let i = 0; i < r.length; i += 4) {
      assert.ok(r.subarray(i, i + 4).every(Number.isFinite), `frame ${k} joint ${i / 4}`);
      assert.ok(Math.abs(Math.hypot(r[i], r[i + 1], r[i + 2], r[i + 3]) - 1) < 1e-5, `frame ${k} joint ${i / 4}`);
    }
  }
  assert.notDeepEqual(Float32Array.from(instance.rotations), first, 'the springs moved');
  instance.dispose();
}

describe('loadVrm', () => {
  test('VRM 1.0 (VRMC_springBone): joints, colliders on avatar bones, finite unit quaternions', () => {
    const rig = sb.loadVrm(fixture('vrm10_springs.vrm'));
    assert.equal(rig.format, 'vrmc-springbone');
    assert.equal(rig.contentHash, '');
    assert.ok(rig.joints.length > 0 && rig.chains.length > 0);
    assert.ok(rig.colliders.length > 0);
    for (const c of rig.colliders) {
      assert.ok(c.driver >= 0 && rig.drivers[c.driver].name === c.node);
      assert.ok(c.shape === 'sphere' || c.shape === 'capsule');
    }
    assert.ok(rig.joints.every((j) => typeof j.tail === 'string' && j.tailNode >= 0));
    assert.ok(Object.isFrozen(rig.joints[0]));
    stepAndCheck(rig);
    stepAndCheck(rig, { integrator: 'xpbd' });
    rig.dispose();
  });

  test('VRMC_springBone_extended_collider: plane and inside shapes in rig.colliders, an unknown version falls back', () => {
    const rig = sb.loadVrm(fixture('vrm10_extended_colliders.vrm'));
    assert.deepEqual(rig.colliders.map((c) => [c.node, c.shape, c.inside]), [
      ['J_Head', 'plane', false], ['J_Head', 'sphere', true], ['J_Hips', 'capsule', true], ['J_Chest', 'sphere', false],
    ]);
    assert.deepEqual(rig.colliders[0].normal, [0, 0, -1]);
    assert.equal(rig.colliders[0].radius, 0);
    assert.deepEqual(rig.warnings.map((w) => [w.code, w.path]),
      [['vrm-extended-collider', '/extensions/VRMC_springBone/colliders/3/extensions/VRMC_springBone_extended_collider']]);
    stepAndCheck(rig);
    stepAndCheck(rig, { integrator: 'xpbd' });
    rig.dispose();
  });

  test('VRM 0.x (secondaryAnimation): leaves have a virtual tail (no node, an offset)', () => {
    const rig = sb.loadVrm(fixture('vrm0_springs.vrm'));
    assert.equal(rig.format, 'vrm0');
    const leaves = rig.joints.filter((j) => j.tailNode === -1);
    assert.ok(leaves.length > 0);
    for (const leaf of leaves) {
      assert.equal(leaf.tail, null);
      assert.ok(Math.abs(Math.hypot(...leaf.tailOffset) - 0.07) < 1e-6, 'the 7 cm virtual tail');
    }
    stepAndCheck(rig);
    stepAndCheck(rig, { integrator: 'xpbd' });
    rig.dispose();
  });

  test('a glTF without VRM springs loads as an empty rig with a warning', () => {
    const rig = sb.loadVrm(springRig().glb);
    assert.equal(rig.format, 'none');
    assert.equal(rig.joints.length, 0);
    assert.ok(rig.warnings.some((w) => w.code === 'vrm-no-springs'));
    rig.dispose();
  });

  test('bad bytes: TypeError before crossing, SpringBonesError after; nothing leaks; the module keeps working', () => {
    const vrm = fixture('vrm10_springs.vrm');
    sb.loadVrm(vrm).dispose();  // warm up one-time allocations
    const before = sb.stats();
    for (const bad of [undefined, null, 'vrm', [1, 2], new Float32Array(4)]) {
      assert.throws(() => sb.loadVrm(bad), (e) => e instanceof TypeError);
    }
    const truncated = vrm.subarray(0, 200);
    const notJson = new TextEncoder().encode('{"asset": {"version": "2.0"}, "extensions": {"VRMC_springBone": ');
    const badSprings = new TextEncoder().encode(JSON.stringify({ asset: { version: '2.0' }, nodes: [{ name: 'a' }], extensions: { VRMC_springBone: { specVersion: '1.0', springs: 5 } } }));
    for (const [bytes, code] of [[new Uint8Array(0), 'glb-truncated'], [new Uint8Array([1, 2, 3, 4, 5, 6, 7, 8]), 'glb-bad-magic'],
      [truncated, 'glb-truncated'], [notJson, 'gltf-bad-json'], [badSprings, 'metadata-invalid']]) {
      assert.throws(() => sb.loadVrm(bytes), (e) => e instanceof SpringBonesError && e.code === code && e.message.length > 0, code);
    }
    assert.deepEqual(sb.stats(), before);
    const rig = sb.loadVrm(vrm);
    stepAndCheck(rig);
    rig.dispose();
  });
});
