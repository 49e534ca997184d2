// The typed encoding's one description (src/common/typed_encoding.json): the C++ header and the
// JavaScript module generated from it are up to date, and the runtime reads exactly the glTF node
// fields it lists, through the page's encoder and the readers alike.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { before, describe, test } from 'node:test';

import { description, headerText, kHeaderPath, kModulePath, moduleText } from '../../scripts/generate/make_typed_encoding.mjs';
import { kGltfNodeFields, kTypedLimits, kTypedTags } from '../../web/typed_encoding.js';
import { loadReaders } from '../../web/readers.js';
import { createSpringBones, SpringBonesError } from '../../web/springbones.js';
import { encodeTyped } from '../../web/typed_value.js';
import { decodeTyped } from './typed_decode.mjs';

let sb;
let readers;
before(async () => {
  sb = await createSpringBones();
  await sb.readers();
  readers = await loadReaders({});
});

describe('the description', () => {
  test('src/common/typed_encoding.h and web/typed_encoding.js are what the generator writes from the JSON', () => {
    const d = description();
    assert.equal(readFileSync(kHeaderPath, 'utf8'), headerText(d), 'run node scripts/generate/make_typed_encoding.mjs');
    assert.equal(readFileSync(kModulePath, 'utf8'), moduleText(d), 'run node scripts/generate/make_typed_encoding.mjs');
    assert.deepEqual({ ...kTypedTags }, d.tags);
    assert.deepEqual({ ...kTypedLimits }, d.limits);
  });

  test('the core decodes each tag as the description names it', () => {
    // One value of each kind, written by hand from the tags alone, read back by the runtime's
    // decoder through the rig options (the smallest typed entry point): {hitRadius: <number>}.
    const key = new TextEncoder().encode('hitRadius');
    const bytes = new Uint8Array([kTypedTags.object, 1, 0, 0, 0, key.length, 0, 0, 0, ...key, kTypedTags.number,
      ...new Uint8Array(new Float64Array([0.25]).buffer)]);
    assert.deepEqual(decodeTyped(bytes), { hitRadius: 0.25 });
    assert.deepEqual(encodeTyped('test', { hitRadius: 0.25 }), bytes);
    const doc = { asset: { version: '2.0' }, nodes: [{ name: 'Avatar_Head' }] };
    const rig = sb.loadRig(doc, null, { hitRadius: 0.25 });
    rig.dispose();
  });
});

describe('the glTF node fields', () => {
  // The page's document, and the same as glTF JSON text for the readers.
  const bothWays = (doc, check) => {
    check(() => sb.loadRig(doc, null), 'parsed');
    check(() => sb.loadRig(new TextEncoder().encode(JSON.stringify(doc)), null), 'bytes');
  };

  for (const field of kGltfNodeFields) {
    test(`'${field}' is read: a value of the wrong type is gltf-invalid through both front ends`, () => {
      const doc = { asset: { version: '2.0' }, nodes: [{ [field]: true }] };
      bothWays(doc, (load, how) => assert.throws(load, (e) => e instanceof SpringBonesError && e.code === 'gltf-invalid' &&
                                                 e.message.includes(field), how));
    });
  }

  test('a field not in the list is neither read nor copied, whatever it holds', () => {
    const doc = { asset: { version: '2.0' }, nodes: [{ name: 'a', mesh: true, skin: 'x', extras: { deep: [1] }, extensions: 1 }] };
    bothWays(doc, (load, how) => {
      const rig = load();
      assert.equal(rig.nodeCount, 1, how);
      rig.dispose();
    });
    assert.deepEqual(Object.keys(decodeTyped(readers.readGltf(new TextEncoder().encode(JSON.stringify(doc)), false)).nodes[0]), ['name']);
  });
});
