// The avatar's colliders in the demo: the page asks loadRig for the 'dcl-body' preset, measured on
// the avatar's bones (head sphere, neck, chest, upper-belly, shoulder and upper-arm capsules,
// though the wearable's GLB carries Hips to Head only), with no warning, and with
// them no joint tail of the sample enters the head sphere while the avatar is shaken and spun hard,
// with either integrator. Without them the same motion does put hair inside the head, so the check
// can fail. And the wind slider blows the hair.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { rotationsAfter, skip, useDemoPage } from './demo_page.mjs';

let page;
let consoleErrors;
useDemoPage((demo) => ({ page, consoleErrors } = demo));

const demo = (fn, arg) => page.evaluate(fn, arg);

/**
 * Deterministic hard motion, paused and advanced by the debug hook at 60 Hz: walking, a shake
 * every 0.7 s and a turn of 10 degrees per frame (600 degrees per second) for 4 s. Returns the
 * smallest clearance (metres, negative inside) of any joint tail from the head sphere.
 */
const hardMotion = () => demo(() => {
  const d = window.springbonesDemo;
  d.setPaused(true);
  d.setAnimation('walk');
  d.reset();
  let worst = { clearance: Infinity, joint: null, frame: -1, radius: 0 };
  for (let f = 0; f < 240; f++) {
    if (f % 42 === 0) d.shake();
    d.setYaw(f * 10);
    d.advance(1 / 60);
    const c = d.headClearance();
    if (c.clearance < worst.clearance) worst = { ...c, frame: f };
  }
  d.reset();
  return worst;
});

test('the rig gets the avatar colliders, drawn on demand', { skip }, async () => {
  let state = await demo(() => window.springbonesDemo.state());
  assert.equal(state.colliders, true, 'colliders are on by default');
  assert.equal(state.rigColliders, 8, 'head sphere, neck, chest, upper-belly, shoulder and upper-arm capsules');
  assert.deepEqual(state.rigWarnings, [], 'no body-collider-skipped: the avatar has every bone');
  assert.equal(state.collidersShown, 0);
  await page.locator('#show-colliders').check();
  state = await demo(() => window.springbonesDemo.state());
  assert.equal(state.collidersShown, 8, 'one wireframe per collider, on the avatar bones');
  await page.locator('#colliders').uncheck();
  state = await demo(() => window.springbonesDemo.state());
  assert.equal(state.rigColliders, 0);
  assert.equal(state.collidersShown, 0);
  assert.equal(state.joints, 15, 'the springs keep running without colliders');
  await page.locator('#colliders').check();
  await page.locator('#show-colliders').uncheck();
  state = await demo(() => window.springbonesDemo.state());
  assert.equal(state.rigColliders, 8);
  assert.equal(state.collidersShown, 0);
  assert.deepEqual(consoleErrors, []);
});

for (const integrator of ['vrm', 'xpbd']) {
  test(`with ${integrator}, no hair enters the head when the avatar is shaken and spun hard`, { skip }, async (t) => {
    await page.locator('#integrator').selectOption(integrator);
    await page.locator('#colliders').uncheck();
    const without = await hardMotion();
    await page.locator('#colliders').check();
    const withColliders = await hardMotion();
    assert.equal((await demo(() => window.springbonesDemo.state())).integrator, integrator);
    const cm = (m) => (m * 100).toFixed(2);
    t.diagnostic(`${integrator}: deepest tail inside the head sphere (radius ${cm(withColliders.radius)} cm): ` +
      `without colliders ${cm(-without.clearance)} cm (${without.joint}, frame ${without.frame}), ` +
      `with colliders ${cm(-withColliders.clearance)} cm (${withColliders.joint})`);
    // The same motion without colliders goes through the head: the check below can fail.
    assert.ok(without.clearance < -0.01, `without colliders the deepest tail is only ${cm(-without.clearance)} cm inside`);
    // With them every tail stays outside the sphere (the hit radius, 1 cm, is extra room).
    assert.ok(withColliders.clearance >= -1e-4, `${withColliders.joint} went ${cm(-withColliders.clearance)} cm into the head`);
    assert.deepEqual(consoleErrors, []);
  });
}

test('the wind slider sets a wind on every avatar, which moves the hair', { skip }, async () => {
  const pose = () => rotationsAfter(page, 'idle', 2);
  const calm = await pose();
  await page.locator('#wind').evaluate((input) => {
    input.value = '2';
    input.dispatchEvent(new Event('input', { bubbles: true }));
  });
  assert.equal((await demo(() => window.springbonesDemo.state())).wind, 2);
  const windy = await pose();
  const largest = Math.max(...calm.map((v, i) => Math.abs(v - windy[i])));
  assert.ok(largest > 0.05, `the wind changed no rotation by more than ${largest}`);
  await demo(() => window.springbonesDemo.setWind(0));
  const calmAgain = await pose();
  assert.deepEqual(calmAgain, calm, 'no wind: the same motion as before, bit for bit');
  assert.deepEqual(consoleErrors, []);
});

test('the body colliders slider resizes the body shapes while the avatar moves; back at 1, the same motion', { skip }, async () => {
  const pose = () => rotationsAfter(page, 'walk', 2);
  const setSlider = (value) => page.locator('#body-scale').evaluate((input, v) => {
    input.value = v;
    input.dispatchEvent(new Event('input', { bubbles: true }));
  }, value);
  const before = await pose();
  await setSlider('2');
  const state = await demo(() => window.springbonesDemo.state());
  assert.equal(state.bodyScale, 2);
  assert.equal(state.rigColliders, 8, 'the rig is not rebuilt: the instance has the shapes resized');
  const larger = await pose();
  const largest = Math.max(...before.map((v, i) => Math.abs(v - larger[i])));
  assert.ok(largest > 0.05, `twice the body's radii changed no rotation by more than ${largest}`);
  await setSlider('1');
  assert.deepEqual(await pose(), before, 'the rig\'s own shapes again: bit for bit the motion before');
  assert.deepEqual(consoleErrors, []);
});
