// Out of memory is an error, not the end, in Chromium: the scenario of
// tests/scenarios/out_of_memory.mjs (also run in Node by tests/wasm/out_of_memory.test.mjs) in a
// page, with the same checks.
import assert from 'node:assert/strict';
import { after, before, test } from 'node:test';
import { openPage, skip } from './demo_page.mjs';
import { checkOutOfMemoryReport } from '../scenarios/out_of_memory_checks.mjs';

let page, consoleErrors, close;
before(async () => {
  if (skip) return;
  ({ page, consoleErrors, close } = await openPage('/tests/browser/pages/blank.html', () => window.blankPageReady === true));
});
after(async () => { await close?.(); });

test('a capped memory: out-of-memory errors, then the module keeps working', { skip }, async () => {
  const report = await page.evaluate(async () => {
    const { createSpringBones } = await import('/web/springbones.js');
    const { outOfMemoryScenario } = await import('/tests/scenarios/out_of_memory.mjs');
    const bytes = async (url) => new Uint8Array(await (await fetch(url)).arrayBuffer());
    return outOfMemoryScenario({
      // The scenario loads GLB and VRM bytes: a page reads them with the readers module.
      createSpringBones: async () => {
        const sb = await createSpringBones();
        await sb.readers();
        return sb;
      },
      wearable: {
        glb: await bytes('/web/demo/assets/hair_wearable.glb'),
        springBones: await (await fetch('/web/demo/assets/hair_wearable.metadata.json')).json(),
      },
      vrm: await bytes('/tests/fixtures/vrm10_springs.vrm'),
    });
  });
  checkOutOfMemoryReport(assert, report);
  assert.deepEqual(consoleErrors, []);
});
