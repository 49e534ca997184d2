// The preview's readout tells the truth: the solver time is the median over the last second of
// frames, and only of frames of what is simulated now (a change of wearable or integrator starts
// it afresh); the substep count is what the core ran in the last frame, checked against the
// core's own results (a frame of k steps leaves the same rotations as k frames of one step).
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { test } from 'node:test';
import { maxAbsDiff, root, skip, useDemoPage } from './demo_page.mjs';

let page;
let consoleErrors;
useDemoPage((demo) => ({ page, consoleErrors } = demo));

const demo = (fn, arg) => page.evaluate(fn, arg);
const median = (xs) => [...xs].sort((a, b) => a - b)[xs.length >> 1];

/** The readout a few animation frames from now (the frame loop running). */
const readoutAfterFrames = (frames = 5) => demo(async (n) => {
  for (let i = 0; i < n; i++) await new Promise(requestAnimationFrame);
  return window.springbonesDemo.readout();
}, frames);

/** The readout is the median of its samples, all from the last second, and the page shows it. */
function assertConsistent(r) {
  assert.ok(r.samples.length > 0, 'frames were simulated');
  assert.ok(r.samples.every((s) => r.now - s.at <= 1000), 'only the last second');
  assert.equal(r.medianMs, median(r.samples.map((s) => s.ms)));
  assert.equal(r.shown.solver, r.medianMs.toFixed(3));
  assert.equal(Number(r.shown.frames), r.samples.length);
}

test('a change of wearable or integrator restarts the readout', { skip }, async () => {
  // Running: the readout is the median of the last second's frames, and the page shows it.
  await demo(() => { const d = window.springbonesDemo; d.setPaused(false); d.setAnimation('walk'); });
  await page.waitForTimeout(1200);
  const running = await readoutAfterFrames(1);
  assertConsistent(running);
  assert.ok(running.samples.every((s) => s.joints === 15), 'the sample: 15 joints per frame');

  // Another wearable first (prefilled roots, not the sample's 15 joints).
  const posed = readFileSync(join(root, 'tests/fixtures/adr_example_posed.glb'));
  await page.locator('#file-glb').setInputFiles({ name: 'adr_example_posed.glb', mimeType: 'model/gltf-binary', buffer: posed });
  await page.waitForFunction(() => window.springbonesDemo.state().wearable === 'adr_example_posed.glb');
  const joints = (await demo(() => window.springbonesDemo.state())).joints;
  assert.notEqual(joints, 15);

  // Paused, the hook's frames are the only ones simulated: half a second of this wearable, the
  // sample loaded, three frames of it. The readout then holds those three frames and nothing
  // older (however old: loading may take longer than a second on a busy machine).
  const wearable = await demo(async () => {
    const d = window.springbonesDemo;
    d.setPaused(true);
    d.advance(0.5);
    const before = d.readout();
    document.getElementById('load-sample').click();
    while (d.state().wearable !== 'hair_wearable.glb') await new Promise(requestAnimationFrame);
    d.advance(3 / 60);
    return { before, after: d.readout() };
  });
  assert.ok(wearable.before.held >= 30 && wearable.before.samples.every((s) => s.joints === joints));
  assertConsistent(wearable.after);
  assert.equal(wearable.after.held, 3, 'the three frames after the change, nothing before it');
  assert.deepEqual(wearable.after.samples.map((s) => s.joints), [15, 15, 15]);

  const integrator = await demo(() => {
    const d = window.springbonesDemo;
    d.advance(0.5);
    const before = d.readout();
    d.setIntegrator('xpbd');
    d.advance(3 / 60);
    return { before, after: d.readout() };
  });
  // held, not samples.length: the samples are cut at a second of wall time, which 30 frames may
  // exceed on a loaded machine.
  assert.ok(integrator.before.held >= 30 && integrator.before.samples.every((s) => s.integrator === 'vrm'));
  assertConsistent(integrator.after);
  assert.equal(integrator.after.held, 3, 'the three frames after the switch, nothing before it');
  assert.deepEqual(integrator.after.samples.map((s) => s.integrator), ['xpbd', 'xpbd', 'xpbd']);

  await demo(() => { const d = window.springbonesDemo; d.setIntegrator('vrm'); d.setPaused(false); });
  assert.deepEqual(consoleErrors, []);
});

test('the substep count follows the frame dt, as the core steps', { skip }, async (t) => {
  // Paused: the debug hook's advance(dt, dt) runs exactly one frame of dt.
  const counts = (integrator, dt, frames) => demo(([name, step, n]) => {
    const d = window.springbonesDemo;
    d.setPaused(true);
    d.setIntegrator(name);
    d.reset();
    const out = [];
    for (let i = 0; i < n; i++) {
      d.advance(step, step);
      out.push(d.readout().substeps);
    }
    return { counts: out, shown: d.readout().shown.substeps };
  }, [integrator, dt, frames]);

  // VRM at 60 Hz, at most 4 steps a frame; XPBD at 120 Hz, at most 8.
  assert.deepEqual((await counts('vrm', 1 / 60, 3)).counts, [1, 1, 1]);
  assert.deepEqual((await counts('vrm', 1 / 30, 3)).counts, [2, 2, 2]);
  assert.deepEqual((await counts('vrm', 1 / 20, 2)).counts, [3, 3]);
  const capped = await counts('vrm', 0.2, 2);
  assert.deepEqual(capped.counts, [4, 4], 'a long frame is capped at maxSubsteps');
  assert.equal(capped.shown, '4');
  assert.deepEqual((await counts('vrm', 1 / 120, 4)).counts, [0, 1, 0, 1], 'a 120 fps display steps every other frame');
  assert.deepEqual((await counts('vrm', 1 / 144, 6)).counts, [0, 0, 1, 0, 1, 0], 'at 144 fps, 5 steps in 12 frames');
  assert.deepEqual((await counts('xpbd', 1 / 60, 2)).counts, [2, 2]);
  assert.deepEqual((await counts('xpbd', 0.1, 1)).counts, [8]);

  // The core agrees: standing still (constant drivers), the chains fall from the bind pose under
  // gravity, and a frame of k steps leaves the rotations that k frames of 1/60 leave, and not
  // those of k - 1 or k + 1 (the same up to rounding: within a frame of several steps the core
  // interpolates the drivers, which moves a constant pose by a few ulps).
  const rotationsAfter = (frames) => demo((dts) => {
    const d = window.springbonesDemo;
    d.setIntegrator('vrm');
    d.setAnimation('none');
    d.advance(1);  // the walk fades out: the drivers stand still from here on
    d.reset();
    d.restartSprings();  // Reset settles the hair; the springs fall from the rest pose instead
    for (const dt of dts) d.advance(dt, dt);
    return { rotations: d.rotations(), substeps: d.readout().substeps };
  }, frames);
  for (const [dt, k] of [[1 / 30, 2], [1 / 20, 3], [0.2, 4]]) {
    const one = await rotationsAfter([dt]);
    assert.equal(one.substeps, k);
    const off = {};
    for (const steps of [k - 1, k, k + 1]) off[steps] = maxAbsDiff(one.rotations, (await rotationsAfter(Array(steps).fill(1 / 60))).rotations);
    t.diagnostic(`one frame of ${dt.toFixed(4)} s against ${k - 1}, ${k}, ${k + 1} frames of 1/60: ${[off[k - 1], off[k], off[k + 1]].map((x) => x.toExponential(1)).join(', ')}`);
    assert.ok(off[k] < 1e-5, `one frame of ${dt.toFixed(4)} s is ${off[k]} away from ${k} steps`);
    assert.ok(off[k - 1] > 1e-3 && off[k + 1] > 1e-3, `one frame of ${dt.toFixed(4)} s: ${off[k - 1]} from ${k - 1} steps, ${off[k + 1]} from ${k + 1}`);
  }
  // and a frame of no step leaves the rotations as they were
  const half = await rotationsAfter([1 / 60, 1 / 120]);
  assert.equal(half.substeps, 0);
  assert.deepEqual(half.rotations, (await rotationsAfter([1 / 60])).rotations);

  await demo(() => { const d = window.springbonesDemo; d.setAnimation('walk'); d.setPaused(false); });
  assert.deepEqual(consoleErrors, []);
});
