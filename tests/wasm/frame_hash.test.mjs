// One answer everywhere, Node's part: 1,000 frames of the sample wearable and of the three VRM
// fixtures under the scripted sway give bit-identical rotations natively and in Node's
// WebAssembly, in both builds of the runtime (the hash of every frame's rotations,
// tests/scenarios/frame_hash.mjs).
// tests/browser/frame_hash.test.mjs checks Chromium against the same native hashes.
import assert from 'node:assert/strict';
import { readFile } from 'node:fs/promises';
import { join } from 'node:path';
import { test } from 'node:test';

import { createSpringBones } from '../../web/springbones.js';
import { frameHashes } from '../scenarios/frame_hash.mjs';
import { nativeFrameHashes } from '../scenarios/native_frame_hashes.mjs';
import { root } from './helpers.mjs';

// Both builds of the runtime: the runtime module (its per-frame path at -Oz, scalar) and the crowd
// module (-O3, SIMD).
for (const crowd of [false, true]) {
  const module = crowd ? 'the crowd module' : 'the runtime module';
  test(`1,000 frames hash the same natively and in Node, in ${module}`, async (t) => {
    const native = nativeFrameHashes();
    const sb = await createSpringBones({ crowd });
    assert.equal(sb.crowd, crowd);
    const node = await frameHashes(sb, async (path) => new Uint8Array(await readFile(join(root, path))));
    for (const [name, { joints, hash }] of Object.entries(native)) {
      t.diagnostic(`${name} (${joints} joints): native ${hash}, Node ${node[name].hash}`);
    }
    assert.deepEqual(node, native);
    // A different answer per rig: the hash depends on the rig, so equal hashes are not a constant.
    assert.equal(new Set(Object.values(node).map((h) => h.hash)).size, Object.keys(native).length);
  });
}
