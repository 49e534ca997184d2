// instance.carryFrom(previous) from JavaScript: an instance of the rig rebuilt with the same entry
// continues exactly where the previous one was (against that instance stepped on), an edited one
// keeps the untouched chains as they were; the argument checks. The rules: docs/semantics.md,
// "Editing a live rig"; the native tests cover the three paths (tests/native/carry_from_test.cpp).
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { before, test } from 'node:test';
import { SpringBonesError, createSpringBones } from '../../web/springbones.js';

const asset = (name) => readFileSync(new URL(`../../web/demo/assets/${name}`, import.meta.url));
const glb = asset('hair_wearable.glb');
const metadata = JSON.parse(asset('hair_wearable.metadata.json'));
const [hash] = Object.keys(metadata.models);
const entry = metadata.models[hash];

let sb;
before(async () => {
  sb = await createSpringBones();
});

/** Every driver at the head of an avatar swaying and turning, frame f. */
function drive(instance, f) {
  const m = instance.driverMatrices;
  const yaw = 0.5 * Math.sin(f * 0.11);
  for (let o = 0; o < m.length; o += 16) {
    m.set([Math.cos(yaw), 0, -Math.sin(yaw), 0, 0, 1, 0, 0, Math.sin(yaw), 0, Math.cos(yaw), 0,
      0.15 * Math.sin(f * 0.15), 1.6, 0, 1], o);
  }
}

const maxDifference = (a, b) => Math.max(...Array.from(a, (x, i) => Math.abs(x - b[i])));
const rotationsOf = (instance, rig, names) => names.map((name) => {
  const j = rig.joints.findIndex((joint) => joint.name === name);
  return Array.from(instance.rotations.subarray(4 * j, 4 * j + 4));
});

test('an instance of the rebuilt rig continues exactly where the previous one was', () => {
  const rig = sb.loadRig(glb, metadata);
  const old = rig.createInstance();
  for (let f = 0; f < 60; f++) {
    drive(old, f);
    old.step(1 / 60);
  }
  const rebuilt = sb.loadRig(glb, metadata);
  const next = rebuilt.createInstance();
  drive(next, 59);
  next.carryFrom(old);
  assert.deepEqual(Array.from(next.rotations), Array.from(old.rotations), 'the last rotations, before any step');
  let apart = 0;
  let moving = 0;
  for (let f = 60; f < 120; f++) {
    const before = Array.from(old.rotations);
    drive(old, f);
    old.step(1 / 60);
    drive(next, f);
    next.step(1 / 60);
    apart = Math.max(apart, maxDifference(next.rotations, old.rotations));
    moving = Math.max(moving, maxDifference(old.rotations, before));
  }
  assert.ok(moving > 1e-3, `the chains move (${moving})`);
  assert.ok(apart < 1e-6, `within ${apart} of the instance stepped on`);
  for (const x of [old, next, rig, rebuilt]) x.dispose();
});

test('an edit of one chain leaves the other chains as they would have been', () => {
  const rig = sb.loadRig(glb, metadata);
  const old = rig.createInstance();
  for (let f = 0; f < 60; f++) {
    drive(old, f);
    old.step(1 / 60);
  }
  const edited = sb.loadRig(glb, { version: 1, models: { [hash]: { ...entry, SpringBone_ponytail: { ...entry.SpringBone_ponytail, stiffness: 3 } } } });
  const next = edited.createInstance();
  drive(next, 59);
  next.carryFrom(old);
  const untouched = ['hair_springbone_l', 'hair_springbone_r', 'springbone_earring_l'];
  let apart = 0;
  let ponytailApart = 0;
  for (let f = 60; f < 90; f++) {
    drive(old, f);
    old.step(1 / 60);
    drive(next, f);
    next.step(1 / 60);
    apart = Math.max(apart, maxDifference(rotationsOf(next, edited, untouched).flat(), rotationsOf(old, rig, untouched).flat()));
    ponytailApart = Math.max(ponytailApart, maxDifference(rotationsOf(next, edited, ['SpringBone_ponytail_1'])[0], rotationsOf(old, rig, ['SpringBone_ponytail_1'])[0]));
  }
  assert.ok(apart < 1e-6, `untouched chains within ${apart}`);
  assert.ok(ponytailApart > 1e-4, `the edited chain follows its new stiffness (${ponytailApart})`);
  for (const x of [old, next, rig, edited]) x.dispose();
});

test('carryFrom: an instance of this module, not disposed of', async () => {
  const rig = sb.loadRig(glb, metadata);
  const a = rig.createInstance();
  const b = rig.createInstance();
  assert.throws(() => a.carryFrom({}), TypeError);
  assert.throws(() => a.carryFrom(null), TypeError);
  const other = await createSpringBones();
  const foreign = other.loadRig(glb, metadata).createInstance();
  assert.throws(() => a.carryFrom(foreign), /another springbones module/);
  b.dispose();
  assert.throws(() => a.carryFrom(b), (e) => e instanceof SpringBonesError && e.code === 'disposed');
  a.dispose();
  const c = rig.createInstance();
  assert.throws(() => a.carryFrom(c), (e) => e instanceof SpringBonesError && e.code === 'disposed');
  for (const x of [c, foreign, rig]) x.dispose();
});
