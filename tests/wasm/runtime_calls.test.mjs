// The runtime module's entry points: the C functions the module exports (wasm/bindings.cpp,
// wasm/module_kind.cpp) and web/runtime_calls.js's list of them agree, name by name and in the
// number of their parameters, in both builds of the runtime; strings cross both ways whole.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { pathToFileURL } from 'node:url';
import { test } from 'node:test';

import { instantiateModule } from '../../web/module_loader.js';
import { createSpringBones } from '../../web/springbones.js';
import { kRuntimeCalls } from '../../web/runtime_calls.js';
import { root, springRig } from './helpers.mjs';

// The text result's own two functions, which runtime_calls.js calls itself.
const kTextResult = ['sb_textSize', 'sb_textFree'];

/**
 * Each exported sb_ function's parameter count in `file`. The module's own export names are
 * minified: the glue says which one each sb_ function is (Module["_sb_x"] ... Module["asm"]["k"]).
 */
async function exportedFunctions(file) {
  const module = await instantiateModule('test', {}, {
    importGlue: () => import('../../web/dist/springbones_wasm.js'),
    glueFile: 'web/dist/springbones_wasm.js',
    defaultUrl: pathToFileURL(join(root, 'web', 'dist', file)),
  });
  const glue = readFileSync(join(root, 'web', 'dist', 'springbones_wasm.js'), 'utf8');
  const exported = new Map();
  for (const [, name, minified] of glue.matchAll(/Module\["_(sb_\w+)"\]=Module\["asm"\]\["(\w+)"\]/g)) {
    exported.set(name, module.asm[minified].length);
  }
  return exported;
}

for (const file of ['springbones_wasm.wasm', 'springbones_crowd.wasm']) {
  test(`${file}: every entry point web/runtime_calls.js lists, and nothing else, with its parameters`, async () => {
    const exported = await exportedFunctions(file);
    const listed = Object.keys(kRuntimeCalls).map((name) => `sb_${name}`);
    assert.deepEqual([...exported.keys()].filter((name) => !kTextResult.includes(name)).sort(), listed.sort());
    for (const name of kTextResult) assert.ok(exported.has(name), `${name} is exported`);
    for (const [name, [argumentKinds]] of Object.entries(kRuntimeCalls)) {
      // A string argument is two parameters: its UTF-8 bytes' address and size.
      const parameters = [...argumentKinds].reduce((n, kind) => n + (kind === 's' ? 2 : 1), 0);
      assert.equal(exported.get(`sb_${name}`), parameters, `sb_${name}'s parameters for '${argumentKinds}'`);
    }
  });
}

test('a string crosses in and back whole: a models key outside ASCII, and the text results', async () => {
  const sb = await createSpringBones();
  const key = 'Qm-é-ключ-🦴';
  const { doc, springBones } = springRig({ hash: key });
  const rig = sb.loadRig(doc, springBones, { contentHash: key });
  assert.equal(rig.contentHash, key);
  assert.ok(rig.joints.length > 0, 'the entry under that key was found');
  // Booleans come back as booleans, and the module's text results as text.
  assert.equal(sb.crowd, false);
  const instance = rig.createInstance();
  assert.equal(instance.step(1 / 60), undefined);
  assert.equal(typeof sb.stats().heapInUse, 'number');
  // A text the core wrote about a key that came in: the warning's message and path carry it back.
  const other = sb.loadRig(doc, springBones, { contentHash: 'no-such-key-é' });
  assert.deepEqual(other.warnings.map(({ code, path }) => [code, path]), [['model-not-found', '/models/no-such-key-é']]);
  assert.match(other.warnings[0].message, /no entry for hash no-such-key-é \(it has: Qm-é-ключ-🦴\)/);
  other.dispose();
  instance.dispose();
  rig.dispose();
});
