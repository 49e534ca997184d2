// A backpack that never leaks, the CI version: 600 cycles of load a wearable -> wear it on the
// avatar -> 30 frames -> take it off and dispose, through the three.js adapter and its loader
// plugin in Chromium (tests/scenarios/backpack_soak.mjs), sampled every 50 cycles: flat after the
// first 100 as tests/browser/soakBounds.mjs defines it, and no console error. `scripts/bench
// --soak` runs 2,000 cycles.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { runBackpackSoak } from './backpackSoak.mjs';
import { skip } from './demoPage.mjs';
import { soakProblems } from './soakBounds.mjs';

test('600 wearable swaps through the three.js adapter leave memory, handles and the avatar flat', { skip }, async (t) => {
  const { samples, consoleErrors } = await runBackpackSoak({ cycles: 600, batch: 50 });
  const first = samples.find((s) => s.cycles === 100);
  const last = samples.at(-1);
  t.diagnostic(`cycle 100 -> ${last.cycles}: WebAssembly memory ${first.heapBytes} -> ${last.heapBytes}, in use ` +
    `${first.heapInUse} -> ${last.heapInUse}, JS heap ${first.jsHeapUsed} -> ${last.jsHeapUsed} bytes`);
  assert.equal(last.cycles, 600);
  assert.deepEqual(soakProblems(samples), []);
  assert.deepEqual(consoleErrors, []);
});
