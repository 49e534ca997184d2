// What the demo pages show before anyone touches them, wide and in a marketplace's 420 px iframe:
// the three.js page's default camera shows the ponytail (in the frustum, and not behind the head);
// at 420 px the readout never covers the avatar; the Babylon.js page has ground under the avatar
// and its teleport keeps the avatar in frame. Measured from the pages' own projections
// (springbonesDemo.onScreen, springbonesBabylonDemo.onScreen) and the readout's layout box.
// Leaves screenshots in tests/artifacts/view-*.png.
import assert from 'node:assert/strict';
import { mkdirSync } from 'node:fs';
import { join } from 'node:path';
import { after, before, describe, test } from 'node:test';
import { artifacts, kWideViewport, openDemo, skip } from './demo_page.mjs';

// A marketplace's wearable preview iframe.
const kNarrow = { width: 420, height: 640 };

const overlaps = (a, b) => a.left < b.right && b.left < a.right && a.top < b.bottom && b.top < a.bottom;
const inside = (a, b) => a.left >= b.left && a.right <= b.right && a.top >= b.top && a.bottom <= b.bottom;
const rectOf = (box) => ({ left: box.x, right: box.x + box.width, top: box.y, bottom: box.y + box.height });
const show = (r) => `[${[r.left, r.top, r.right, r.bottom].map((v) => v.toFixed(0)).join(', ')}]`;

/** Waits for two animation frames, so a resize has been laid out and drawn. */
const frames = (page) => page.evaluate(() => new Promise((resolve) => requestAnimationFrame(() => requestAnimationFrame(resolve))));

/** Checks the walking avatar over a second of frames: the readout box never meets its bounds. */
async function assertReadoutClear(page, onScreen, where) {
  for (let k = 0; k < 6; k++) {
    const { avatar, canvas } = await page.evaluate(onScreen);
    const readout = rectOf(await page.locator('#readout').boundingBox());
    assert.ok(overlaps(avatar, canvas), `${where}: the avatar ${show(avatar)} is drawn in the canvas ${show(canvas)}`);
    assert.ok(!overlaps(readout, avatar), `${where}: the readout ${show(readout)} covers the avatar ${show(avatar)}`);
    await page.waitForTimeout(150);
  }
}

describe('the three.js page', () => {
  let demo;
  before(async () => {
    if (!skip) demo = await openDemo({ viewport: kWideViewport });
  });
  after(async () => demo?.close());

  test('the default camera shows the ponytail, beside the head rather than behind it', { skip }, async () => {
    const { page, consoleErrors } = demo;
    assert.equal(await page.locator('#view-preset').inputValue(), 'body');
    // Walking, a second of frames: the ponytail stays in view all along.
    for (let k = 0; k < 6; k++) {
      const { ponytail } = await page.evaluate(() => window.springbonesDemo.onScreen());
      assert.equal(ponytail.length, 5, 'the ponytail\'s simulated joints');
      for (const joint of ponytail) {
        const [x, y, z] = joint.ndc;
        assert.ok(Math.abs(x) < 1 && Math.abs(y) < 1 && z > -1 && z < 1, `${joint.name} in the frustum: ${joint.ndc}`);
      }
      const hidden = ponytail.filter((j) => j.hidden).map((j) => j.name);
      assert.ok(hidden.length <= 1, `the head hides ${hidden.join(', ')}`);
      assert.ok(!hidden.includes('SpringBone_ponytail_4'), 'the end of the ponytail shows');
      await page.waitForTimeout(150);
    }
    mkdirSync(artifacts, { recursive: true });
    await page.locator('#view').screenshot({ path: join(artifacts, 'view-three-default.png') });
    assert.deepEqual(consoleErrors, []);
  });

  test('at 420 px wide the readout never covers the avatar', { skip }, async () => {
    const { page, consoleErrors } = demo;
    await page.setViewportSize(kNarrow);
    await frames(page);
    await assertReadoutClear(page, () => window.springbonesDemo.onScreen(), 'three.js at 420 px');
    // The readout still says what it says wide.
    assert.equal(await page.locator('#readout').isVisible(), true);
    assert.match(await page.locator('#readout-joints').textContent(), /^\d+$/);
    await page.screenshot({ path: join(artifacts, 'view-three-420.png') });
    await page.setViewportSize(kWideViewport);
    assert.deepEqual(consoleErrors, []);
  });
});

/**
 * The canvas's sizes over `ms` of frames while the readout's texts change length every frame, as
 * a slow machine's numbers make them: each frame every span of the readout gets, in turn, its
 * longest and shortest text, then the canvas is measured (which lays the page out). Returns the
 * distinct sizes seen, as "width x height".
 */
const canvasSizesOver = (page, ms) => page.evaluate((ms) => new Promise((resolve) => {
  const canvas = document.querySelector('canvas');
  const spans = [...document.querySelectorAll('#readout span')];
  const seen = new Set();
  const end = performance.now() + ms;
  let frame = 0;
  const look = () => {
    frame += 1;
    for (const span of spans) span.textContent = frame % 2 ? '12,345.678 (1,234.5 µs per joint, 56 avatars)' : '1';
    const box = canvas.getBoundingClientRect();
    seen.add(`${box.width} x ${box.height}`);
    if (performance.now() < end) requestAnimationFrame(look);
    else resolve([...seen]);
  };
  requestAnimationFrame(look);
}), ms);

describe('at 420 px the layout does not follow the readout', () => {
  for (const [name, options] of [['three.js', {}], ['Babylon.js', { page: 'babylon.html', readyHook: 'springbonesBabylonDemo' }]]) {
    test(`the ${name} page's canvas keeps one size over 3 s while the readout's texts change length`, { skip }, async () => {
      const demo = await openDemo(options);
      try {
        const { page, consoleErrors } = demo;
        await page.setViewportSize(kNarrow);
        await frames(page);
        const sizes = await canvasSizesOver(page, 3000);
        assert.equal(sizes.length, 1, `the canvas took ${sizes.length} sizes: ${sizes.join(', ')}`);
        assert.ok(await page.locator('#readout').isVisible());
        assert.deepEqual(consoleErrors, []);
      } finally {
        await demo.close();
      }
    });
  }
});

describe('the Babylon.js page', () => {
  let demo;
  before(async () => {
    if (!skip) demo = await openDemo({ page: 'babylon.html', readyHook: 'springbonesBabylonDemo', viewport: kWideViewport });
  });
  after(async () => demo?.close());

  const onScreen = () => window.springbonesBabylonDemo.onScreen();

  test('the avatar stands on ground', { skip }, async () => {
    const { page, consoleErrors } = demo;
    const { ground, lowest } = await page.evaluate(onScreen);
    assert.equal(ground.visible, true);
    assert.ok(Math.abs(lowest - ground.y) < 0.05, `the avatar's lowest point ${lowest} m is on the ground at ${ground.y} m`);
    assert.deepEqual(consoleErrors, []);
  });

  test('the teleport keeps the avatar in frame, wide and at 420 px; the readout never covers it', { skip }, async () => {
    const { page, consoleErrors } = demo;
    mkdirSync(artifacts, { recursive: true });
    for (const size of [kWideViewport, kNarrow]) {
      await page.setViewportSize(size);
      await frames(page);
      const where = `${size.width} px`;
      let state = await page.evaluate(onScreen);
      assert.ok(inside(state.avatar, state.canvas), `${where}: the avatar ${show(state.avatar)} in the canvas ${show(state.canvas)}`);
      await page.locator('#teleport').click();
      await frames(page);
      state = await page.evaluate(onScreen);
      assert.ok(Math.hypot(...state.position) > 0.99, `${where}: teleported by ${Math.hypot(...state.position)} m`);
      assert.ok(inside(state.avatar, state.canvas), `${where}: after the teleport the avatar ${show(state.avatar)} in the canvas ${show(state.canvas)}`);
      assert.ok(Math.hypot(state.position[0], state.position[2]) < state.ground.radius, `${where}: still on the ground`);
      await assertReadoutClear(page, onScreen, `Babylon.js at ${where}, teleported`);
      await page.screenshot({ path: join(artifacts, `view-babylon-${size.width}.png`) });
      await page.locator('#teleport').click();
      await frames(page);
      state = await page.evaluate(onScreen);
      assert.deepEqual(state.position, [0, 0, 0], `${where}: back`);
    }
    await page.setViewportSize(kWideViewport);
    assert.deepEqual(consoleErrors, []);
  });
});
