// The demo's Babylon.js page (web/demo/babylon.html) in Debian's Chromium, headless, software
// WebGL: Babylon 4.2's UMD build from a script tag, the sample avatar walking with its hair
// simulated by springbones/babylon's SpringBoneSimulation, and the chain panel's controls driving
// updateParams. Leaves a screenshot in tests/artifacts/babylon.png.
import assert from 'node:assert/strict';
import { mkdirSync } from 'node:fs';
import { join } from 'node:path';
import { test } from 'node:test';
import { artifacts, libraryModulesNotPreloaded, maxAbsDiff, skip, useDemoPage } from './demo_page.mjs';

let page;
let consoleErrors, consoleWarnings;
useDemoPage((demo) => ({ page, consoleErrors, consoleWarnings } = demo), { page: 'babylon.html', readyHook: 'springbonesBabylonDemo' });

const demo = (fn, arg) => page.evaluate(fn, arg);

test('opens on the sample with Babylon 4.2, its five chains and no console errors', { skip }, async () => {
  assert.match(await demo(() => window.springbonesBabylonDemo.babylonVersion), /^4\.2\./);
  const joints = await demo(() => window.springbonesBabylonDemo.joints());
  assert.equal(joints.length, 15);
  assert.equal(new Set(joints.map((j) => j.chain)).size, 5);
  assert.equal(await page.locator('#readout-joints').textContent(), '15');
  assert.deepEqual(consoleErrors, []);
});

test("the hair gets the 'dcl-body' shapes measured on the avatar in the scene, all eight, with no warning", { skip }, async () => {
  assert.deepEqual(await demo(() => window.springbonesBabylonDemo.colliders()), ['Avatar_Head', 'Avatar_Neck', 'Avatar_Spine2',
    'Avatar_Spine1', 'Avatar_LeftShoulder', 'Avatar_RightShoulder', 'Avatar_LeftArm', 'Avatar_RightArm']);
  assert.deepEqual(await demo(() => window.springbonesBabylonDemo.warnings()), []);
  assert.equal(await page.locator('#warnings').textContent(), '');
});

test('every library module is preloaded, and every preload used', { skip }, async () => {
  assert.deepEqual(await libraryModulesNotPreloaded(page), []);
  assert.deepEqual(consoleWarnings.filter((w) => /preload/i.test(w)), []);
});

test('the hair moves while the avatar walks', { skip }, async () => {
  const a = await demo(() => window.springbonesBabylonDemo.rotations());
  await page.waitForTimeout(600);
  const b = await demo(() => window.springbonesBabylonDemo.rotations());
  assert.ok(maxAbsDiff(a, b) > 1e-3, `rotations changed by only ${maxAbsDiff(a, b)} in 0.6 s of walking`);
});

test('the panel drives updateParams: a slider sets a chain\'s parameter, switching a chain off puts it at rest', { skip }, async () => {
  await page.locator('#root').selectOption('SpringBone_ponytail');
  await page.locator('#stiffness').fill('3.5');
  const ponytail = (await demo(() => window.springbonesBabylonDemo.joints())).find((j) => j.name === 'SpringBone_ponytail');
  assert.equal(ponytail.params.stiffness, 3.5);
  assert.equal(await page.locator('#stiffness-value').textContent(), '3.50');

  const names = ['SpringBone_ponytail', 'SpringBone_ponytail_1', 'SpringBone_ponytail_2'];
  const before = await demo((n) => window.springbonesBabylonDemo.rotations(n), names);
  await page.locator('#simulated').uncheck();
  assert.equal(await page.locator('#readout-chains').textContent(), '4');
  const off = await demo((n) => window.springbonesBabylonDemo.rotations(n), names);
  await page.waitForTimeout(300);
  const stillOff = await demo((n) => window.springbonesBabylonDemo.rotations(n), names);
  assert.ok(maxAbsDiff(before, off) > 1e-4, 'the chain was bent before');
  assert.deepEqual(stillOff, off, 'at rest and staying there while the avatar walks');
  await page.locator('#simulated').check();
  assert.equal(await page.locator('#readout-chains').textContent(), '5');
  await page.waitForTimeout(300);
  const on = await demo((n) => window.springbonesBabylonDemo.rotations(n), names);
  assert.ok(maxAbsDiff(on, off) > 1e-4, 'simulated again');
  assert.deepEqual(consoleErrors, []);
});

test('the wind slider goes to simulation.setWind without errors', { skip }, async () => {
  await page.locator('#wind').fill('2');
  assert.equal(await page.locator('#wind-value').textContent(), '2.0');
  await page.waitForTimeout(300);
  const rotations = await demo(() => window.springbonesBabylonDemo.rotations());
  assert.ok(rotations.every(Number.isFinite));
  await page.locator('#wind').fill('0');
  assert.equal(await page.locator('#wind-value').textContent(), '0.0');
  assert.deepEqual(consoleErrors, []);
});

test('the body colliders slider goes to simulation.setColliders without errors or warnings', { skip }, async () => {
  await page.locator('#body-scale').fill('2');
  assert.equal(await page.locator('#body-scale-value').textContent(), '2.00');
  await page.waitForTimeout(300);
  const rotations = await demo(() => window.springbonesBabylonDemo.rotations());
  assert.ok(rotations.every(Number.isFinite));
  await page.locator('#body-scale').fill('1');
  assert.equal(await page.locator('#body-scale-value').textContent(), '1.00');
  assert.deepEqual(consoleErrors, []);
});

test('teleport: the avatar moves and the page keeps running; screenshot', { skip }, async () => {
  await page.locator('#teleport').click();
  await page.waitForTimeout(400);
  const rotations = await demo(() => window.springbonesBabylonDemo.rotations());
  assert.ok(rotations.every(Number.isFinite));
  await page.locator('#teleport').click();
  await page.waitForTimeout(500);
  mkdirSync(artifacts, { recursive: true });
  await page.locator('#view').screenshot({ path: join(artifacts, 'babylon.png') });
  assert.deepEqual(consoleErrors, []);
});
