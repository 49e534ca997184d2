// The built module itself: its size against the budget, and that the same two files load the way
// a browser loads them (fetched over HTTP relative to the page, streaming compilation), not only
// the way Node does (bytes read with fs).
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { createServer } from 'node:http';
import { join } from 'node:path';
import { test } from 'node:test';
import { gzipSync } from 'node:zlib';

import { createSpringBones, SpringBonesError } from '../../web/springbones.js';
import { loadFixtureRig, root } from './helpers.mjs';

const dist = join(root, 'web', 'dist');
const kBudgetBytes = 186 * 1024;  // docs/design.md, Numbers: wasm + js at most 186 KiB gzip

test('springbones_wasm.wasm + .js stay within 186 KiB gzip', () => {
  const sizes = ['springbones_wasm.js', 'springbones_wasm.wasm'].map((name) => {
    const bytes = readFileSync(join(dist, name));
    return { name, raw: bytes.length, gzip: gzipSync(bytes, { level: 9 }).length };
  });
  const total = sizes.reduce((sum, s) => sum + s.gzip, 0);
  console.log(sizes.map((s) => `${s.name}: ${s.raw} bytes, ${s.gzip} gzip`).join('; ') + `; total ${total} gzip`);
  assert.ok(total < kBudgetBytes, `${total} bytes gzip is over the budget of ${kBudgetBytes}`);
});

test('the glue is browser code: an ES module with no Node-only globals', () => {
  const glue = readFileSync(join(dist, 'springbones_wasm.js'), 'utf8');
  assert.match(glue, /export default createSpringBonesModule/);
  assert.match(glue, /import\.meta\.url/);
  for (const nodeOnly of ['require(', '__dirname', '__filename', 'process.versions']) {
    assert.ok(!glue.includes(nodeOnly), `the glue mentions ${nodeOnly}`);
  }
});

test('loads over HTTP like a browser: fetch + instantiateStreaming with application/wasm', async (t) => {
  const requests = [];
  const server = createServer((req, res) => {
    requests.push(req.url);
    if (req.url !== '/web/dist/springbones_wasm.wasm') {
      res.writeHead(404).end();
      return;
    }
    res.writeHead(200, { 'content-type': 'application/wasm' }).end(readFileSync(join(dist, 'springbones_wasm.wasm')));
  });
  await new Promise((resolve) => server.listen(0, '127.0.0.1', resolve));
  t.after(() => server.close());
  const base = `http://127.0.0.1:${server.address().port}/web/dist/`;

  const sb = await createSpringBones({ wasmUrl: new URL('springbones_wasm.wasm', base) });
  assert.deepEqual(requests, ['/web/dist/springbones_wasm.wasm']);
  const inst = loadFixtureRig(sb, 'avatar_hair.glb').createInstance();
  inst.driverMatrices[12] += 0.1;
  inst.step(1 / 60);
  assert.ok(inst.rotations.every(Number.isFinite));

  await assert.rejects(createSpringBones({ wasmUrl: new URL('missing.wasm', base) }),
                       (e) => e.code === 'module-load-failed');
});

test('takes the module from the page: a Response, a fetch promise, a WebAssembly.Module or its promise', async (t) => {
  const bytes = readFileSync(join(dist, 'springbones_wasm.wasm'));
  const server = createServer((req, res) => {
    if (req.url === '/ok.wasm') res.writeHead(200, { 'content-type': 'application/wasm' }).end(bytes);
    else if (req.url === '/octet.wasm') res.writeHead(200, { 'content-type': 'application/octet-stream' }).end(bytes);
    else if (req.url === '/garbage.wasm') res.writeHead(200, { 'content-type': 'application/wasm' }).end('not a module');
    else res.writeHead(404).end();
  });
  await new Promise((resolve) => server.listen(0, '127.0.0.1', resolve));
  t.after(() => server.close());
  const at = (path) => `http://127.0.0.1:${server.address().port}${path}`;
  const works = async (sb) => {
    const inst = loadFixtureRig(sb, 'avatar_hair.glb').createInstance();
    inst.driverMatrices[12] += 0.1;
    inst.step(1 / 60);
    assert.equal(inst.lastSteps, 1);
    assert.ok(inst.rotations.every(Number.isFinite));
  };

  await works(await createSpringBones({ wasm: fetch(at('/ok.wasm')) }));
  await works(await createSpringBones({ wasm: await fetch(at('/ok.wasm')) }));
  await works(await createSpringBones({ wasm: fetch(at('/octet.wasm')) }));  // compiled from its bytes
  await works(await createSpringBones({ wasm: WebAssembly.compile(bytes) }));
  await works(await createSpringBones({ wasm: await WebAssembly.compile(bytes) }));

  const failed = (pattern) => (e) => e instanceof SpringBonesError && e.code === 'module-load-failed' && pattern.test(e.message);
  await assert.rejects(createSpringBones({ wasm: fetch(at('/missing.wasm')) }), failed(/missing\.wasm.*HTTP 404/));
  await assert.rejects(createSpringBones({ wasm: fetch(at('/garbage.wasm')) }), failed(/garbage\.wasm/));
  await assert.rejects(createSpringBones({ wasm: Promise.reject(new Error('offline')) }), failed(/offline/));
  await assert.rejects(createSpringBones({ wasm: Promise.resolve('bytes') }), failed(/neither a Response nor a WebAssembly\.Module/));
  // A module that compiles but is not ours is refused, not run.
  const empty = new Uint8Array([0, 97, 115, 109, 1, 0, 0, 0]);
  await assert.rejects(createSpringBones({ wasm: WebAssembly.compile(empty) }), failed(/not the springbones module/));

  await assert.rejects(createSpringBones({ wasm: bytes }), TypeError);
  const pending = fetch(at('/ok.wasm'));
  await assert.rejects(createSpringBones({ wasm: pending, wasmBinary: bytes }), TypeError);
  await pending;
});
