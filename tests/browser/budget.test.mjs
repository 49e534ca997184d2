// The demo's "simulate nearest" control: a crowd in one springbones scene with a budget,
// the viewer at the camera. Only the N avatars nearest to the camera are simulated; the others'
// joints hold still (the core's behaviour) while the animation goes on, and moving the camera
// changes which ones move. The readout counts the simulated avatars. With "all" every avatar
// moves again, which is what the held ones would do without the budget.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { skip, useDemoPage } from './demo_page.mjs';

let page;
let consoleErrors;
useDemoPage((demo) => ({ page, consoleErrors } = demo));

const demo = (fn, arg) => page.evaluate(fn, arg);
const readout = () => page.locator('#readout-budget').textContent();
/** Waits until the readout (refreshed every 250 ms by the frame loop) says `text`, then checks it. */
const readoutSays = async (text) => {
  await page.waitForFunction((t) => document.getElementById('readout-budget').textContent === t, text).catch(() => {});
  assert.equal(await readout(), text);
};

/**
 * Paused, deterministic: `warm` seconds of walking, then every avatar's joint rotations and
 * whether the last step simulated it, then `seconds` more and the rotations again. All in one
 * evaluate, so the camera does not move in between.
 */
const motion = (warm = 0.5, seconds = 0.4) => demo(([w, s]) => {
  const d = window.springbonesDemo;
  d.setPaused(true);
  d.advance(w);
  const n = d.state().avatars;
  const all = () => Array.from({ length: n }, (_, i) => d.rotations(i));
  const before = all();
  const avatars = d.activeAvatars();
  d.advance(s);
  const after = all();
  return avatars.map((a, i) => ({ ...a, moved: before[i].length ? Math.max(...before[i].map((v, k) => Math.abs(v - after[i][k]))) : NaN }));
}, [warm, seconds]);

/** The active avatars are the `count` nearest to the camera. */
const assertNearest = (avatars, count, where) => {
  const active = avatars.filter((a) => a.active);
  const held = avatars.filter((a) => !a.active);
  assert.equal(active.length, count, `${where}: ${active.length} avatars simulated`);
  const farthestActive = Math.max(...active.map((a) => a.distance));
  const nearestHeld = Math.min(...held.map((a) => a.distance));
  assert.ok(farthestActive <= nearestHeld, `${where}: a simulated avatar at ${farthestActive} m, a held one at ${nearestHeld} m`);
};

test('simulate nearest 5 of 20: the others hold their pose, the camera decides which', { skip }, async () => {
  assert.equal(await page.locator('#budget').inputValue(), 'all', 'no budget by default');
  assert.equal((await demo(() => window.springbonesDemo.state())).budget, null);
  await page.locator('#avatars').fill('20');
  await page.locator('#avatars').dispatchEvent('change');
  await page.locator('#animation').selectOption('walk');
  await page.locator('#budget').selectOption('5');
  let s = await demo(() => window.springbonesDemo.state());
  assert.deepEqual([s.avatars, s.sceneSize, s.budget], [20, 20, 5]);
  await readoutSays('simulated 5 of 20 avatars');
  assert.equal(Number(await page.locator('#readout-joints').textContent()), 5 * 15, 'the joints of the simulated avatars');

  const body = await motion();
  assertNearest(body, 5, 'whole-avatar view');
  for (const [i, a] of body.entries()) {
    if (a.active) assert.ok(a.moved > 1e-4, `simulated avatar ${i}'s joints moved only ${a.moved}`);
    else assert.equal(a.moved, 0, `held avatar ${i}'s joints moved by ${a.moved}`);
  }

  // Zoom to the head of the front avatar: other avatars are now the nearest.
  await page.locator('#view-preset').selectOption('head');
  const head = await motion(0.2);
  assertNearest(head, 5, 'head view');
  const activeSet = (avatars) => avatars.flatMap((a, i) => (a.active ? [i] : []));
  assert.notDeepEqual(activeSet(head), activeSet(body), 'the camera moved, so did the budget');
  for (const [i, a] of head.entries()) {
    if (a.active) assert.ok(a.moved > 1e-4, `simulated avatar ${i}'s joints moved only ${a.moved}`);
    else assert.equal(a.moved, 0, `held avatar ${i}'s joints moved by ${a.moved}`);
  }
  // Some avatars left the budget (and hold, checked above), others came in (and move).
  assert.ok(activeSet(body).some((i) => !head[i].active), 'some avatar left the budget');
  assert.ok(activeSet(head).some((i) => !body[i].active), 'some avatar came into the budget');

  // "all": every avatar moves again, the held ones included.
  await page.locator('#view-preset').selectOption('body');
  await page.locator('#budget').selectOption('all');
  s = await demo(() => window.springbonesDemo.state());
  assert.equal(s.budget, null);
  const all = await motion(0.2);
  assert.equal(all.filter((a) => a.active).length, 20);
  for (const [i, a] of all.entries()) assert.ok(a.moved > 1e-4, `avatar ${i}'s joints moved only ${a.moved}`);
  await demo(() => window.springbonesDemo.setPaused(false));
  await readoutSays('simulated 20 of 20 avatars');
  assert.equal(Number(await page.locator('#readout-joints').textContent()), 20 * 15);
  assert.equal((await demo(() => window.springbonesDemo.state())).simulated, 20);
  assert.deepEqual(consoleErrors, []);
});
