// loadVrm in Chromium, where the runtime carries no VRM reader: the VRM rules run in the readers
// module. A page that has not loaded them gets 'readers-not-loaded' for the glTF JSON its loader
// parsed, as for bytes, and has downloaded the runtime alone; after sb.readers() the parsed JSON
// and the bytes give the rig Node gives, warnings and rotations included.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { after, test } from 'node:test';

import { createSpringBones } from '../../web/springbones.js';
import { glbJson, vrmSummary } from '../scenarios/load_vrm.mjs';
import { openPage, root, skip } from './demo_page.mjs';

let close;
after(async () => { await close?.(); });

const kFixture = 'tests/fixtures/vrm0_springs.vrm';

test('loadVrm in Chromium: readers-not-loaded before sb.readers(), then the rig Node loads', { skip }, async () => {
  const opened = await openPage('/tests/browser/pages/blank.html', () => window.blankPageReady === true);
  close = opened.close;
  const outcome = await opened.page.evaluate(async (fixture) => {
    const { createSpringBones } = await import('/web/springbones.js');
    const { glbJson: parse, vrmSummary: summarize } = await import('/tests/scenarios/load_vrm.mjs');
    const sb = await createSpringBones();
    const bytes = new Uint8Array(await (await fetch(`/${fixture}`)).arrayBuffer());
    const json = parse(bytes);
    const before = {};
    for (const [key, input] of [['parsed', json], ['bytes', bytes]]) {
      try {
        sb.loadVrm(input);
        before[key] = 'loaded';
      } catch (e) {
        before[key] = { code: e.code, message: e.message };
      }
    }
    const requestedBefore = performance.getEntriesByType('resource').map((r) => r.name).filter((n) => n.includes('readers'));
    await sb.readers();
    return { before, requestedBefore, parsed: summarize(sb.loadVrm(json)), bytes: summarize(sb.loadVrm(bytes)), rigs: sb.stats().rigs };
  }, kFixture);

  assert.equal(outcome.before.parsed?.code, 'readers-not-loaded');
  assert.match(outcome.before.parsed.message, /^loadVrm .*readers module.*await sb\.readers\(\)/);
  assert.equal(outcome.before.bytes?.code, 'readers-not-loaded');
  assert.deepEqual(outcome.requestedBefore, [], 'the runtime alone was downloaded before sb.readers()');

  const sb = await createSpringBones();
  const bytes = new Uint8Array(readFileSync(join(root, kFixture)));
  const expected = vrmSummary(sb.loadVrm(glbJson(bytes)));
  assert.equal(expected.format, 'vrm0');
  assert.ok(expected.joints.length > 0);
  assert.deepEqual(vrmSummary(sb.loadVrm(bytes)), expected, 'in Node, the bytes and the parsed JSON give one rig');
  for (const key of ['parsed', 'bytes']) {
    assert.deepEqual(outcome[key], expected, `in Chromium, the ${key} input gives Node's rig, bit for bit`);
  }
  assert.equal(outcome.rigs, 0);
  assert.deepEqual(opened.consoleErrors, []);
});
