// The two builds of the runtime (wasm/CMakeLists.txt): springbones_wasm.wasm, what a preview
// downloads, with its per-frame path at -Oz without SIMD; springbones_crowd.wasm, loaded by
// createSpringBones({ crowd: true }), with it at -O3 with SIMD. Whichever module runs a rig,
// instance or scene, it does the same thing: the same rotations and world matrices bit for bit, the
// same errors. The crowd module runs on the runtime's glue, so the two glues must be one text.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { before, describe, test } from 'node:test';

import { swayDrivers } from '../../bin/sway.mjs';
import { createSpringBones } from '../../web/springbones.js';
import { fixture, loadFixtureRig, root, springRig } from './helpers.mjs';

const dist = join(root, 'web', 'dist');

let preview, crowd;
before(async () => {
  [preview, crowd] = await Promise.all([createSpringBones(), createSpringBones({ crowd: true })]);
});

test('createSpringBones loads the runtime by default and the crowd module with crowd: true', async () => {
  assert.equal(preview.crowd, false);
  assert.equal(crowd.crowd, true);
  assert.equal((await createSpringBones({ crowd: false })).crowd, false);
  const given = await createSpringBones({ crowd: true, wasmBinary: readFileSync(join(dist, 'springbones_wasm.wasm')) });
  assert.equal(given.crowd, false, 'a module given is the one that runs');
  await assert.rejects(createSpringBones({ crowd: 'yes' }), { name: 'TypeError', message: 'createSpringBones: crowd must be true or false' });
  await assert.rejects(createSpringBones({ crowd: true, wasmUrl: './does-not-exist.wasm' }),
    (e) => e.code === 'module-load-failed' && e.message.includes('does-not-exist.wasm'));
});

test('the inline entry fetches the crowd module (it inlines the runtime only)', async () => {
  const inline = await import('../../web/inline.js');
  assert.equal((await inline.createSpringBones()).crowd, false);
  assert.equal((await inline.createSpringBones({ crowd: true })).crowd, true);
});

test('the crowd module runs on the runtime\'s glue: the two glues differ in the .wasm file name only', () => {
  const glue = readFileSync(join(dist, 'springbones_wasm.js'), 'utf8');
  const crowdGlue = readFileSync(join(dist, 'springbones_crowd.js'), 'utf8');
  assert.ok(glue.includes('springbones_wasm.wasm'));
  assert.equal(crowdGlue.replaceAll('springbones_crowd.wasm', 'springbones_wasm.wasm'), glue);
});

// The rigs of the comparison in one module: the sample hair (loadRig, colliders), a small rig with
// three chains, and two VRM avatars (loadVrm, sphere and capsule colliders; VRM 0.x).
function rigsOf(sb) {
  const { glb, springBones, hash } = springRig({ chains: 3, joints: 4 });
  return [
    loadFixtureRig(sb, 'avatar_hair.glb'),
    sb.loadRig(glb, springBones, { contentHash: hash }),
    sb.loadVrm(fixture('vrm10_springs.vrm')),
    sb.loadVrm(fixture('vrm0_springs.vrm')),
  ];
}

const bytesOf = (view) => Buffer.from(view.buffer, view.byteOffset, view.byteLength);

describe('the same rotations bit for bit in the runtime and the crowd module', () => {
  test('a scene of 24 instances of four rigs, swaying with their own phases, with long frames and jumps', () => {
    const sides = [preview, crowd].map((sb) => {
      const rigs = rigsOf(sb);
      const scene = sb.createScene();
      const instances = [];
      for (let i = 0; i < 24; ++i) {
        const instance = rigs[i % rigs.length].createInstance();
        scene.add(instance);
        instances.push({ instance, rest: Float32Array.from(instance.driverMatrices), phase: 0.29 * i });
      }
      return { rigs, scene, instances };
    });
    for (let k = 1; k <= 240; ++k) {
      const dt = k % 53 === 0 ? 0.25 : 1 / 60;
      for (const { scene, instances } of sides) {
        for (const { instance, rest, phase } of instances) {
          swayDrivers(rest, instance.driverMatrices, k / 60 + phase);
          // A teleport of a few avatars now and then: the jump carry on both paths.
          if (k % 97 === 0 && phase < 2) instance.driverMatrices[12] += 3;
        }
        scene.step(dt);
      }
      sides[0].instances.forEach(({ instance }, i) => {
        const other = sides[1].instances[i].instance;
        assert.ok(bytesOf(instance.rotations).equals(bytesOf(other.rotations)), `frame ${k}, instance ${i}: rotations`);
      });
    }
    sides[0].instances.forEach(({ instance }, i) => {
      assert.ok(bytesOf(instance.worldMatrices).equals(bytesOf(sides[1].instances[i].instance.worldMatrices)), `instance ${i}: world matrices`);
    });
    const moved = sides[0].instances[0].instance.rotations.some((v, j) => v !== sides[0].instances[4].instance.rotations[j]);
    assert.ok(moved, 'the phases make the instances of one rig differ');
    for (const { rigs, scene, instances } of sides) {
      scene.dispose();
      for (const { instance } of instances) instance.dispose();
      for (const rig of rigs) rig.dispose();
    }
  });

  test('instances stepped alone, with settle and reset, and the same errors for bad input', () => {
    const results = [preview, crowd].map((sb) => {
      const [hair] = rigsOf(sb);
      const a = hair.createInstance(), b = hair.createInstance();
      const rest = Float32Array.from(a.driverMatrices);
      const frames = [];
      for (let k = 1; k <= 120; ++k) {
        swayDrivers(rest, a.driverMatrices, k / 60);
        swayDrivers(rest, b.driverMatrices, k / 45);
        a.step(1 / 60);
        b.step(1 / 60);
        if (k === 60) b.reset();
        frames.push(Buffer.concat([bytesOf(a.rotations), bytesOf(b.rotations)]));
      }
      const errors = [() => sb.loadRig(new Uint8Array(8)), () => a.step(Number.NaN)].map((call) => {
        try {
          call();
          return 'no error';
        } catch (e) {
          return `${e.name} ${e.code} ${e.path} ${e.message}`;
        }
      });
      return { frames, errors };
    });
    results[0].frames.forEach((frame, k) => assert.ok(frame.equals(results[1].frames[k]), `frame ${k + 1}`));
    assert.deepEqual(results[0].errors, results[1].errors);
  });
});
