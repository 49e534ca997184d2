// Determinism of the WebAssembly build: the scripted scenario of tests/native/determinism_test.cpp
// hashes to the same constant here, and repeated runs (same module, fresh module) agree bit for bit.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { test } from 'node:test';

import { createSpringBones } from '../../web/springbones.js';
import { fnv1a, loadFixtureRig, root, swayFrames } from './helpers.mjs';

// The scenario of tests/native/determinism_test.cpp (keep both in step): avatar_hair.glb with its
// metadata; for frame f = 1..600 every driver gets its rest matrix with the x translation plus
// tri(f) / 256 (tri(f) = f % 60 < 30 ? f % 60 : 60 - f % 60), then step(1/60); FNV-1a over the
// rotation floats after the last step. The constant is read from the native test itself, so the
// two suites cannot drift apart: when the solver changes it, both compare against the new value.
const kNativeTest = join(root, 'tests', 'native', 'determinism_test.cpp');
const kRecordedHash = Number.parseInt(
  /EXPECT_EQ\(hash, 0x([0-9a-fA-F]+)u\)/.exec(readFileSync(kNativeTest, 'utf8'))?.[1] ?? 'NaN', 16);

function runRecordedScenario(sb) {
  const rig = loadFixtureRig(sb, 'avatar_hair.glb');
  const inst = rig.createInstance();
  const rest = Float32Array.from(inst.driverMatrices);
  for (let f = 1; f <= 600; ++f) {
    const phase = f % 60;
    const offset = (phase < 30 ? phase : 60 - phase) / 256;
    const m = inst.driverMatrices;
    m.set(rest);
    for (let d = 0; d < rest.length; d += 16) m[d + 12] = rest[d + 12] + offset;
    inst.step(1 / 60);
  }
  const hash = fnv1a(inst.rotations);
  inst.dispose();
  rig.dispose();
  return hash;
}

function runSway(sb, frames, fps) {
  const rig = loadFixtureRig(sb, 'avatar_hair.glb');
  const inst = rig.createInstance();
  swayFrames(inst, frames, fps);
  const out = Float32Array.from(inst.rotations);
  inst.dispose();
  rig.dispose();
  return out;
}

test('the native determinism scenario hashes to the constant recorded in determinism_test.cpp', async () => {
  assert.ok(Number.isInteger(kRecordedHash), `no EXPECT_EQ(hash, 0x...u) in ${kNativeTest}`);
  const sb = await createSpringBones();
  const hash = runRecordedScenario(sb);
  assert.equal(hash, kRecordedHash, `hash 0x${hash.toString(16)}`);
});

test('the same inputs give the same bits: twice in one module, and in a fresh module', async () => {
  const a = await createSpringBones();
  const first = runSway(a, 500, 45);
  const second = runSway(a, 500, 45);
  const b = await createSpringBones();
  const third = runSway(b, 500, 45);
  assert.equal(fnv1a(first), fnv1a(second));
  assert.equal(fnv1a(first), fnv1a(third));
  assert.ok(first.some((v, i) => i % 4 !== 3 && v !== 0), 'something moved');
});
