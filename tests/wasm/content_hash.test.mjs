// sb.contentHash against Decentraland's own hashing (npm @dcl/hashing hashV1, a test dependency):
// the chunk and tree boundaries, a file above 45 MiB, and every fixture.
import assert from 'node:assert/strict';
import { readdirSync } from 'node:fs';
import { before, describe, test } from 'node:test';

import hashing from '@dcl/hashing';  // a CommonJS bundle: Node sees only its default export

import { createSpringBones } from '../../web/springbones.js';
import { fixture, fixturesDir } from './helpers.mjs';

const { hashV1 } = hashing;

let sb;
before(async () => {
  sb = await createSpringBones();
});

// Bytes that differ from chunk to chunk, so a wrongly ordered or repeated leaf changes the hash.
function patterned(size) {
  const bytes = new Uint8Array(size);
  let x = 0x9e3779b9;
  for (let i = 0; i < size; ++i) {
    x ^= x << 13; x ^= x >>> 17; x ^= x << 5;
    bytes[i] = x & 0xff;
  }
  return bytes;
}

describe('contentHash equals @dcl/hashing hashV1', () => {
  // 0 and 1 byte; exactly one 256 KiB chunk; one byte into a second chunk (a dag-pb root);
  // several chunks; and 46,000,000 bytes: 176 leaves, more than the 174 links one node holds,
  // so the tree has a second level.
  for (const size of [0, 1, 262144, 262145, 1000000, 46000000]) {
    test(`${size} bytes`, async () => {
      const bytes = patterned(size);
      const expected = await hashV1(bytes);
      assert.equal(sb.contentHash(bytes), expected);
      assert.equal(sb.contentHash(bytes.buffer), expected, 'an ArrayBuffer hashes the same');
    });
  }

  test('a subarray hashes only its own bytes', async () => {
    const bytes = patterned(300000);
    const part = bytes.subarray(1000, 263145);
    assert.equal(sb.contentHash(part), await hashV1(part.slice()));
  });

  test('every fixture', async () => {
    const names = readdirSync(fixturesDir).filter((n) => !n.startsWith('.')).sort();
    assert.ok(names.length >= 10);
    for (const name of names) {
      const bytes = fixture(name);
      assert.equal(sb.contentHash(bytes), await hashV1(new Uint8Array(bytes)), name);
    }
  });

  test('bad arguments are TypeErrors and the module keeps hashing', () => {
    for (const bad of [undefined, null, 'text', 42, [1, 2], new Float32Array(2), new DataView(new ArrayBuffer(2))]) {
      assert.throws(() => sb.contentHash(bad), TypeError);
    }
    assert.match(sb.contentHash(new Uint8Array([1, 2, 3])), /^bafkrei[a-z2-7]{52}$/);
  });
});
