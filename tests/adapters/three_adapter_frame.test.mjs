// What the three.js adapter leaves in the bones each frame, and SpringBonesGroup (one scene.step
// for many attachments): quaternions equal to the instance's rotations, world matrices (after
// three.js's updateMatrixWorld) equal to the instance's, `.rotation` brought in step on request
// (the adapter bypasses Quaternion.set()), and a group stepping exactly like separate updates.
import assert from 'node:assert/strict';
import { describe, test } from 'node:test';
import { spawnSync } from 'node:child_process';
import { fileURLToPath } from 'node:url';
import { AnimationMixer, Euler, Quaternion, Scene } from 'three';
import * as SkeletonUtils from 'three/examples/jsm/utils/SkeletonUtils.js';
import { createSpringBones } from '../../web/springbones.js';
import { loadSampleWearable } from '../wasm/sample_wearable.mjs';
import { SpringBonesGroup, attachWearable, wearableNodes } from '../../web/three/springBonesThree.js';

const DT = 1 / 60;
// One solver step per frame, landing at the frame's end: the instance's world matrices are then
// those of this frame's drivers, the ones three.js composes the bones under.
const ONE_STEP = { stepHz: 60 };

const { sb, avatarGltf, wearableGltf, wearableBytes, metadata, rig } = await loadSampleWearable();

/** A fresh avatar in `scene` wearing a fresh clone of the sample wearable, walking. */
function walker(scene, { instance = ONE_STEP, x = 0, speed = 1 } = {}) {
  const avatarRoot = SkeletonUtils.clone(avatarGltf.scene);
  avatarRoot.position.x = x;
  scene.add(avatarRoot);
  const wearable = SkeletonUtils.clone(wearableGltf.scene);
  const attachment = attachWearable(avatarRoot, wearable, rig, { nodes: wearableNodes(wearableGltf, wearable), instance });
  const mixer = new AnimationMixer(avatarRoot);
  mixer.clipAction(avatarGltf.animations.find((c) => c.name === 'walk')).play();
  scene.updateMatrixWorld();
  return { avatarRoot, attachment, mixer, speed };
}

/** Animation and a turn for each walker, then world matrices: what a page does before update. */
function animate(scene, walkers, f) {
  for (const w of walkers) {
    w.mixer.update(DT * w.speed);
    w.avatarRoot.rotation.y = 0.8 * Math.sin(f * DT * 3 * w.speed);
  }
  scene.updateMatrixWorld();
}

const maxAbsDiff = (a, b) => {
  let m = 0;
  for (let i = 0; i < a.length; i++) m = Math.max(m, Math.abs(a[i] - b[i]));
  return m;
};

describe('what the adapter writes', () => {
  test('each joint quaternion is exactly the instance rotation, every frame', () => {
    const scene = new Scene();
    const w = walker(scene);
    const { attachment } = w;
    let bent = 0;
    for (let f = 0; f < 90; f++) {
      animate(scene, [w], f);
      attachment.update(DT);
      const r = attachment.instance.rotations;
      attachment.jointObjects.forEach((o, j) => {
        const q = o.quaternion;
        assert.deepEqual([q.x, q.y, q.z, q.w], Array.from(r.subarray(4 * j, 4 * j + 4)), `frame ${f}, ${o.name}`);
        if (Math.abs(q.w) < 0.999) bent += 1;
      });
    }
    assert.ok(bent > 0, 'the walk bends some joints away from identity');
    attachment.dispose();
  });

  test('after updateMatrixWorld, each joint matrixWorld equals the instance world matrix (1e-6)', () => {
    const scene = new Scene();
    const w = walker(scene);
    const { attachment } = w;
    let worst = 0;
    let moved = 0;
    const first = attachment.jointObjects.map((o) => o.matrixWorld.elements.slice(12, 15));
    for (let f = 0; f < 120; f++) {
      animate(scene, [w], f);
      attachment.update(DT);
      scene.updateMatrixWorld();  // the renderer's pass: joints composed from the new quaternions
      const world = attachment.instance.worldMatrices;
      attachment.jointObjects.forEach((o, j) => {
        worst = Math.max(worst, maxAbsDiff(o.matrixWorld.elements, world.subarray(16 * j, 16 * j + 16)));
        moved = Math.max(moved, maxAbsDiff(o.matrixWorld.elements.slice(12, 15), first[j]));
      });
    }
    assert.ok(worst < 1e-6, `largest difference ${worst}`);
    assert.ok(moved > 0.05, `the joints travel (${moved} m), so the comparison is not of rest poses`);
    attachment.dispose();
  });

  test('.rotation: stale while simulated (no Euler sync per joint), in step after syncEulers and dispose', () => {
    const scene = new Scene();
    const w = walker(scene);
    const { attachment } = w;
    const expected = new Euler();
    const eulerError = (o) => {
      expected.setFromQuaternion(o.quaternion, o.rotation.order);
      return maxAbsDiff(o.rotation.toArray().slice(0, 3), expected.toArray().slice(0, 3));
    };
    for (let f = 0; f < 30; f++) {
      animate(scene, [w], f);
      attachment.update(DT);
    }
    assert.ok(Math.max(...attachment.jointObjects.map(eulerError)) > 1e-3, 'the per-frame writes skip the Euler');
    attachment.syncEulers();
    for (const o of attachment.jointObjects) assert.ok(eulerError(o) < 1e-12, o.name);
    // Writing through .rotation still drives the quaternion (three.js's own Euler onChange).
    const joint = attachment.jointObjects[0];
    joint.rotation.set(0.3, -0.2, 0.1);
    const q = new Quaternion().setFromEuler(new Euler(0.3, -0.2, 0.1));
    assert.ok(maxAbsDiff(joint.quaternion.toArray(), q.toArray()) < 1e-12);
    // The joints stay plain Object3Ds (fast properties: a redefined `rotation` slowed
    // updateMatrixWorld down for the whole tree).
    assert.ok('value' in Object.getOwnPropertyDescriptor(joint, 'rotation'));
    // Disposing without detaching keeps the pose, with a current .rotation.
    for (let f = 30; f < 40; f++) {
      animate(scene, [w], f);
      attachment.update(DT);
    }
    attachment.dispose({ detach: false });
    assert.ok(Math.abs(joint.quaternion.w) < 0.99999, 'still bent');
    for (const o of attachment.jointObjects) assert.ok(eulerError(o) < 1e-12, o.name);
  });

  test('clones of a simulated joint get its current rotation, Euler included', () => {
    const scene = new Scene();
    const w = walker(scene);
    for (let f = 0; f < 20; f++) {
      animate(scene, [w], f);
      w.attachment.update(DT);
    }
    const joint = w.attachment.jointObjects[1];
    const copy = joint.clone(false);  // Object3D.copy copies the quaternion with onChange
    assert.deepEqual(copy.quaternion.toArray(), joint.quaternion.toArray());
    const expected = new Euler().setFromQuaternion(joint.quaternion, joint.rotation.order);
    assert.ok(maxAbsDiff(copy.rotation.toArray().slice(0, 3), expected.toArray().slice(0, 3)) < 1e-12);
    w.attachment.dispose();
  });
});

// A group holding the walkers' attachments, in order; and its end, with the attachments.
function groupOf(walkers) {
  const group = new SpringBonesGroup(sb);
  for (const w of walkers) group.add(w.attachment);
  return group;
}

function disposeAll(group, walkers) {
  group.dispose();
  for (const w of walkers) w.attachment.dispose();
}

describe('SpringBonesGroup', () => {
  test('one group.update steps every attachment exactly as separate updates do', () => {
    const sceneA = new Scene();
    const sceneB = new Scene();
    const speeds = [1, 0.5, 1.7];
    const separate = speeds.map((speed, i) => walker(sceneA, { speed, x: i }));
    const grouped = speeds.map((speed, i) => walker(sceneB, { speed, x: i }));
    const group = new SpringBonesGroup(sb);
    for (const w of grouped) group.add(w.attachment);
    assert.equal(group.scene.size, 3);
    for (let f = 0; f < 90; f++) {
      animate(sceneA, separate, f);
      for (const w of separate) w.attachment.update(DT);
      animate(sceneB, grouped, f);
      group.update(DT);
    }
    speeds.forEach((_, i) => {
      assert.deepEqual(Array.from(grouped[i].attachment.instance.rotations), Array.from(separate[i].attachment.instance.rotations));
      grouped[i].attachment.jointObjects.forEach((o, j) => {
        assert.deepEqual(o.quaternion.toArray(), separate[i].attachment.jointObjects[j].quaternion.toArray());
      });
    });
    assert.ok(maxAbsDiff(grouped[0].attachment.instance.rotations, grouped[1].attachment.instance.rotations) > 1e-3,
      'the avatars move differently, so equal results are not trivially equal');
    group.dispose();
    for (const w of [...separate, ...grouped]) w.attachment.dispose();
  });

  test('avatar positions feed the scene budget: only the nearest avatars are simulated', () => {
    const scene = new Scene();
    const walkers = [0, 10, 3].map((x) => walker(scene, { x }));
    const group = groupOf(walkers);
    group.scene.setBudget(2, 0, 0, 0);
    animate(scene, walkers, 0);
    group.update(DT);
    const positions = group.scene.positions;
    walkers.forEach((w, i) => {
      assert.deepEqual(Array.from(positions.subarray(3 * i, 3 * i + 3)), w.avatarRoot.getWorldPosition(w.avatarRoot.position.clone()).toArray());
    });
    assert.deepEqual(walkers.map((w) => group.scene.isActive(w.attachment.instance)), [true, false, true]);
    disposeAll(group, walkers);
  });

  test('the joints of avatars the budget holds are not written; they keep their pose and move again when back', () => {
    const scene = new Scene();
    const walkers = [0, 10, 3].map((x) => walker(scene, { x }));
    const group = groupOf(walkers);
    group.scene.setBudget(2, 0, 0, 0);
    const quaternions = (w) => w.attachment.jointObjects.map((o) => o.quaternion.toArray());
    for (let f = 0; f < 30; f++) {
      animate(scene, walkers, f);
      group.update(DT);
    }
    assert.deepEqual(Array.from(group.scene.active), [1, 0, 1]);
    // A marker in a held avatar's joint stays: the group does not write that avatar's joints.
    const far = walkers[1].attachment.jointObjects[1];
    far.quaternion._x = 0.25;
    const heldPose = quaternions(walkers[1]);
    const near = quaternions(walkers[2]);
    animate(scene, walkers, 30);
    group.update(DT);
    assert.deepEqual(quaternions(walkers[1]), heldPose);
    assert.notDeepEqual(quaternions(walkers[2]), near, 'the active ones are written');
    // Back in the budget: written again, from its instance.
    walkers[1].avatarRoot.position.x = 0.5;
    for (let f = 31; f < 40; f++) {
      animate(scene, walkers, f);
      group.update(DT);
    }
    assert.equal(group.scene.active[1], 1);
    const rotations = walkers[1].attachment.instance.rotations;
    walkers[1].attachment.jointObjects.forEach((o, j) => {
      if (o) assert.deepEqual(o.quaternion.toArray(), Array.from(rotations.subarray(4 * j, 4 * j + 4)), `joint ${j}`);
    });
    disposeAll(group, walkers);
  });

  test('setRig, remove and dispose keep the group and the scene in step', () => {
    const scene = new Scene();
    const walkers = [0, 1, 2].map((x) => walker(scene, { x }));
    const group = groupOf(walkers);
    group.add(walkers[0].attachment);  // again: nothing happens
    assert.equal(group.scene.size, 3);

    // setRig: the new instance takes the last slot, in the scene and in group.attachments.
    const [hash] = Object.keys(metadata.models);
    const ponytail = sb.loadRig(wearableBytes, { version: 1, models: { [hash]: { SpringBone_ponytail: metadata.models[hash].SpringBone_ponytail } } });
    walkers[0].attachment.setRig(ponytail);
    assert.deepEqual(group.attachments, [walkers[1].attachment, walkers[2].attachment, walkers[0].attachment]);
    assert.equal(group.scene.size, 3);
    assert.equal(group.scene.slotOf(walkers[0].attachment.instance), 2);
    assert.equal(group.scene.slotOf(walkers[1].attachment.instance), 0);
    animate(scene, walkers, 0);
    group.update(DT);
    assert.ok(walkers.every((w) => group.scene.isActive(w.attachment.instance)), 'all stepped after setRig');

    // remove: stepped on its own again; dispose: leaves the group.
    group.remove(walkers[1].attachment);
    assert.equal(group.scene.size, 2);
    walkers[1].attachment.update(DT);
    walkers[2].attachment.dispose();
    assert.deepEqual(group.attachments, [walkers[0].attachment]);
    assert.equal(group.scene.size, 1);
    group.update(DT);

    // one group per attachment; only attachments
    const other = new SpringBonesGroup(sb);
    assert.throws(() => other.add(walkers[0].attachment), /another group/);
    assert.throws(() => other.add({}), TypeError);
    assert.throws(() => other.add(walkers[2].attachment), { code: 'disposed' });
    assert.throws(() => new SpringBonesGroup({}), TypeError);
    other.add(walkers[1].attachment);
    other.dispose();
    walkers[1].attachment.update(DT);  // usable on its own after its group is gone

    group.dispose();
    assert.throws(() => group.update(DT), { code: 'disposed' });
    walkers[0].attachment.dispose();
    walkers[1].attachment.dispose();
    ponytail.dispose();
  });

  test('members of different sizes: each instance gets its own drivers and its own joints get its rotations', () => {
    // The group copies through flat lists over all members: a wrong offset at a member boundary
    // shows as a driver matrix or a quaternion of another avatar.
    const scene = new Scene();
    const walkers = [0, 1, 2, 3].map((x, i) => walker(scene, { x, speed: 1 + 0.3 * i }));
    const [hash] = Object.keys(metadata.models);
    const ponytail = sb.loadRig(wearableBytes, { version: 1, models: { [hash]: { SpringBone_ponytail: metadata.models[hash].SpringBone_ponytail } } });
    walkers[1].attachment.setRig(ponytail);
    assert.ok(ponytail.joints.length < rig.joints.length, 'the members differ in joint count');
    const group = groupOf(walkers);
    for (let f = 0; f < 30; f++) {
      animate(scene, walkers, f);
      group.readDrivers();
      for (const { attachment } of walkers) {
        const m = attachment.instance.driverMatrices;
        attachment.driverObjects.forEach((o, d) => {
          assert.deepEqual(Array.from(m.subarray(16 * d, 16 * d + 16)), Array.from(Float32Array.from(o.matrixWorld.elements)), `frame ${f}, driver ${d}`);
        });
      }
      group.scene.step(DT);
      group.writeRotations();
      for (const { attachment } of walkers) {
        const r = attachment.instance.rotations;
        attachment.jointObjects.forEach((o, j) => {
          assert.deepEqual(o.quaternion.toArray(), Array.from(r.subarray(4 * j, 4 * j + 4)), `frame ${f}, ${o.name}`);
        });
      }
    }
    disposeAll(group, walkers);
    ponytail.dispose();
  });

  test('a joint or driver without a three.js object: warned, skipped, and the others are right', () => {
    const scene = new Scene();
    const complete = walker(scene, { x: 1 });
    const avatarRoot = SkeletonUtils.clone(avatarGltf.scene);
    scene.add(avatarRoot);
    const wearable = SkeletonUtils.clone(wearableGltf.scene);
    const nodes = wearableNodes(wearableGltf, wearable);
    const lostDriver = 0;
    const lostJoint = rig.joints.length - 1;
    delete nodes[rig.drivers[lostDriver].node];
    delete nodes[rig.joints[lostJoint].node];
    const attachment = attachWearable(avatarRoot, wearable, rig, { nodes, instance: ONE_STEP });
    assert.deepEqual(attachment.warnings.map((w) => w.code), ['node-not-found', 'node-not-found']);
    assert.equal(attachment.driverObjects[lostDriver], null);
    assert.equal(attachment.jointObjects[lostJoint], null);
    const rest = Array.from(attachment.instance.driverMatrices.subarray(16 * lostDriver, 16 * lostDriver + 16));
    const mixer = new AnimationMixer(avatarRoot);
    mixer.clipAction(avatarGltf.animations.find((c) => c.name === 'walk')).play();
    const walkers = [{ avatarRoot, attachment, mixer, speed: 1.3 }, complete];
    const group = new SpringBonesGroup(sb);
    for (const w of walkers) group.add(w.attachment);  // the complete one after: offsets past the gaps
    for (let f = 0; f < 30; f++) {
      animate(scene, walkers, f);
      group.update(DT);
      for (const w of walkers) {
        const m = w.attachment.instance.driverMatrices;
        w.attachment.driverObjects.forEach((o, d) => {
          const expected = o ? Array.from(Float32Array.from(o.matrixWorld.elements)) : rest;
          assert.deepEqual(Array.from(m.subarray(16 * d, 16 * d + 16)), expected, `frame ${f}, driver ${d}`);
        });
        const r = w.attachment.instance.rotations;
        w.attachment.jointObjects.forEach((o, j) => {
          if (o) assert.deepEqual(o.quaternion.toArray(), Array.from(r.subarray(4 * j, 4 * j + 4)), `frame ${f}, ${o.name}`);
        });
      }
    }
    disposeAll(group, walkers);
  });

  test('after WebAssembly memory grows, updates go through the new views', () => {
    // The adapter keeps each instance's views between frames; growth detaches them.
    const scene = new Scene();
    const walkers = [0, 1, 2].map((x, i) => walker(scene, { x, speed: 1 + 0.4 * i }));
    const group = new SpringBonesGroup(sb);
    group.add(walkers[1].attachment);
    group.add(walkers[2].attachment);
    const frame = (f) => {
      animate(scene, walkers, f);
      walkers[0].attachment.update(DT);
      group.update(DT);
    };
    for (let f = 0; f < 10; f++) frame(f);
    const old = walkers.map((w) => w.attachment.instance.rotations);
    sb.contentHash(new Uint8Array(sb.stats().heapBytes + (8 << 20)));  // copied into WASM memory: it grows
    assert.ok(old.every((view) => view.byteLength === 0), 'the views held across the growth are detached');
    for (let f = 10; f < 20; f++) {
      frame(f);
      for (const { attachment } of walkers) {
        const m = attachment.instance.driverMatrices;
        attachment.driverObjects.forEach((o, d) => {
          assert.deepEqual(Array.from(m.subarray(16 * d, 16 * d + 16)), Array.from(Float32Array.from(o.matrixWorld.elements)), `frame ${f}, driver ${d}`);
        });
        const r = attachment.instance.rotations;
        attachment.jointObjects.forEach((o, j) => {
          assert.deepEqual(o.quaternion.toArray(), Array.from(r.subarray(4 * j, 4 * j + 4)), `frame ${f}, ${o.name}`);
        });
      }
    }
    disposeAll(group, walkers);
  });

  test('an instance disposed of directly: update throws \'disposed\' before writing anything', () => {
    const scene = new Scene();
    const walkers = [0, 1].map((x) => walker(scene, { x }));
    const group = new SpringBonesGroup(sb);
    group.add(walkers[1].attachment);
    animate(scene, walkers, 0);
    walkers[0].attachment.update(DT);
    group.update(DT);
    for (const { attachment } of walkers) attachment.instance.dispose();
    // New instances may take the freed memory: a view kept across the dispose would write there.
    const fresh = [rig.createInstance(), rig.createInstance()];
    const before = fresh.map((i) => [Float32Array.from(i.driverMatrices), Float32Array.from(i.rotations)]);
    animate(scene, walkers, 1);
    assert.throws(() => walkers[0].attachment.update(DT), { code: 'disposed' });
    assert.throws(() => walkers[0].attachment.readDrivers(), { code: 'disposed' });
    assert.throws(() => walkers[0].attachment.writeRotations(), { code: 'disposed' });
    assert.throws(() => group.update(DT), { code: 'disposed' });
    assert.throws(() => group.writeRotations(), { code: 'disposed' });
    fresh.forEach((i, k) => {
      assert.deepEqual(i.driverMatrices, before[k][0]);
      assert.deepEqual(i.rotations, before[k][1]);
      i.dispose();
    });
    disposeAll(group, walkers);
  });

  test('a setRig the group cannot take (another module\'s rig) changes nothing', async () => {
    const scene = new Scene();
    const w = walker(scene);
    const group = new SpringBonesGroup(sb);
    group.add(w.attachment);
    const instance = w.attachment.instance;
    const otherModule = await createSpringBones();
    const foreign = otherModule.loadRig(wearableBytes, metadata);
    assert.throws(() => w.attachment.setRig(foreign), /another springbones module/);
    assert.equal(w.attachment.instance, instance);
    assert.equal(w.attachment.rig, rig);
    assert.equal(group.scene.slotOf(instance), 0);
    assert.equal(group.scene.size, 1);
    group.update(DT);
    group.dispose();
    w.attachment.dispose();
    foreign.dispose();
  });
});

// The measurement runs in child processes (three_adapter_allocation.mjs), each in one V8 tier
// fixed by its flags, so that what it reads depends on the code alone and never on the machine's
// speed or load (a tier-up finishing late on a loaded machine once made this test fail by chance):
//   baseline   the optimizing compilers off: nothing is escape-analysed away, so any temporary
//              of the adapter shows; floats are boxed here, so the frame is compared with a
//              reference frame that makes the same step calls and reads the same floats;
//   optimized  TurboFan as usual but compiling on the main thread (--single-threaded), so it
//              tiers up at the same frame on any machine: the frame must allocate nothing.
// Each child's new space is large enough that no scavenge falls inside a window, and the new
// space's used size grows by exactly what the window allocated.
const CHILD = fileURLToPath(new URL('./three_adapter_allocation.mjs', import.meta.url));
const HEAP_FLAGS = ['--expose-gc', '--min-semi-space-size=64', '--max-semi-space-size=64'];
const TIERS = { baseline: ['--no-opt', '--no-maglev'], optimized: ['--single-threaded'] };
// The smallest heap object is 16 bytes (a heap number), a JavaScript object 24: one per frame
// is at least twice these bounds. The measurement itself costs 0.5 bytes per frame.
const BOUND_BYTES_PER_FRAME = 8;

function measureAllocation(tier) {
  const { stdout } = spawnSync(process.execPath, [...HEAP_FLAGS, ...TIERS[tier], CHILD], { encoding: 'utf8', maxBuffer: 1 << 20 });
  const line = stdout.trim().split('\n').pop();
  assert.ok(line?.startsWith('{'), `${tier} child printed no result: ${stdout}`);
  return JSON.parse(line);
}

const middle = (xs) => [...xs].sort((a, b) => a - b)[xs.length >> 1];

test('attachment.update and group.update allocate nothing per frame, with the optimizing compiler off', () => {
  const { adapter, reference } = measureAllocation('baseline');
  assert.ok(middle(reference) > 1000, `the reference frame boxes its float reads (${reference} bytes per frame), so the tier is the baseline`);
  assert.ok(middle(adapter) - middle(reference) < BOUND_BYTES_PER_FRAME,
    `bytes per frame, adapter ${adapter.join(', ')} against the reference's ${reference.join(', ')}`);
});

test('attachment.update and group.update allocate nothing per frame, optimized', () => {
  const { adapter, reference } = measureAllocation('optimized');
  assert.ok(middle(reference) > 1000, `the reference frame's float reads into a variable allocate (${reference}), so allocations are seen`);
  assert.ok(middle(adapter) < BOUND_BYTES_PER_FRAME, `bytes per frame over each window: ${adapter.join(', ')}`);
});
