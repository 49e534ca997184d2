// Wind through the JS API: instance.setWind and scene.setWind, off by default, deterministic for a
// seed on both integrators (the same bits alone and in a scene), and the argument checks (TypeError
// and RangeError before anything crosses into WebAssembly).
import assert from 'node:assert/strict';
import { describe, test } from 'node:test';

import { createSpringBones } from '../../web/springbones.js';
import { springRig } from './helpers.mjs';

const sb = await createSpringBones();
const chain = springRig({ chains: 2, joints: 3 });
const rig = sb.loadRig(chain.glb, chain.springBones, { contentHash: chain.hash });
const gusty = { direction: [1, 0, 0], strength: 1, gustFrequency: 1.5, seed: 7 };

function run(instance, frames = 120) {
  for (let f = 0; f < frames; f++) instance.step(1 / 60);
  return Float32Array.from(instance.rotations);
}

const same = (a, b) => a.length === b.length && a.every((v, i) => Object.is(v, b[i]));

for (const integrator of ['vrm', 'xpbd']) {
  describe(`${integrator}`, () => {
    test('off by default: a null wind and a zero one change no bit', () => {
      const plain = rig.createInstance({ integrator });
      const off = rig.createInstance({ integrator });
      const zero = rig.createInstance({ integrator });
      off.setWind(null);
      zero.setWind({ direction: [0, 0, 0], strength: 0 });
      const expected = run(plain);
      assert.ok(same(run(off), expected));
      assert.ok(same(run(zero), expected));
      for (const i of [plain, off, zero]) i.dispose();
    });

    test('the same seed gives the same bits, another seed other motion, and the chain leans downwind', () => {
      const [a, b, c, still] = [0, 1, 2, 3].map(() => rig.createInstance({ integrator }));
      a.setWind(gusty);
      b.setWind(gusty);
      c.setWind({ ...gusty, seed: 8 });
      const ra = run(a), rb = run(b), rc = run(c);
      run(still);
      assert.ok(same(ra, rb));
      assert.ok(!same(ra, rc));
      // The last joint of the first chain: its world x moved toward +x.
      const x = (instance) => instance.worldMatrices[16 * 2 + 12];
      assert.ok(x(a) > x(still) + 0.005, `${x(a)} vs ${x(still)}`);
      for (const i of [a, b, c, still]) i.dispose();
    });

    test("a scene's wind reaches its instances and later ones, with the same bits as alone", () => {
      const scene = sb.createScene();
      const inScene = rig.createInstance({ integrator });
      const lateInScene = rig.createInstance({ integrator });
      const alone = rig.createInstance({ integrator });
      scene.add(inScene);
      scene.setWind(gusty);
      scene.add(lateInScene);
      alone.setWind(gusty);
      for (let f = 0; f < 120; f++) {
        scene.step(1 / 60);
        alone.step(1 / 60);
      }
      assert.ok(same(inScene.rotations, alone.rotations));
      assert.ok(same(lateInScene.rotations, alone.rotations));
      for (const x of [scene, inScene, lateInScene, alone]) x.dispose();
    });
  });
}

describe('argument checks', () => {
  const instance = rig.createInstance();
  const scene = sb.createScene();
  const bad = [
    [TypeError, undefined],
    [TypeError, 5],
    [TypeError, [1, 0, 0]],
    [TypeError, { direction: [1, 0], strength: 1 }],
    [TypeError, { direction: [1, 0, 0], strength: '1' }],
    [TypeError, { direction: [1, 0, 0], strength: 1, speed: 2 }],  // unknown key
    [RangeError, { direction: [NaN, 0, 0], strength: 1 }],
    [RangeError, { direction: [1, 0, Infinity], strength: 1 }],
    [RangeError, { direction: [0, 0, 0], strength: 1 }],
    [RangeError, { direction: [1, 0, 0], strength: NaN }],
    [RangeError, { direction: [1, 0, 0], strength: -1 }],
    [RangeError, { direction: [1, 0, 0], strength: 1e9 }],
    [RangeError, { direction: [1, 0, 0], strength: 1, gustFrequency: 11 }],
    [RangeError, { direction: [1, 0, 0], strength: 1, gustFrequency: -0.5 }],
    [RangeError, { direction: [1, 0, 0], strength: 1, seed: 1.5 }],
    [RangeError, { direction: [1, 0, 0], strength: 1, seed: -1 }],
    [RangeError, { direction: [1, 0, 0], strength: 1, seed: 2 ** 32 }],
  ];
  for (const [type, wind] of bad) {
    test(`${type.name} for ${JSON.stringify(wind) ?? 'undefined'}`, () => {
      assert.throws(() => instance.setWind(wind), type);
      assert.throws(() => scene.setWind(wind), type);
    });
  }

  test('the limits: strength 10, gusts 10 per second, seeds up to 2^32 - 1', () => {
    instance.setWind({ direction: [0, 0, -3], strength: 10, gustFrequency: 10, seed: 2 ** 32 - 1 });
    assert.ok(run(instance, 600).every(Number.isFinite));
  });

  test('a disposed instance or scene is a disposed error', () => {
    const gone = rig.createInstance();
    gone.dispose();
    assert.throws(() => gone.setWind(gusty), { code: 'disposed' });
    const goneScene = sb.createScene();
    goneScene.dispose();
    assert.throws(() => goneScene.setWind(gusty), { code: 'disposed' });
  });
});
