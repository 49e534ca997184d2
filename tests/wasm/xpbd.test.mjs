// integrator: 'xpbd' through the JS API: its defaults (120 Hz, 8 substeps), bone lengths that stay
// exact under violent driving, finite unit quaternions, and the option checks.
import assert from 'node:assert/strict';
import { before, describe, test } from 'node:test';

import { createSpringBones } from '../../web/springbones.js';
import { swayDrivers } from '../../bin/sway.mjs';
import { loadFixtureRig, springRig } from './helpers.mjs';

let sb;
before(async () => {
  sb = await createSpringBones();
});

/** Rotations after `frames` frames of sway, each frame's dt from dtOf(k). */
function run(rig, options, frames, dtOf = () => 1 / 60) {
  const instance = rig.createInstance(options);
  const rest = Float32Array.from(instance.driverMatrices);
  for (let k = 1; k <= frames; ++k) {
    swayDrivers(rest, instance.driverMatrices, k / 60);
    instance.step(dtOf(k));
  }
  const rotations = Float32Array.from(instance.rotations);
  instance.dispose();
  return rotations;
}

function assertUnitQuaternions(rotations, label) {
  for (let i = 0; i < rotations.length; i += 4) {
    const q = rotations.subarray(i, i + 4);
    assert.ok(q.every(Number.isFinite), `${label}: joint ${i / 4} not finite`);
    assert.ok(Math.abs(Math.hypot(...q) - 1) < 1e-5, `${label}: joint ${i / 4} not unit`);
  }
}

describe('integrator xpbd', () => {
  test('without stepHz / maxSubsteps it runs at 120 Hz with up to 8 substeps', () => {
    const rig = loadFixtureRig(sb, 'avatar_hair.glb');
    const hitchy = (k) => (k % 7 === 0 ? 0.2 : 1 / 30);  // 0.2 s needs 24 substeps: the cap shows
    const defaults = run(rig, { integrator: 'xpbd' }, 60, hitchy);
    assert.deepEqual(defaults, run(rig, { integrator: 'xpbd', stepHz: 120, maxSubsteps: 8 }, 60, hitchy));
    assert.notDeepEqual(defaults, run(rig, { integrator: 'xpbd', stepHz: 60, maxSubsteps: 8 }, 60, hitchy));
    assert.notDeepEqual(defaults, run(rig, { integrator: 'xpbd', stepHz: 120, maxSubsteps: 4 }, 60, hitchy));
    // And it is another integrator than the default one at the same rate.
    assert.notDeepEqual(defaults, run(rig, { integrator: 'vrm', stepHz: 120, maxSubsteps: 8 }, 60, hitchy));
    // Explicit values still win; xpbdIterations is accepted.
    assertUnitQuaternions(run(rig, { integrator: 'xpbd', stepHz: 240, maxSubsteps: 16, xpbdIterations: 1 }, 60, hitchy), 'explicit');
    rig.dispose();
  });

  test('bone lengths stay at their rest lengths under aggressive parameters, 30 fps and frame spikes', () => {
    const { glb, springBones, hash } = springRig({ chains: 4, joints: 6, params: { stiffness: 4, gravityPower: 2, drag: 0 } });
    const rig = sb.loadRig(glb, springBones, { contentHash: hash });
    const instance = rig.createInstance({ integrator: 'xpbd' });
    const drivers = instance.driverMatrices;
    const rest = Float32Array.from(drivers);
    const restHeads = Float32Array.from(instance.worldMatrices);
    let worst = 0;
    let moved = 0;
    for (let k = 1; k <= 600; ++k) {
      swayDrivers(rest, drivers, k / 30);
      drivers[12] = rest[12] + 0.3 * Math.sin(k);  // jerks of up to 30 cm between frames
      instance.step(k % 50 === 0 ? 0.5 : 1 / 30);
      const world = instance.worldMatrices;
      rig.joints.forEach((joint, j) => {
        if (joint.parent < 0) return;
        const p = 16 * joint.parent;
        const c = 16 * j;
        const length = Math.hypot(world[c + 12] - world[p + 12], world[c + 13] - world[p + 13], world[c + 14] - world[p + 14]);
        worst = Math.max(worst, Math.abs(length - rig.joints[joint.parent].restLength) / rig.joints[joint.parent].restLength);
        moved = Math.max(moved, Math.abs(world[c + 12] - restHeads[c + 12]));
      });
      assertUnitQuaternions(instance.rotations, `frame ${k}`);
    }
    assert.ok(worst < 1e-4, `worst relative bone-length error ${worst}`);
    assert.ok(moved > 0.05, 'the chains did move');
    instance.dispose();
    rig.dispose();
  });
});
