// One answer everywhere, Chromium's part: the hashes of tests/scenarios/frame_hash.mjs computed in
// a page equal the native ones (tests/wasm/frame_hash.test.mjs checks Node against the same).
import assert from 'node:assert/strict';
import { after, before, test } from 'node:test';
import { openPage, skip } from './demo_page.mjs';
import { nativeFrameHashes } from '../scenarios/native_frame_hashes.mjs';

let page, consoleErrors, close;
before(async () => {
  if (skip) return;
  ({ page, consoleErrors, close } = await openPage('/tests/browser/pages/blank.html', () => window.blankPageReady === true));
});
after(async () => { await close?.(); });

// Both builds of the runtime: the runtime module (its per-frame path at -Oz, scalar) and the crowd
// module (-O3, SIMD).
for (const crowd of [false, true]) {
  const module = crowd ? 'the crowd module' : 'the runtime module';
  test(`1,000 frames hash the same natively and in Chromium, in ${module}`, { skip }, async (t) => {
    const native = nativeFrameHashes();
    const chromium = await page.evaluate(async (crowd) => {
      const { createSpringBones } = await import('/web/springbones.js');
      const { frameHashes } = await import('/tests/scenarios/frame_hash.mjs');
      const sb = await createSpringBones({ crowd });
      if (sb.crowd !== crowd) throw new Error(`sb.crowd is ${sb.crowd}`);
      await sb.readers();  // the scenario loads the fixtures' bytes
      return frameHashes(sb, async (path) => new Uint8Array(await (await fetch(`/${path}`)).arrayBuffer()));
    }, crowd);
    for (const [name, { joints, hash }] of Object.entries(native)) {
      t.diagnostic(`${name} (${joints} joints): native ${hash}, Chromium ${chromium[name].hash}`);
    }
    assert.deepEqual(chromium, native);
    assert.deepEqual(consoleErrors, []);
  });
}
