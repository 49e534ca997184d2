// Out of memory is an error, not the end, in Node: tests/scenarios/out_of_memory.mjs (the same
// scenario runs in Chromium in tests/browser/out_of_memory.test.mjs) caps the module's memory,
// loads the sample wearable until it no longer fits, calls every entry point on the full heap,
// then disposes and loads again.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { test } from 'node:test';

import { createSpringBones } from '../../web/springbones.js';
import { outOfMemoryScenario } from '../scenarios/out_of_memory.mjs';
import { checkOutOfMemoryReport } from '../scenarios/out_of_memory_checks.mjs';
import { fixture, root } from './helpers.mjs';

test('a capped memory: out-of-memory errors, then the module keeps working', async () => {
  const assets = join(root, 'web', 'demo', 'assets');
  const report = await outOfMemoryScenario({
    createSpringBones,
    wearable: {
      glb: new Uint8Array(readFileSync(join(assets, 'hair_wearable.glb'))),
      springBones: JSON.parse(readFileSync(join(assets, 'hair_wearable.metadata.json'), 'utf8')),
    },
    vrm: new Uint8Array(fixture('vrm10_springs.vrm')),
  });
  checkOutOfMemoryReport(assert, report);
});
