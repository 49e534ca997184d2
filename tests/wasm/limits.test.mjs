// Angle limits (VRMC_springBone_limit 1.0-draft; docs/semantics.md, "Angle limits") on three-vrm's
// three example files (read where they are, in ../shared/fixtures/real): rig.joints reports them,
// no limited joint leaves its limit under shaking, wind and colliders with either integrator, and
// the motion agrees with @pixiv/three-vrm-springbone 3.5.5 given the rules of three-vrm's limit
// pull request (scripts/lib/three_vrm_limits.mjs), with a collider listed by two collider groups
// (three-vrm pushes with it once per group, as we do). loadRig takes limits as an option.
import assert from 'node:assert/strict';
import { existsSync, readFileSync } from 'node:fs';
import path from 'node:path';
import { before, describe, test } from 'node:test';
import * as THREE from 'three';
import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';
import { VRMSpringBoneLoaderPlugin } from '@pixiv/three-vrm-springbone';

import { createSpringBones } from '../../web/springbones.js';
import { applyLimits } from '../../scripts/lib/three_vrm_limits.mjs';
import { countCollisions } from '../../scripts/lib/three_vrm_collisions.mjs';
import { useExactBoneLength } from '../../scripts/lib/three_vrm_equalized.mjs';
import { realFixturesDir, springRig } from './helpers.mjs';

const realDir = realFixturesDir();
const kFiles = ['threevrm-cone-limit.gltf', 'threevrm-hinge-limit.gltf', 'threevrm-spherical-limit.gltf'];
const fps = 60;

let sb;
before(async () => {
  for (const f of kFiles) {
    assert.ok(existsSync(path.join(realDir, f)), `missing ${path.join(realDir, f)}: the shared real fixtures are required`);
  }
  sb = await createSpringBones();
});

/**
 * The file's glTF JSON, changed in memory only: its scene roots hang from a new node, Body, that
 * the tests move (the example chains are scene roots, which nothing moves); with `collider`, a
 * sphere on Body in two collider groups, both listed by every spring, where the chains swing.
 */
function readExample(file, { collider = false } = {}) {
  const json = JSON.parse(readFileSync(path.join(realDir, file), 'utf8'));
  const scene = json.scenes[json.scene ?? 0];
  const body = json.nodes.length;
  json.nodes.push({ name: 'Body', children: scene.nodes });
  scene.nodes = [body];
  if (collider) {
    const ext = json.extensions.VRMC_springBone;
    ext.colliders = [
      { node: body, shape: { sphere: { offset: [0.35, 1.2, 0], radius: 0.18 } } },
      { node: body, shape: { sphere: { offset: [-0.35, 1.2, 0.1], radius: 0.18 } } },
    ];
    ext.colliderGroups = [{ colliders: [0, 1] }, { colliders: [1] }];
    for (const spring of ext.springs) spring.colliderGroups = [0, 1];
  }
  return json;
}

const bytesOf = (json) => new TextEncoder().encode(JSON.stringify(json));

// Body's world matrix at frame f (1-based): it slides and turns hard enough to hit every limit.
function bodyMatrix(f, out = new THREE.Matrix4()) {
  const t = (f - 1) / fps;
  const position = new THREE.Vector3(0.8 * Math.sin(2 * Math.PI * 0.8 * t), 0.3 * Math.sin(2 * Math.PI * 1.3 * t),
    0.6 * Math.sin(2 * Math.PI * 0.55 * t));
  const turn = new THREE.Quaternion().setFromEuler(new THREE.Euler(0.7 * Math.sin(2 * Math.PI * 0.6 * t),
    1.2 * Math.sin(2 * Math.PI * 0.4 * t), 0.9 * Math.sin(2 * Math.PI * 0.9 * t)));
  return out.compose(position, turn, new THREE.Vector3(1, 1, 1));
}

describe('rig.joints reports the limits of the example files', () => {
  for (const file of kFiles) {
    test(file, () => {
      const json = readExample(file);
      const rig = sb.loadVrm(bytesOf(json));
      assert.deepEqual(rig.warnings, []);
      const expected = new Map();
      for (const spring of json.extensions.VRMC_springBone.springs) {
        for (const joint of spring.joints.slice(0, -1)) expected.set(joint.node, joint.extensions.VRMC_springBone_limit.limit);
      }
      assert.equal(rig.joints.length, expected.size);
      for (const joint of rig.joints) {
        const want = expected.get(joint.node);
        const [kind] = Object.keys(want);
        assert.deepEqual(Object.keys(joint.limit), [kind]);
        for (const key of kind === 'spherical' ? ['pitch', 'yaw'] : ['angle']) {
          assert.ok(Math.abs(joint.limit[kind][key] - want[kind][key]) < 1e-6, `${joint.name} ${kind}.${key}`);
        }
        const r = want[kind].rotation;
        const n = Math.hypot(...r);
        joint.limit[kind].rotation.forEach((v, k) => assert.ok(Math.abs(v - r[k] / n) < 1e-6, `${joint.name} rotation`));
      }
      rig.dispose();
    });
  }
});

/** A joint's limit space in the world after a step, from the instance's world matrices, as the draft defines it. */
function limitSpace(rig, world, drivers, j) {
  const joint = rig.joints[j];
  const parent = joint.parent >= 0 ? new THREE.Matrix4().fromArray(world, 16 * joint.parent) : drivers[joint.parentDriver];
  const parentRotation = new THREE.Quaternion();
  parent.decompose(new THREE.Vector3(), parentRotation, new THREE.Vector3());
  // The joint's rest rotation: its world matrix turned back by its own swing is not known here,
  // so take it from the rest pose the rig reports: world = parent x rest local x swing, and the
  // rest local rotation is the rotation at rest (frame 0 of the instance).
  const axis = new THREE.Vector3().fromArray(joint.tailOffset).normalize();
  const toAxis = axis.equals(new THREE.Vector3(0, -1, 0)) ? new THREE.Quaternion(1, 0, 0, 0)
    : new THREE.Quaternion().setFromUnitVectors(new THREE.Vector3(0, 1, 0), axis);
  const [kind] = Object.keys(joint.limit);
  return parentRotation.multiply(restRotations.get(rig)[j]).multiply(toAxis)
    .multiply(new THREE.Quaternion().fromArray(joint.limit[kind].rotation));
}
const restRotations = new WeakMap();

/** Radians by which a unit direction in limit space is outside the limit (<= 0 inside). */
function beyond(limit, d) {
  const clamp = (v) => Math.min(1, Math.max(-1, v));
  if (limit.cone) return Math.acos(clamp(d.y)) - limit.cone.angle;
  if (limit.hinge) return Math.max(Math.asin(Math.abs(clamp(d.x))), Math.acos(clamp(d.y / Math.hypot(d.y, d.z))) - limit.hinge.angle);
  return Math.max(Math.abs(Math.atan2(d.z, d.y)) - limit.spherical.pitch, Math.abs(Math.asin(clamp(d.x))) - limit.spherical.yaw);
}

/**
 * 6 s of Body's motion under a gusty wind: the largest angle by which a joint left its limit
 * (radians), with `limited` false measured against the file's limits on a rig without them.
 */
function worstExcess(file, integrator, limited) {
  const json = readExample(file, { collider: true });
  const reference = sb.loadVrm(bytesOf(json));
  if (!limited) {
    for (const spring of json.extensions.VRMC_springBone.springs) for (const j of spring.joints) delete j.extensions;
  }
  const rig = sb.loadVrm(bytesOf(json));
  const instance = rig.createInstance({ integrator });
  instance.setWind({ direction: [1, 0, 0.4], strength: 4, gustFrequency: 1.5, seed: 3 });
  const restOf = rig.joints.map((_, j) => new THREE.Quaternion().fromArray(instance.rotations, 4 * j));
  restRotations.set(reference, restOf);
  const drivers = rig.drivers.map(() => new THREE.Matrix4());
  let worst = -Infinity;
  for (let f = 1; f <= 360; f++) {
    rig.drivers.forEach((d, i) => {
      assert.equal(d.name, 'Body');
      bodyMatrix(f, drivers[i]);
      instance.driverMatrices.set(drivers[i].elements, 16 * i);
    });
    instance.step(1 / fps);
    const world = instance.worldMatrices;
    reference.joints.forEach((joint, j) => {
      const m = new THREE.Matrix4().fromArray(world, 16 * j);
      const offset = new THREE.Vector3().fromArray(joint.tailOffset).applyMatrix4(m).sub(new THREE.Vector3().setFromMatrixPosition(m));
      const d = offset.normalize().applyQuaternion(limitSpace(reference, world, drivers, j).invert());
      worst = Math.max(worst, beyond(joint.limit, d));
    });
  }
  instance.dispose();
  rig.dispose();
  reference.dispose();
  return worst;
}

describe('no limited joint leaves its limit under shaking, wind and colliders', () => {
  for (const file of kFiles) {
    for (const integrator of ['vrm', 'xpbd']) {
      test(`${file}, ${integrator}`, (t) => {
        const free = worstExcess(file, integrator, false);
        const held = worstExcess(file, integrator, true);
        t.diagnostic(`without the limits a joint goes ${(free * 180 / Math.PI).toFixed(1)} degrees beyond them; with them ${held.toExponential(2)} rad`);
        assert.ok(free > 0.2, `the motion does not reach the limits (${free} rad)`);
        assert.ok(held < 1e-4, `a joint went ${held} rad beyond its limit`);
      });
    }
  }
});

/**
 * The file in springbones and in three-vrm 3.5.5 with the PR's limit rules, one step per frame for
 * 240 frames under Body's motion: the largest quaternion component difference, the limit
 * activations and collider contacts three-vrm saw.
 */
async function compareWithThreeVrm(file, { exactRotation = true } = {}) {
  const json = readExample(file, { collider: true });
  const bytes = bytesOf(json);
  const rig = sb.loadVrm(bytes);
  const instance = rig.createInstance({ stepHz: fps, maxSubsteps: 4 });
  const loader = new GLTFLoader();
  loader.register((parser) => new VRMSpringBoneLoaderPlugin(parser));
  const gltf = await loader.parseAsync(bytes.slice().buffer, '');
  const manager = gltf.userData.vrmSpringBoneManager;
  const nodes = await gltf.parser.getDependencies('node');
  const body = nodes[json.nodes.length - 1];
  gltf.scene.updateMatrixWorld(true);
  manager.setInitState();
  useExactBoneLength(true);
  const activations = applyLimits(manager, json, nodes, { exactRotation });
  const contacts = countCollisions(manager, () => 'sphere');
  const m = new THREE.Matrix4();
  let worst = 0;
  let worstFrame = 0;
  try {
    for (let f = 1; f <= 240; f++) {
      bodyMatrix(f, m).decompose(body.position, body.quaternion, body.scale);
      gltf.scene.updateMatrixWorld(true);
      manager.update(1 / fps);
      instance.driverMatrices.set(body.matrixWorld.elements, 0);
      instance.step(1 / fps);
      const r = instance.rotations;
      rig.joints.forEach((joint, j) => {
        const q = nodes[joint.node].quaternion;
        const want = [q.x, q.y, q.z, q.w];
        const sign = want.reduce((s, v, k) => s + v * r[4 * j + k], 0) < 0 ? -1 : 1;
        const d = Math.max(...want.map((v, k) => Math.abs(r[4 * j + k] - sign * v)));
        if (d > worst) [worst, worstFrame] = [d, f];
      });
    }
  } finally {
    useExactBoneLength(false);
  }
  assert.equal(rig.drivers.length, 1);
  instance.dispose();
  rig.dispose();
  return { worst, worstFrame, activations, contacts };
}

describe("agreement with three-vrm's limit rules (PR #1632) on the example files", () => {
  for (const file of kFiles) {
    test(file, async (t) => {
      const { worst, worstFrame, activations, contacts } = await compareWithThreeVrm(file);
      const stock = await compareWithThreeVrm(file, { exactRotation: false });
      t.diagnostic(`max |dq| ${worst.toExponential(2)} (frame ${worstFrame}); limits moved a tail ${JSON.stringify(activations)} times, ` +
        `the sphere pushed ${contacts.sphere} times; with the PR's rotation of a scaled matrix ${stock.worst.toExponential(2)}`);
      assert.ok(Object.values(activations).reduce((a, b) => a + b) > 100, 'three-vrm hit the limits');
      assert.ok(contacts.sphere > 20, 'three-vrm hit the collider listed by two groups');
      // float against three.js's double, through the limits' switches between free and bounded
      // motion: the hinge's largest difference, at one frame, is 9.6e-5 (docs/semantics.md).
      assert.ok(worst < 2e-4, `rotations differ by ${worst}`);
    });
  }
});

test('hostile limit values in a VRM file load as finite limits with warnings, and the springs stay finite', () => {
  const json = readExample('threevrm-hinge-limit.gltf');
  const [j0, j1, j2, j3] = json.extensions.VRMC_springBone.springs[0].joints;
  j0.extensions.VRMC_springBone_limit.limit = { cone: { angle: 1e300, rotation: [1e300, 0, 0, 1] } };
  j1.extensions.VRMC_springBone_limit.limit = { spherical: { pitch: 'wide', yaw: -1e300, rotation: [0, 0, 1] } };
  j2.extensions.VRMC_springBone_limit.limit = { hinge: [] };
  j3.extensions.VRMC_springBone_limit = { specVersion: '1.0-draft', limit: { cone: { angle: 0.2 }, hinge: { angle: 0.1 } } };
  const rig = sb.loadVrm(bytesOf(json));
  // Two shapes: ignored, as UniVRM's import rules have it (docs/semantics.md, "Angle limits").
  assert.deepEqual(rig.joints.map((j) => j.limit && Object.keys(j.limit)[0]), ['cone', 'spherical', null, null]);
  for (const { limit } of rig.joints.filter((j) => j.limit)) {
    const [shape] = Object.values(limit);
    for (const v of [...Object.values(shape).filter((x) => !Array.isArray(x)), ...shape.rotation]) {
      assert.ok(typeof v === 'number' && Number.isFinite(v), JSON.stringify(limit));
    }
  }
  assert.ok(Math.abs(rig.joints[0].limit.cone.angle - Math.PI) < 1e-6, "an angle beyond float is pi");
  assert.deepEqual(rig.joints[0].limit.cone.rotation, [0, 0, 0, 1]);
  assert.deepEqual([...new Set(rig.warnings.map((w) => w.code))].sort(),
    ['limit-clamped', 'limit-invalid', 'limit-rotation-invalid']);
  const instance = rig.createInstance();
  for (let f = 1; f <= 60; f++) {
    instance.driverMatrices.set(bodyMatrix(f).elements, 0);
    instance.step(1 / fps);
  }
  assert.ok(instance.rotations.every(Number.isFinite));
  instance.dispose();
  rig.dispose();
});

test('the collider in two groups pushes twice: listing one group only changes the motion', () => {
  const rotationsOver = (json) => {
    const rig = sb.loadVrm(bytesOf(json));
    const instance = rig.createInstance();
    const out = [];
    for (let f = 1; f <= 240; f++) {
      instance.driverMatrices.set(bodyMatrix(f).elements, 0);
      instance.step(1 / fps);
      out.push(...instance.rotations);
    }
    const codes = rig.warnings.map((w) => w.code);
    instance.dispose();
    rig.dispose();
    return { out, codes };
  };
  for (const file of kFiles) {
    const twice = readExample(file, { collider: true });
    const once = readExample(file, { collider: true });
    for (const spring of once.extensions.VRMC_springBone.springs) spring.colliderGroups = [0];
    const a = rotationsOver(twice), b = rotationsOver(once);
    assert.ok(a.codes.includes('vrm-collider-repeated') && !b.codes.includes('vrm-collider-repeated'), file);
    const differ = Math.max(...a.out.map((v, k) => Math.abs(v - b.out[k])));
    assert.ok(differ > 1e-3, `${file}: the second push changed nothing (${differ})`);
  }
});

describe("loadRig's limits option", () => {
  const { glb, springBones, hash } = springRig({ chains: 1, joints: 3 });

  test('puts a limit on a joint by name, reported by rig.joints, and holds it under shaking', () => {
    const rig = sb.loadRig(glb, springBones, { contentHash: hash, limits: { SpringBone_0_1: { cone: { angle: 0.3 } } } });
    assert.deepEqual(rig.warnings, []);
    assert.deepEqual(rig.joints[1].limit, { cone: { angle: 0.3, rotation: [0, 0, 0, 1] } });
    assert.equal(rig.joints[0].limit, null);
    rig.dispose();
  });

  test('warns about a name that is no joint, a chain tip, and clamps angles beyond the draft', () => {
    const rig = sb.loadRig(glb, springBones, {
      contentHash: hash,
      limits: { nope: { hinge: { angle: 1 } }, SpringBone_0_tip: { cone: { angle: 1 } }, SpringBone_0_0: { spherical: { pitch: -1, yaw: 9 } } },
    });
    assert.deepEqual(rig.warnings.map((w) => w.code).sort(), ['limit-clamped', 'limit-clamped', 'limit-joint-not-found', 'limit-on-end-joint']);
    assert.deepEqual(rig.joints[0].limit.spherical.pitch, 0);
    assert.ok(Math.abs(rig.joints[0].limit.spherical.yaw - Math.PI / 2) < 1e-6);
    rig.dispose();
  });

  test('a rotation of extreme finite size is made unit, with a warning naming its length', () => {
    // Squared in float32, [1e20, 0, 0, 1e20] overflows and [1e-25, 0, 0, 1e-25] underflows; both are
    // half a turn about X.
    const rig = sb.loadRig(glb, springBones, {
      contentHash: hash,
      limits: {
        SpringBone_0_0: { cone: { angle: 0.3, rotation: [1e20, 0, 0, 1e20] } },
        SpringBone_0_1: { hinge: { angle: 0.3, rotation: [1e-25, 0, 0, 1e-25] } },
      },
    });
    const h = Math.SQRT1_2;
    for (const [j, kind] of [[0, 'cone'], [1, 'hinge']]) {
      const q = rig.joints[j].limit[kind].rotation;
      assert.ok(Math.hypot(q[0] - h, q[1], q[2], q[3] - h) < 1e-6, `joint ${j}: ${q}`);
    }
    const messages = rig.warnings.filter((w) => w.code === 'limit-rotation-invalid').map((w) => w.message);
    assert.equal(messages.length, 2, rig.warnings.map((w) => w.message).join('; '));
    assert.ok(messages.some((m) => m.includes('1.41421e+20')) && messages.some((m) => m.includes('1.41421e-25')), messages.join('; '));
    assert.ok(messages.every((m) => !m.includes('finite')), messages.join('; '));
    rig.dispose();
  });

  test('wrong types are TypeErrors and non-finite numbers RangeErrors, before crossing', () => {
    const load = (limits) => () => sb.loadRig(glb, springBones, { contentHash: hash, limits });
    assert.throws(load([]), TypeError);
    assert.throws(load({ SpringBone_0_1: { cone: { angle: 0.3 }, hinge: { angle: 0.3 } } }), TypeError);
    assert.throws(load({ SpringBone_0_1: { box: {} } }), TypeError);
    assert.throws(load({ SpringBone_0_1: { cone: { angle: '1' } } }), TypeError);
    assert.throws(load({ SpringBone_0_1: { cone: { angle: 0.3, rotation: [0, 0, 1] } } }), TypeError);
    assert.throws(load({ SpringBone_0_1: { spherical: { pitch: 0.3 } } }), TypeError);
    assert.throws(load({ SpringBone_0_1: { cone: { angle: NaN } } }), RangeError);
    assert.throws(load({ SpringBone_0_1: { hinge: { angle: 1, rotation: [0, 0, 0, Infinity] } } }), RangeError);
  });
});
