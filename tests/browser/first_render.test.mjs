// The demo is never held up by the WebAssembly module: with the module's download held back by
// the test (playwright routing), the avatar is drawn (performance mark 'first-drawable-frame',
// set after the first render) before the module is ready ('springbones-ready'), and the page
// then finishes starting as usual, the sample wearable simulated.
import assert from 'node:assert/strict';
import { after, test } from 'node:test';
import { openDemo, skip } from './demo_page.mjs';

const HOLD_MS = 3000;
let close;
after(async () => { await close?.(); });

test('the avatar is drawn before the module is ready', { skip }, async () => {
  let heldAt = null;
  let released = null;
  const demo = await openDemo({
    beforeOpen: (page) => page.route('**/springbones_wasm.wasm', async (route) => {
      heldAt = Date.now();
      // While the module is held back the page must draw: wait for its mark, then let it go.
      await page.waitForFunction(() => performance.getEntriesByName('first-drawable-frame').length > 0, null, { timeout: 120000 })
        .catch(() => {});
      released = await page.evaluate(() => ({
        drawable: performance.getEntriesByName('first-drawable-frame').length,
        ready: performance.getEntriesByName('springbones-ready').length,
      }));
      await new Promise((resolve) => setTimeout(resolve, HOLD_MS));
      await route.continue();
    }),
  });
  close = demo.close;
  assert.ok(heldAt !== null, 'the module was requested (and held back)');
  assert.deepEqual(released, { drawable: 1, ready: 0 }, 'drawn while the module was held back, not ready yet');
  const marks = await demo.page.evaluate(() => Object.fromEntries(['first-drawable-frame', 'springbones-ready']
    .map((name) => [name, performance.getEntriesByName(name)[0]?.startTime ?? null])));
  assert.ok(marks['first-drawable-frame'] + HOLD_MS <= marks['springbones-ready'] + 1,
    `drawn at ${marks['first-drawable-frame']} ms, module ready at ${marks['springbones-ready']} ms`);
  const state = await demo.page.evaluate(() => window.springbonesDemo.state());
  assert.equal(state.joints, 15, 'the sample wearable is simulated once the module is there');
  assert.deepEqual(demo.consoleErrors, []);
});
