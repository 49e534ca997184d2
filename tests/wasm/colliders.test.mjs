// Colliders through loadRig's options: spheres, capsules and planes, outside or inside, on named
// nodes (GLB nodes or avatar bones the GLB does not have, which become drivers the caller moves),
// the joint hit radius, and the argument checks.
import assert from 'node:assert/strict';
import { before, describe, test } from 'node:test';

import { createSpringBones, SpringBonesError } from '../../web/springbones.js';
import { springRig, tailPositions } from './helpers.mjs';

let sb;
before(async () => {
  sb = await createSpringBones();
});

// One chain of three 5 cm bones hanging from Avatar_Head (at y 1.6) at z 0.05: the tails rest at
// y 1.55, 1.50 and 1.45.
const chain = springRig({ chains: 1, joints: 3 });
const kRadius = 0.03;
const kHit = 0.01;

function load(options) {
  return sb.loadRig(chain.glb, chain.springBones, { contentHash: chain.hash, ...options });
}

const distance = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
function distanceToSegment(p, a, b) {
  const ab = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
  const t = Math.max(0, Math.min(1, ((p[0] - a[0]) * ab[0] + (p[1] - a[1]) * ab[1] + (p[2] - a[2]) * ab[2]) / (ab[0] ** 2 + ab[1] ** 2 + ab[2] ** 2)));
  return distance(p, [a[0] + t * ab[0], a[1] + t * ab[1], a[2] + t * ab[2]]);
}

function settle(instance, frames = 120) {
  for (let k = 0; k < frames; ++k) instance.step(1 / 60);
}

describe('pushing a chain out', () => {
  // Centred 1 cm beside the middle tail: without the collider that tail sits inside the sphere.
  const head = [0, 1.6, 0];
  const offset = [0.01, -0.1, 0.05];
  const center = [head[0] + offset[0], head[1] + offset[1], head[2] + offset[2]];

  test('a head sphere: every tail ends outside radius + hitRadius (the length constraint may give back a little)', () => {
    const plain = load();
    const free = plain.createInstance();
    settle(free);
    assert.ok(distance(tailPositions(plain, free)[1], center) < 0.011, 'without colliders the tail stays inside');

    const rig = load({ colliders: [{ node: 'Avatar_Head', offset, radius: kRadius }], hitRadius: kHit });
    assert.deepEqual(rig.colliders, [{ driver: 0, node: 'Avatar_Head', shape: 'sphere', inside: false, offset, radius: kRadius }]);
    assert.ok(rig.joints.every((j) => j.hitRadius === kHit));
    const pushed = rig.createInstance();
    settle(pushed);
    const after = tailPositions(rig, pushed);
    for (const [i, tail] of after.entries()) {
      assert.ok(distance(tail, center) > 0.95 * (kRadius + kHit), `tail ${i} at ${distance(tail, center)}`);
    }
    assert.ok(after[1][0] < -0.02, 'pushed away from the side the centre is on');
    assert.ok(pushed.rotations.every(Number.isFinite));
    for (const x of [free, pushed, plain, rig]) x.dispose();
  });

  test('a capsule across the chain, 1 cm in front of it, pushes the tails back', () => {
    const start = [-0.1, -0.1, 0.06];
    const end = [0.1, -0.1, 0.06];
    const rig = load({ colliders: [{ node: 'Avatar_Head', offset: start, tail: end, radius: kRadius }], hitRadius: kHit });
    assert.equal(rig.colliders[0].shape, 'capsule');
    assert.deepEqual(rig.colliders[0].tail, end);
    const instance = rig.createInstance();
    settle(instance);
    const world = (p) => [head[0] + p[0], head[1] + p[1], head[2] + p[2]];
    for (const [i, tail] of tailPositions(rig, instance).entries()) {
      assert.ok(distanceToSegment(tail, world(start), world(end)) > 0.95 * (kRadius + kHit), `tail ${i}`);
    }
    assert.ok(tailPositions(rig, instance)[1][2] < 0.03, 'pushed towards -z');
    instance.dispose();
    rig.dispose();
  });

  test('a collider on an avatar bone the GLB lacks becomes a driver the caller moves', () => {
    const rig = load({ colliders: [{ node: 'Avatar_Chest', radius: kRadius }], hitRadius: kHit });
    assert.deepEqual(rig.drivers, [{ name: 'Avatar_Head', node: 0 }, { name: 'Avatar_Chest', node: -1 }]);
    assert.deepEqual(rig.colliders, [{ driver: 1, node: 'Avatar_Chest', shape: 'sphere', inside: false, offset: [0, 0, 0], radius: kRadius }]);
    assert.equal(rig.warnings.length, 0);
    const instance = rig.createInstance();
    const chest = instance.driverMatrices.subarray(16, 32);
    const rest = tailPositions(rig, instance);
    // Far away: the chain hangs as at rest.
    chest.set([1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 5, 0, 0, 1]);
    settle(instance, 30);
    tailPositions(rig, instance).forEach((t, i) => assert.ok(distance(t, rest[i]) < 1e-5, `tail ${i}`));
    // Moved next to the middle tail: it pushes.
    chest.set([0.01, 1.5, 0.05], 12);
    settle(instance);
    assert.ok(distance(tailPositions(rig, instance)[1], [0.01, 1.5, 0.05]) > 0.95 * (kRadius + kHit));
    instance.dispose();
    rig.dispose();
  });

  test('the XPBD integrator honours the same colliders', () => {
    const rig = load({ colliders: [{ node: 'Avatar_Head', offset, radius: kRadius }], hitRadius: kHit });
    const instance = rig.createInstance({ integrator: 'xpbd' });
    settle(instance);
    for (const tail of tailPositions(rig, instance)) assert.ok(distance(tail, center) > 0.95 * (kRadius + kHit));
    instance.dispose();
    rig.dispose();
  });
});

describe('extended shapes: inside sphere, inside capsule, plane', () => {
  // Each shape beside the chain (tails at rest at x 0, z 0.05, y 1.55 / 1.50 / 1.45) so that
  // some rest tail is on its forbidden side; `allowed(tail)` is how far a tail is on the allowed
  // side (world), `kHit` included.
  const head = [0, 1.6, 0];
  const world = (p) => [head[0] + p[0], head[1] + p[1], head[2] + p[2]];
  const shapes = [
    {
      name: 'inside sphere',
      collider: { node: 'Avatar_Head', shape: 'sphere', inside: true, offset: [0.03, -0.07, 0.05], radius: 0.06 },
      allowed: (t) => 0.06 - kHit - distance(t, world([0.03, -0.07, 0.05])),
    },
    {
      name: 'inside capsule',
      collider: { node: 'Avatar_Head', inside: true, offset: [0.04, 0, 0.05], tail: [0.04, -0.2, 0.05], radius: 0.04 },
      allowed: (t) => 0.04 - kHit - distanceToSegment(t, world([0.04, 0, 0.05]), world([0.04, -0.2, 0.05])),
    },
    {
      name: 'plane',
      collider: { node: 'Avatar_Head', shape: 'plane', offset: [0.02, 0, 0], normal: [2, 0, 0] },
      allowed: (t) => t[0] - (0.02 + kHit),
    },
  ];

  for (const shape of shapes) {
    test(`${shape.name}: rest tails are on its forbidden side; both integrators bring them back`, () => {
      const plain = load();
      const free = plain.createInstance();
      settle(free);
      const without = Math.min(...tailPositions(plain, free).map(shape.allowed));
      assert.ok(without < -0.005, `without it a tail is on the forbidden side (${without})`);
      const rig = load({ colliders: [shape.collider], hitRadius: kHit });
      for (const integrator of ['vrm', 'xpbd']) {
        const instance = rig.createInstance({ integrator });
        settle(instance);
        // Each step's stiffness pulls toward the rest pose again and the length constraint after
        // the move gives back some of it, so a tail may stay a little on the forbidden side: here
        // under a centimetre, and at most a third of the way it is without the shape.
        const withShape = Math.min(...tailPositions(rig, instance).map(shape.allowed));
        assert.ok(withShape > -0.01 && withShape > without / 3, `${integrator}: ${withShape} (without the shape ${without})`);
        assert.ok(instance.rotations.every(Number.isFinite));
        instance.dispose();
      }
      for (const x of [free, plain, rig]) x.dispose();
    });
  }

  test('rig.colliders reports shape, inside, a plane\'s unit normal and radius 0', () => {
    const rig = load({ colliders: shapes.map((s) => s.collider), hitRadius: kHit });
    assert.deepEqual(rig.colliders, [
      { driver: 0, node: 'Avatar_Head', shape: 'sphere', inside: true, offset: [0.03, -0.07, 0.05], radius: 0.06 },
      { driver: 0, node: 'Avatar_Head', shape: 'capsule', inside: true, offset: [0.04, 0, 0.05], tail: [0.04, -0.2, 0.05], radius: 0.04 },
      { driver: 0, node: 'Avatar_Head', shape: 'plane', inside: false, offset: [0.02, 0, 0], normal: [1, 0, 0], radius: 0 },
    ]);
    assert.deepEqual(rig.warnings, []);
    rig.dispose();
  });

  test('a capsule named by shape needs no tail; inside: false is an outside shape', () => {
    const rig = load({ colliders: [{ node: 'Avatar_Head', shape: 'capsule', radius: 0.1 }, { node: 'Avatar_Head', radius: 0.1, inside: false }] });
    assert.deepEqual(rig.colliders.map((c) => [c.shape, c.tail, c.inside]), [['capsule', [0, 0, 0], false], ['sphere', undefined, false]]);
    rig.dispose();
  });
});

describe('argument checks', () => {
  function expectBeforeCrossing(type, options) {
    const before = sb.stats();
    assert.throws(() => load(options), (e) => e instanceof type && !(e instanceof SpringBonesError), JSON.stringify(options));
    assert.deepEqual(sb.stats(), before);
  }

  test('bad colliders and hit radii are TypeError / RangeError before crossing; the module keeps working', () => {
    const ok = { node: 'Avatar_Head', offset: [0, 0, 0], radius: 0.1 };
    for (const [type, options] of [
      [TypeError, { colliders: ok }], [RangeError, { colliders: 'head' }], [TypeError, { colliders: 7 }], [TypeError, { colliders: [null] }],
      [TypeError, { colliders: [{ ...ok, node: undefined }] }], [TypeError, { colliders: [{ ...ok, node: 3 }] }],
      [RangeError, { colliders: [{ ...ok, node: '' }] }], [TypeError, { colliders: [{ ...ok, offset: [0, 0] }] }],
      [TypeError, { colliders: [{ ...ok, offset: [0, '0', 0] }] }], [RangeError, { colliders: [{ ...ok, offset: [0, NaN, 0] }] }],
      [TypeError, { colliders: [{ ...ok, radius: undefined }] }], [RangeError, { colliders: [{ ...ok, radius: -0.1 }] }],
      [RangeError, { colliders: [{ ...ok, radius: Infinity }] }], [TypeError, { colliders: [{ ...ok, tail: 1 }] }],
      [RangeError, { colliders: [{ ...ok, tail: [0, 0, -Infinity] }] }], [RangeError, { colliders: [{ ...ok, shape: 'box' }] }],
      [TypeError, { colliders: [{ ...ok, shape: 2 }] }], [TypeError, { colliders: [{ ...ok, shape: 'sphere', tail: [0, 1, 0] }] }],
      [TypeError, { colliders: [{ ...ok, normal: [0, 1, 0] }] }], [TypeError, { colliders: [{ ...ok, inside: 'yes' }] }],
      [TypeError, { colliders: [{ node: 'Avatar_Head', shape: 'plane', radius: 0.1 }] }],
      [TypeError, { colliders: [{ node: 'Avatar_Head', shape: 'plane', inside: true }] }],
      [TypeError, { colliders: [{ node: 'Avatar_Head', shape: 'plane', tail: [0, 1, 0] }] }],
      [RangeError, { colliders: [{ node: 'Avatar_Head', shape: 'plane', normal: [0, 0, 0] }] }],
      [RangeError, { colliders: [{ node: 'Avatar_Head', shape: 'plane', normal: [0, NaN, 1] }] }],
      [TypeError, { colliders: [{ node: 'Avatar_Head', shape: 'plane', normal: [0, 1] }] }],
      [TypeError, { colliders: [{ node: 'Avatar_Head', shape: 'capsule', tail: [0, 1, 0] }] }],
      [TypeError, { hitRadius: '0.1' }], [RangeError, { hitRadius: -1 }], [RangeError, { hitRadius: NaN }],
    ]) {
      expectBeforeCrossing(type, options);
    }
    const rig = load({ colliders: [ok, { ...ok, tail: new Float32Array([0, 1, 0]) }], hitRadius: 0 });
    assert.equal(rig.colliders.length, 2);
    assert.ok(Object.isFrozen(rig.colliders) && Object.isFrozen(rig.colliders[0].offset));
    rig.dispose();
  });

  test('a collider on a spring bone is ignored with a warning', () => {
    const rig = load({ colliders: [{ node: 'SpringBone_0_1', radius: 0.1 }] });
    assert.equal(rig.colliders.length, 0);
    assert.ok(rig.warnings.some((w) => w.code === 'collider-on-spring-bone'));
    rig.dispose();
  });
});
