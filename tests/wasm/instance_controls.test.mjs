// settle, grab / release and inertia from JavaScript: the springs at rest in a pose, a chain held
// and let go, how much of its driver's motion a chain feels; their argument checks; the three.js
// attachment's and group's settle and the Babylon drop-in's settle and grab. The core's rules are
// tested natively in tests/native/instance_controls_test.cpp.
import assert from 'node:assert/strict';
import { readFile } from 'node:fs/promises';
import { join } from 'node:path';
import { before, describe, test } from 'node:test';
import { SpringBonesError } from '../../web/springbones.js';
import { SpringBoneSimulation } from '../../web/babylon/index.js';
import { SpringBonesGroup } from '../../web/three/springBonesThree.js';
import { frameHash, frameHashCases } from '../scenarios/frame_hash.mjs';
import { nativeFrameHashes } from '../scenarios/native_frame_hashes.mjs';
import { babylonKit, readAsset } from '../adapters/babylon_kit.mjs';
import { fixture, root, springRig } from './helpers.mjs';
import { loadSampleWearable } from './sample_wearable.mjs';

let sb;
let sample;
const rigs = {};  // name -> rig, the sample wearable and the three VRM fixtures
before(async () => {
  sample = await loadSampleWearable();
  sb = sample.sb;
  rigs['sample wearable'] = sample.rig;
  for (const name of ['vrm0_springs.vrm', 'vrm10_springs.vrm', 'vrm10_extended_colliders.vrm']) {
    rigs[name] = sb.loadVrm(fixture(name));
  }
});

/** The angle between two unit quaternions, accurate for small angles. */
function turnBetween(a, i, b, j) {
  const [ax, ay, az, aw] = [-a[i], -a[i + 1], -a[i + 2], a[i + 3]];  // conjugate of a
  const [bx, by, bz, bw] = [b[j], b[j + 1], b[j + 2], b[j + 3]];
  const x = aw * bx + ax * bw + ay * bz - az * by;
  const y = aw * by - ax * bz + ay * bw + az * bx;
  const z = aw * bz + ax * by - ay * bx + az * bw;
  const w = aw * bw - ax * bx - ay * by - az * bz;
  return 2 * Math.atan2(Math.hypot(x, y, z), Math.abs(w));
}

function largestTurn(before, after) {
  let turn = 0;
  for (let k = 0; k < before.length; k += 4) turn = Math.max(turn, turnBetween(before, k, after, k));
  return turn;
}

/** Every driver of `inst` at m x its value now (m: a column-major 4x4 of a rotation and translation). */
function moveDrivers(inst, rest, m) {
  const out = inst.driverMatrices;
  for (let d = 0; d < rest.length; d += 16) {
    for (let col = 0; col < 4; col++) {
      const x = rest[d + 4 * col], y = rest[d + 4 * col + 1], z = rest[d + 4 * col + 2], w = rest[d + 4 * col + 3];
      for (let row = 0; row < 3; row++) out[d + 4 * col + row] = m[row] * x + m[4 + row] * y + m[8 + row] * z + m[12 + row] * w;
      out[d + 4 * col + 3] = w;
    }
  }
}

// The avatar bent forward 0.9 rad and turned 0.6 rad, moved 0.3 m: R = Rx(0.9) Ry(0.6).
function bentPose() {
  const ca = Math.cos(0.9), sa = Math.sin(0.9), cb = Math.cos(0.6), sb2 = Math.sin(0.6);
  return [cb, sa * sb2, -ca * sb2, 0, 0, ca, sa, 0, sb2, -sa * cb, ca * cb, 0, 0.3, 0, 0, 1];
}
const translation = (x, y, z) => [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, x, y, z, 1];

describe('settle', () => {
  test('the next frame after settling turns no joint by more than 1e-3 rad, both integrators', () => {
    let unsettled = 0;
    for (const [name, rig] of Object.entries(rigs)) {
      for (const integrator of ['vrm', 'xpbd']) {
        const inst = rig.createInstance({ integrator });
        const rest = Float32Array.from(inst.driverMatrices);
        moveDrivers(inst, rest, bentPose());
        const steps = inst.settle();
        const stepHz = integrator === 'xpbd' ? 120 : 60;
        assert.ok(steps >= 1 && steps <= 2 * stepHz, `${name} ${integrator}: ${steps} steps`);
        const settled = Float32Array.from(inst.rotations);
        inst.step(1 / 60);
        const turn = largestTurn(settled, inst.rotations);
        assert.ok(turn <= 1e-3, `${name} ${integrator}: the next frame turns a joint by ${turn} rad`);
        inst.dispose();

        // Without settling, the same pose's frames swing: the bound above could fail.
        const fresh = rig.createInstance({ integrator });
        moveDrivers(fresh, rest, bentPose());
        fresh.step(1 / 60);
        const first = Float32Array.from(fresh.rotations);
        fresh.step(1 / 60);
        unsettled = Math.max(unsettled, largestTurn(first, fresh.rotations));
        fresh.dispose();
      }
    }
    assert.ok(unsettled > 1e-2, `unsettled frames turn ${unsettled} rad`);
  });

  test('is deterministic: the same pose gives the same rotations and steps, whatever came before', () => {
    for (const integrator of ['vrm', 'xpbd']) {
      const walked = sample.rig.createInstance({ integrator });
      const fresh = sample.rig.createInstance({ integrator });
      const rest = Float32Array.from(walked.driverMatrices);
      for (let f = 0; f < 90; f++) {
        moveDrivers(walked, rest, translation(0, 0, 0.03 * f));
        walked.step(1 / 60);
      }
      moveDrivers(walked, rest, bentPose());
      moveDrivers(fresh, rest, bentPose());
      assert.equal(walked.settle(), fresh.settle());
      assert.deepEqual(Array.from(walked.rotations), Array.from(fresh.rotations));
      walked.dispose();
      fresh.dispose();
    }
  });

  test('checks its time: [0, 60] seconds, 0 steps for 0', () => {
    const inst = sample.rig.createInstance();
    assert.equal(inst.settle(0), 0);
    assert.equal(inst.settle(1 / 60), 1);
    for (const bad of [-1, 61, NaN, Infinity]) assert.throws(() => inst.settle(bad), RangeError);
    assert.throws(() => inst.settle('2'), TypeError);
    inst.dispose();
    assert.throws(() => inst.settle(), (e) => e instanceof SpringBonesError && e.code === 'disposed');
  });
});

describe('grab', () => {
  const joints = 3;
  const chain = springRig({ joints });

  /** The world tail of joint j, from the instance's joint world matrices. */
  function tailOf(inst, rig, j) {
    const m = inst.worldMatrices.subarray(16 * j, 16 * j + 16);
    const [x, y, z] = rig.joints[j].tailOffset;
    return [0, 1, 2].map((r) => m[r] * x + m[4 + r] * y + m[8 + r] * z + m[12 + r]);
  }

  test('the grabbed tail reaches a point within the chain reach, and the chain swings back on release', () => {
    const rig = sb.loadRig(chain.glb, chain.springBones, { contentHash: chain.hash });
    for (const integrator of ['vrm', 'xpbd']) {
      const inst = rig.createInstance({ integrator });
      inst.settle();
      const settled = Float32Array.from(inst.rotations);
      const root = Array.from(inst.worldMatrices.subarray(12, 15));
      // 0.1 m beside and 0.05 m below the root: inside the reach of three 5 cm bones.
      const point = [root[0] + 0.1, root[1] - 0.05, root[2] + 0.02];
      for (let f = 0; f < 120; f++) {
        inst.grab(joints - 1, point);
        inst.step(1 / 60);
      }
      assert.equal(inst.grabbedJoint, joints - 1);
      const tail = tailOf(inst, rig, joints - 1);
      const distance = Math.hypot(tail[0] - point[0], tail[1] - point[1], tail[2] - point[2]);
      assert.ok(distance < 2e-3, `${integrator}: the tail is ${distance} m from the point`);
      const held = largestTurn(settled, inst.rotations);
      inst.release();
      assert.equal(inst.grabbedJoint, -1);
      for (let f = 0; f < 600; f++) inst.step(1 / 60);
      const after = largestTurn(settled, inst.rotations);
      assert.ok(after < 0.1 * held, `${integrator}: ${after} rad from rest after release, ${held} while held`);
      inst.dispose();
    }
    rig.dispose();
  });

  test('a disposed instance, a joint out of range or a non-finite point is a RangeError', () => {
    const inst = sample.rig.createInstance();
    const count = sample.rig.joints.length;
    for (const joint of [-1, count, 1.5]) assert.throws(() => inst.grab(joint, [0, 0, 0]), RangeError);
    assert.throws(() => inst.grab(0, [NaN, 0, 0]), RangeError);
    assert.throws(() => inst.grab(0, [0, Infinity, 0]), RangeError);
    assert.throws(() => inst.grab('0', [0, 0, 0]), TypeError);
    assert.throws(() => inst.grab(0, [0, 0]), TypeError);
    assert.equal(inst.grabbedJoint, -1);
    inst.grab(count - 1, [0, 1.5, 0]);
    assert.equal(inst.grabbedJoint, count - 1);
    inst.dispose();
    assert.throws(() => inst.grab(0, [0, 0, 0]), RangeError);
    assert.throws(() => inst.release(), RangeError);
  });

  test('a point finite in double but beyond float32 is a RangeError naming the coordinate, and the grab is kept', () => {
    // It crosses as float32, where 1e39 is infinite: the core would ignore it, silently.
    const inst = sample.rig.createInstance();
    const joint = sample.rig.joints.length - 1;
    inst.grab(joint, [0, 1.5, 0]);
    const beyond = 2 ** 128;  // the first double that Math.fround makes infinite is a little below it
    assert.equal(Math.fround(beyond), Infinity);
    for (const [point, named] of [[[1e39, 0, 0], 'point[0]'], [[0, -beyond, 0], 'point[1]'], [[0, 0, -1e300], 'point[2]']]) {
      assert.throws(() => inst.grab(0, point), (e) => e instanceof RangeError && e.message.includes(`grab: ${named}`) &&
                    /float32/.test(e.message));
    }
    assert.equal(inst.grabbedJoint, joint, 'the refused calls left the earlier grab as it was');
    // The largest float32 itself crosses.
    const largest = (2 - 2 ** -23) * 2 ** 127;
    inst.grab(0, [largest, 0, 0]);
    assert.equal(inst.grabbedJoint, 0);
    inst.dispose();
  });
});

describe('inertia', () => {
  test('inertia 1 gives the frame hashes of an instance without it, bit for bit', async () => {
    const native = nativeFrameHashes();
    for (const c of frameHashCases) {
      const bytes = new Uint8Array(await readFile(join(root, c.file)));
      const rig = c.vrm ? sb.loadVrm(bytes) : sb.loadRig(bytes, JSON.parse(await readFile(join(root, c.metadata), 'utf8')));
      assert.deepEqual(frameHash(rig, { options: { inertia: 1 } }), native[c.name], c.name);
      rig.dispose();
    }
  });

  test('inertia 0 keeps the sample wearable at rest under a pure translation of the avatar', (t) => {
    const ride = (inertia, integrator) => {
      const inst = sample.rig.createInstance({ inertia, integrator });
      const rest = Float32Array.from(inst.driverMatrices);
      inst.settle();
      let last = Float32Array.from(inst.rotations);
      let turn = 0;
      for (let f = 1; f <= 120; f++) {
        const t = f / 60;
        moveDrivers(inst, rest, translation(0.3 * Math.sin(3 * t), 0.1 * Math.sin(5 * t), 2 * t * t));
        inst.step(1 / 60);
        turn = Math.max(turn, largestTurn(last, inst.rotations));
        last = Float32Array.from(inst.rotations);
      }
      inst.dispose();
      return turn;
    };
    for (const integrator of ['vrm', 'xpbd']) {
      const full = ride(1, integrator), none = ride(0, integrator);
      t.diagnostic(`${integrator}: largest turn per frame ${full} rad at inertia 1, ${none} rad at inertia 0`);
      assert.ok(full > 1e-2, `${integrator}: inertia 1 turns ${full} rad per frame`);
      // At rest as settle leaves a chain: the drivers end 8 m from the origin, where float32 world
      // positions are 1e-6 m apart, a few 1e-5 rad on these 5 cm bones (6e-5 and 2.3e-4 measured).
      assert.ok(none < 1e-3, `${integrator}: inertia 0 turns ${none} rad per frame`);
    }
  });

  test('createInstance and setInertia check the value and the chain', () => {
    for (const bad of [-0.1, 1.5, NaN]) assert.throws(() => sample.rig.createInstance({ inertia: bad }), RangeError);
    assert.throws(() => sample.rig.createInstance({ inertia: '1' }), TypeError);
    const inst = sample.rig.createInstance({ inertia: 0.5 });
    inst.setInertia(0.25);
    inst.setInertia(0, sample.rig.chains.length - 1);
    assert.throws(() => inst.setInertia(0, sample.rig.chains.length), RangeError);
    assert.throws(() => inst.setInertia(0, -1), RangeError);
    assert.throws(() => inst.setInertia(2), RangeError);
    inst.dispose();
    assert.throws(() => inst.setInertia(1), (e) => e instanceof SpringBonesError && e.code === 'disposed');
  });
});

describe('adapters', () => {
  test('three.js: the attachment and the group settle in the avatar pose and write the joints', () => {
    const worn = sample.wear(sample.rig);
    const { attachment, holder, scene } = worn;
    holder.rotation.set(0.9, 0.6, 0);
    scene.updateMatrixWorld();
    const steps = attachment.settle();
    assert.ok(steps > 0);
    const rotations = attachment.instance.rotations;
    attachment.jointObjects.forEach((object, j) => {
      const q = object.quaternion;
      assert.deepEqual([q.x, q.y, q.z, q.w], Array.from(rotations.subarray(4 * j, 4 * j + 4)));
    });
    // Settled in the bent pose: the next update hardly moves.
    const settled = Float32Array.from(rotations);
    attachment.update(1 / 60);
    assert.ok(largestTurn(settled, attachment.instance.rotations) <= 1e-3);

    const group = new SpringBonesGroup(sb);
    group.add(attachment);
    assert.equal(group.settle(), steps);
    group.dispose();
    attachment.dispose();
  });

  test('Babylon: SpringBoneSimulation settles and grabs a registered wearable', async () => {
    const kit = await babylonKit('current');
    const scene = kit.scene();
    const container = await kit.load(scene, readAsset('hair_wearable.glb'));
    container.addAllToScene();
    const metadata = JSON.parse(new TextDecoder().decode(readAsset('hair_wearable.metadata.json')));
    const [hash] = Object.keys(metadata.models);
    const simulation = new SpringBoneSimulation(sb);
    simulation.registerWearable(scene, container, hash, metadata.models[hash]);
    simulation.start(scene);
    assert.ok(simulation.settle() > 0);
    assert.ok(simulation.settle(hash, 1) > 0);
    assert.throws(() => simulation.settle(hash, -1), RangeError);
    const joints = simulation.rigOf(hash).joints;
    simulation.grab(hash, joints.length - 1, { x: 0.3, y: 1.6, z: 0.3 });
    assert.throws(() => simulation.grab(hash, joints.length, [0, 0, 0]), RangeError);
    assert.throws(() => simulation.grab(hash, joints.length - 1, { x: 1e39, y: 1.6, z: 0.3 }), /float32/);
    simulation.release();
    simulation.dispose(scene);
  });
});
