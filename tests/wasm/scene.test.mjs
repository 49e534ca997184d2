// sb.createScene: every instance stepped in one call, the nearest-N budget, the positions view,
// dispose semantics (an instance disposed while in a scene leaves it first) and no allocation.
import assert from 'node:assert/strict';
import { readFile } from 'node:fs/promises';
import { before, describe, test } from 'node:test';

import { createSpringBones, SpringBonesError } from '../../web/springbones.js';
import { swayDrivers } from '../../bin/sway.mjs';
import { loadFixtureRig, springRig } from './helpers.mjs';

let sb;
before(async () => {
  sb = await createSpringBones();
});

// Each avatar sways with its own phase, so the instances differ from each other.
function drive(instance, rest, k, phase) {
  swayDrivers(rest, instance.driverMatrices, k / 60 + phase);
}

function rigs() {
  const hair = loadFixtureRig(sb, 'avatar_hair.glb');
  const { glb, springBones, hash } = springRig({ chains: 3, joints: 4 });
  const small = sb.loadRig(glb, springBones, { contentHash: hash });
  return [hair, small];
}

describe('scene.step', () => {
  test('equals stepping each instance on its own, bit for bit', () => {
    const [hair, small] = rigs();
    const scene = sb.createScene();
    const pairs = [hair, small, hair].map((rig, i) => {
      const inScene = rig.createInstance();
      const alone = rig.createInstance();
      assert.equal(scene.add(inScene), i);
      return { inScene, alone, rest: Float32Array.from(alone.driverMatrices), phase: 0.37 * i };
    });
    assert.equal(scene.size, 3);
    for (let k = 1; k <= 300; ++k) {
      const dt = k % 41 === 0 ? 0.3 : 1 / 60;
      for (const p of pairs) {
        drive(p.inScene, p.rest, k, p.phase);
        drive(p.alone, p.rest, k, p.phase);
        p.alone.step(dt);
      }
      scene.step(dt);
      for (const p of pairs) assert.deepEqual(p.inScene.rotations, p.alone.rotations, `frame ${k}`);
    }
    assert.notDeepEqual(Float32Array.from(pairs[0].inScene.rotations), Float32Array.from(pairs[2].inScene.rotations));
    for (const p of pairs) assert.ok(scene.isActive(p.inScene));
    scene.dispose();
    for (const p of pairs) { p.inScene.dispose(); p.alone.dispose(); }
    hair.dispose();
    small.dispose();
  });

  test('adding twice keeps one slot; remove shifts the later slots down', () => {
    const [hair] = rigs();
    const scene = sb.createScene();
    const [a, b, c] = [0, 1, 2].map(() => hair.createInstance());
    for (const x of [a, b, c]) scene.add(x);
    assert.equal(scene.add(b), 1);
    assert.equal(scene.size, 3);
    scene.positions.set([1, 1, 1, 2, 2, 2, 3, 3, 3]);
    scene.remove(b);
    scene.remove(b);  // not in the scene any more: nothing happens
    assert.equal(scene.size, 2);
    assert.deepEqual(Array.from(scene.positions), [1, 1, 1, 3, 3, 3]);
    assert.equal(scene.slotOf(c), 1);
    assert.equal(scene.slotOf(b), -1);
    scene.step(1 / 60);
    assert.ok(!scene.isActive(b));
    scene.dispose();
    for (const x of [a, b, c, hair]) x.dispose();
  });
});

describe('budget', () => {
  test('only the nearest N step; the far ones hold their pose and start from rest when they come back', () => {
    const [hair] = rigs();
    const scene = sb.createScene();
    const members = [0, 1, 2].map(() => hair.createInstance());
    const rest = Float32Array.from(members[0].driverMatrices);
    members.forEach((m) => scene.add(m));
    // A reference for the instance that leaves and comes back: stepped alone, reset on return.
    const reference = hair.createInstance();
    scene.positions.set([1, 0, 0, 2, 0, 0, 10, 0, 0]);
    scene.setBudget(2, 0, 0, 0);
    let k = 0;
    const frame = (referenceSteps) => {
      ++k;
      for (const m of members) drive(m, rest, k, 0);
      drive(reference, rest, k, 0);
      if (referenceSteps) reference.step(1 / 60);
      scene.step(1 / 60);
    };
    assert.deepEqual(Array.from(scene.active), [1, 1, 1], 'every slot is active before a step');
    for (let i = 0; i < 30; ++i) frame(false);
    assert.deepEqual([scene.isActive(members[0]), scene.isActive(members[1]), scene.isActive(members[2])], [true, true, false]);
    assert.deepEqual(Array.from(scene.active), [1, 1, 0], 'the flags agree with isActive');
    // The far one never stepped: still the rest rotations.
    assert.deepEqual(members[2].rotations, reference.rotations);
    const held = Float32Array.from(members[1].rotations);

    // Swap: member 1 goes far, member 2 comes near.
    scene.positions.set([50, 0, 0], 3);
    scene.positions.set([0, 0, 0.5], 6);
    reference.reset();
    for (let i = 0; i < 30; ++i) frame(true);
    assert.deepEqual([scene.isActive(members[0]), scene.isActive(members[1]), scene.isActive(members[2])], [true, false, true]);
    assert.deepEqual(Array.from(scene.active), [1, 0, 1]);
    assert.deepEqual(members[1].rotations, held, 'the far one holds its last pose');
    assert.deepEqual(members[2].rotations, reference.rotations, 're-seeded: same as a reset instance stepped alone');

    // Member 1, which had moved before it left, comes back: it restarts from rest too.
    scene.positions.set([0.1, 0, 0], 3);
    scene.positions.set([100, 0, 0], 6);
    reference.reset();
    for (let i = 0; i < 30; ++i) frame(true);
    assert.deepEqual([scene.isActive(members[0]), scene.isActive(members[1]), scene.isActive(members[2])], [true, true, false]);
    assert.deepEqual(members[1].rotations, reference.rotations, 're-seeded on return');

    // No budget again: everyone steps.
    scene.setBudget(null);
    scene.step(1 / 60);
    assert.ok(members.every((m) => scene.isActive(m)));
    assert.ok(scene.isActive(members[2]));
    scene.dispose();
    for (const x of [...members, reference, hair]) x.dispose();
  });
});

describe('lastSteps', () => {
  test('says how many fixed steps the last frame ran, by the instance or its scene', () => {
    const [hair] = rigs();
    const alone = hair.createInstance();  // 60 Hz, at most 4 steps a frame
    const fast = hair.createInstance({ integrator: 'xpbd' });  // 120 Hz, at most 8
    assert.equal(alone.lastSteps, 0, 'before any frame');
    for (const [dt, steps, fastSteps] of [[1 / 60, 1, 2], [1 / 30, 2, 4], [1, 4, 8], [0, 0, 0], [1 / 240, 0, 0]]) {
      alone.step(dt);
      fast.step(dt);
      assert.deepEqual([alone.lastSteps, fast.lastSteps], [steps, fastSteps], `dt ${dt}`);
    }

    const scene = sb.createScene();
    const near = hair.createInstance(), far = hair.createInstance();
    scene.add(near);
    scene.add(far);
    scene.positions.set([1, 0, 0, 20, 0, 0]);
    scene.step(1 / 30);
    assert.deepEqual([near.lastSteps, far.lastSteps], [2, 2]);
    scene.setBudget(1, 0, 0, 0);
    scene.step(1 / 30);
    assert.deepEqual([near.lastSteps, far.lastSteps], [2, 0], 'the budget held the far one');
    scene.step(0);
    assert.deepEqual([near.lastSteps, far.lastSteps], [0, 0]);
    scene.dispose();
    for (const x of [alone, fast, near, far, hair]) x.dispose();
    assert.throws(() => alone.lastSteps, (e) => e instanceof SpringBonesError && e.code === 'disposed');
  });
});

describe('memory and lifetime', () => {
  test('10,000 scene steps allocate nothing: heap, handles and the positions view are stable', () => {
    const [hair, small] = rigs();
    const scene = sb.createScene();
    // Both integrators, and the world matrices read every frame (computed on request).
    const members = [hair, small, hair, small].map((rig, i) => rig.createInstance({ integrator: i % 2 ? 'xpbd' : 'vrm' }));
    const rests = members.map((m) => Float32Array.from(m.driverMatrices));
    members.forEach((m) => scene.add(m));
    scene.setBudget(3, 0, 0, 0);
    const positions = scene.positions;
    let checksum = 0;
    const frame = (k) => {
      members.forEach((m, i) => drive(m, rests[i], k, 0.1 * i));
      scene.positions[3 * (k % 4)] = (k % 13) - 6;  // the set of nearest changes now and then
      scene.step(k % 97 === 0 ? 0.5 : 1 / 60);
      checksum += members[k % 4].worldMatrices[12];
    };
    for (let k = 1; k <= 100; ++k) frame(k);
    const before = sb.stats();
    for (let k = 101; k <= 10100; ++k) frame(k);
    assert.deepEqual(sb.stats(), before);
    assert.equal(scene.positions, positions, 'the same view object while memory does not grow');
    assert.ok(members.every((m) => m.rotations.every(Number.isFinite)));
    assert.ok(Number.isFinite(checksum));
    scene.dispose();
    for (const x of [...members, hair, small]) x.dispose();
  });

  test('disposing an instance takes it out of its scenes first', () => {
    const [hair] = rigs();
    const sceneA = sb.createScene();
    const sceneB = sb.createScene();
    const [a, b] = [hair.createInstance(), hair.createInstance()];
    for (const s of [sceneA, sceneB]) { s.add(a); s.add(b); }
    sceneA.positions.set([1, 2, 3, 4, 5, 6]);
    a.dispose();
    for (const s of [sceneA, sceneB]) {
      assert.equal(s.size, 1);
      assert.equal(s.slotOf(b), 0);
      s.step(1 / 60);  // steps only b; a's memory is gone
    }
    assert.deepEqual(Array.from(sceneA.positions), [4, 5, 6]);
    assert.throws(() => sceneA.add(a), (e) => e instanceof SpringBonesError && e.code === 'disposed');
    assert.ok(b.rotations.every(Number.isFinite));
    sceneA.dispose();
    sceneB.dispose();
    b.dispose();
    hair.dispose();
  });

  test('disposing a scene leaves its instances working; use after dispose throws; nothing leaks', () => {
    const [hair] = rigs();
    hair.createInstance().dispose();
    const before = sb.stats();
    const scene = sb.createScene();
    const a = hair.createInstance();
    scene.add(a);
    scene.dispose();
    scene.dispose();  // idempotent
    assert.ok(scene.disposed);
    a.step(1 / 60);
    for (const use of [() => scene.step(1 / 60), () => scene.positions, () => scene.add(a), () => scene.setBudget(1), () => scene.isActive(a)]) {
      assert.throws(use, (e) => e instanceof SpringBonesError && e.code === 'disposed');
    }
    a.dispose();
    assert.deepEqual(sb.stats(), before);
    hair.dispose();
  });

  test('the active view follows add and remove and is rebuilt after memory growth', () => {
    const [hair] = rigs();
    const scene = sb.createScene();
    const [a, b, c] = [0, 1, 2].map(() => hair.createInstance());
    assert.equal(scene.active.length, 0);
    for (const x of [a, b, c]) scene.add(x);
    scene.positions.set([0, 0, 0, 5, 0, 0, 1, 0, 0]);
    scene.setBudget(1, 0, 0, 0);
    scene.step(1 / 60);
    assert.deepEqual(Array.from(scene.active), [1, 0, 0]);
    scene.remove(a);  // b and c shift down; the flags go with them
    assert.deepEqual(Array.from(scene.active), [0, 0]);
    scene.step(1 / 60);
    assert.deepEqual(Array.from(scene.active), [0, 1], 'c (at x = 1) is now the nearest');
    const old = scene.active;
    const bytes = new Uint8Array(sb.stats().heapBytes + (8 << 20));
    sb.contentHash(bytes);  // grows the memory
    assert.equal(old.byteLength, 0, 'the old view is detached');
    assert.deepEqual(Array.from(scene.active), [0, 1]);
    scene.dispose();
    assert.throws(() => scene.active, (e) => e instanceof SpringBonesError && e.code === 'disposed');
    for (const x of [a, b, c, hair]) x.dispose();
  });

  test('the positions view is rebuilt after memory growth, with its contents', () => {
    const [hair] = rigs();
    const scene = sb.createScene();
    const a = hair.createInstance();
    scene.add(a);
    scene.positions.set([7, 8, 9]);
    a.step(1 / 60);
    const world = Float32Array.from(a.worldMatrices);
    const old = scene.positions;
    const bytes = new Uint8Array(sb.stats().heapBytes + (8 << 20));
    sb.contentHash(bytes);  // copies the bytes into WASM memory, which grows it
    assert.equal(old.byteLength, 0, 'the old view is detached');
    assert.deepEqual(Array.from(scene.positions), [7, 8, 9]);
    assert.deepEqual(a.worldMatrices, world, 'the world matrices view is rebuilt too');
    scene.dispose();
    a.dispose();
    hair.dispose();
  });
});

describe('argument checks', () => {
  test('TypeError / RangeError before crossing; the scene keeps working', async () => {
    const [hair] = rigs();
    const scene = sb.createScene();
    const a = hair.createInstance();
    const before = sb.stats();
    for (const bad of [undefined, null, {}, hair, scene]) assert.throws(() => scene.add(bad), TypeError);
    const other = await createSpringBones({ wasmBinary: await readFile(new URL('../../web/dist/springbones_wasm.wasm', import.meta.url)) });
    const { glb, springBones, hash } = springRig();
    const foreign = other.loadRig(glb, springBones, { contentHash: hash }).createInstance();
    assert.throws(() => scene.add(foreign), TypeError);
    for (const [type, args] of [[TypeError, ['2']], [RangeError, [-1]], [RangeError, [1.5]], [RangeError, [NaN]],
      [TypeError, [2, '0']], [RangeError, [2, 0, Infinity]], [RangeError, [2, 0, 0, NaN]]]) {
      assert.throws(() => scene.setBudget(...args), (e) => e instanceof type && !(e instanceof SpringBonesError), String(args));
    }
    for (const [type, dt] of [[TypeError, '0.016'], [TypeError, undefined], [RangeError, NaN], [RangeError, -Infinity]]) {
      assert.throws(() => scene.step(dt), type);
    }
    assert.deepEqual(sb.stats(), before);
    scene.add(a);
    scene.setBudget(Infinity);
    scene.step(1 / 60);
    assert.ok(scene.isActive(a));
    scene.dispose();
    a.dispose();
    hair.dispose();
  });
});
