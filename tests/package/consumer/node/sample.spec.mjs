// A Node project's headless test, as a user writes it: the installed package, no options to
// createSpringBones, the sample wearable stepped under a moving head.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { fileURLToPath } from 'node:url';
import { test } from 'node:test';
import { createSpringBones } from 'springbones';

const asset = (name) => new URL(`../assets/${name}`, import.meta.url);
const installed = createRequire(import.meta.url)('springbones/package.json');

test('springbones resolves to the installed package, not a checkout', () => {
  const entry = fileURLToPath(import.meta.resolve('springbones'));
  assert.ok(entry.endsWith('/node_modules/springbones/web/dist/springbones.min.js'), entry);
  assert.equal(fileURLToPath(import.meta.resolve('springbones/wasm')),
      entry.replace(/springbones\.min\.js$/, 'springbones_wasm.wasm'));
});

test('loads the sample wearable, steps and reads rotations', async () => {
  const sb = await createSpringBones();
  assert.equal(sb.version, installed.version);
  const glb = new Uint8Array(readFileSync(asset('hair_wearable.glb')));
  const springBones = JSON.parse(readFileSync(asset('hair_wearable.metadata.json'), 'utf8'));
  const rig = sb.loadRig(glb, springBones);
  assert.equal(rig.contentHash, Object.keys(springBones.models)[0]);
  assert.deepEqual(rig.warnings, []);
  assert.equal(rig.joints.length, 15);
  const head = rig.drivers.findIndex((d) => d.name === 'Avatar_Head');
  assert.ok(head >= 0, 'the head drives the hair');

  const instance = rig.createInstance();
  const rest = instance.rotations.slice();
  for (let frame = 1; frame <= 60; frame++) {
    instance.driverMatrices[16 * head + 12] += 0.01;  // the head moves sideways, 0.6 m per second
    instance.step(1 / 60);
  }
  const rotations = instance.rotations;
  assert.equal(rotations.length, 4 * rig.joints.length);
  let moved = 0;
  for (let j = 0; j < rig.joints.length; j++) {
    const q = rotations.subarray(4 * j, 4 * j + 4);
    assert.ok(q.every(Number.isFinite), `joint ${j} is finite`);
    assert.ok(Math.abs(Math.hypot(...q) - 1) < 1e-5, `joint ${j} is a unit quaternion`);
    for (let k = 0; k < 4; k++) moved = Math.max(moved, Math.abs(q[k] - rest[4 * j + k]));
  }
  assert.ok(moved > 0.05, `the hair swings: rotations moved by up to ${moved}`);
  instance.dispose();
  rig.dispose();
});

test('the crowd module ships: createSpringBones({ crowd: true }) steps the wearable to the same rotations', async () => {
  assert.equal(fileURLToPath(import.meta.resolve('springbones/crowd-wasm')),
      fileURLToPath(import.meta.resolve('springbones/wasm')).replace(/springbones_wasm\.wasm$/, 'springbones_crowd.wasm'));
  const glb = new Uint8Array(readFileSync(asset('hair_wearable.glb')));
  const springBones = JSON.parse(readFileSync(asset('hair_wearable.metadata.json'), 'utf8'));
  const [runtime, crowd] = await Promise.all([createSpringBones(), createSpringBones({ crowd: true })]);
  assert.deepEqual([runtime.crowd, crowd.crowd], [false, true]);
  const rigs = [runtime, crowd].map((sb) => sb.loadRig(glb, springBones));
  const head = rigs[0].drivers.findIndex((d) => d.name === 'Avatar_Head');
  const [a, b] = rigs.map((rig) => rig.createInstance());
  const rest = a.rotations.slice();
  for (let frame = 1; frame <= 60; frame++) {
    for (const instance of [a, b]) {
      instance.driverMatrices[16 * head + 12] += 0.01;
      instance.step(1 / 60);
    }
  }
  assert.notDeepEqual(a.rotations, rest, 'the hair swings');
  assert.deepEqual(b.rotations, a.rotations);
});
