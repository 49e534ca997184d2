// The built modules themselves: each one's size against its budget, that the same files load the
// way a browser loads them (fetched over HTTP relative to the page, streaming compilation), not only
// the way Node does (bytes read with fs), and that the minified bundles the package ships (written
// by scripts/lib/minify.mjs) and the inline entry are the same API.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { createServer } from 'node:http';
import { join } from 'node:path';
import { test } from 'node:test';
import { gzipSync } from 'node:zlib';

import { createSpringBones, SpringBonesError } from '../../web/springbones.js';
import { loadFixtureRig, root, springRig } from './helpers.mjs';

const dist = join(root, 'web', 'dist');

// docs/design.md, "Numbers": each module as a page downloads it (the .wasm and its minified glue),
// gzip -9, at its measured size plus 2%.
const kBudgets = [
  { module: 'runtime', files: ['springbones_wasm.wasm', 'springbones_wasm.min.js'], measured: 91807 },
  // The crowd module runs on the runtime's glue (tests/wasm/crowd.test.mjs).
  { module: 'crowd', files: ['springbones_crowd.wasm', 'springbones_wasm.min.js'], measured: 113166 },
  { module: 'readers', files: ['springbones_readers.wasm', 'springbones_readers.min.js'], measured: 72536 },
  { module: 'creator tools', files: ['springbones_creator_tools.wasm', 'springbones_creator_tools.min.js'], measured: 98471 },
];
for (const { module, files, measured } of kBudgets) {
  const budget = Math.round(measured * 1.02);
  test(`the ${module} module (${files.join(' + ')}) stays within ${budget} bytes gzip (${measured} + 2%)`, () => {
    const sizes = files.map((name) => {
      const bytes = readFileSync(join(dist, name));
      return { name, raw: bytes.length, gzip: gzipSync(bytes, { level: 9 }).length };
    });
    const total = sizes.reduce((sum, s) => sum + s.gzip, 0);
    console.log(sizes.map((s) => `${s.name}: ${s.raw} bytes, ${s.gzip} gzip`).join('; ') + `; total ${total} gzip`);
    assert.ok(total <= budget, `${total} bytes gzip is over the budget of ${budget}`);
  });
}

test('the minified API, its creator tools and the inline entry work as the sources do', async () => {
  const minified = await import('../../web/dist/springbones.min.js');
  const inline = await import('../../web/dist/inline.min.js');
  assert.equal(inline.SpringBonesError, minified.SpringBonesError, 'the inline entry is the API over the inlined module');
  for (const { createSpringBones: create, SpringBonesError: ErrorClass } of [minified, inline]) {
    const sb = await create();
    const { glb, springBones, hash } = springRig();
    const inst = sb.loadRig(glb, springBones, { contentHash: hash }).createInstance();
    inst.driverMatrices[12] += 0.1;
    inst.step(1 / 60);
    assert.ok(inst.rotations.every(Number.isFinite));
    assert.throws(() => sb.loadRig(new Uint8Array(8)), (e) => e instanceof ErrorClass && e.code === 'glb-bad-magic');
    const tools = await sb.creatorTools();
    assert.equal(tools.detectSpringBones(glb).length, 4);
    assert.throws(() => tools.validateSpringBones('{'), (e) => e instanceof ErrorClass && e.code === 'entity-bad-json');
  }
});

test('the inline entry from source: the inlined module by default, another when given', async () => {
  const inline = await import('../../web/inline.js');
  assert.equal(inline.SpringBonesError, SpringBonesError);
  const sb = await inline.createSpringBones();
  assert.equal(sb.loadRig(springRig().glb, springRig().springBones, { contentHash: 'test-hash' }).joints.length, 3);
  await assert.rejects(inline.createSpringBones({ wasmUrl: './does-not-exist.wasm' }),
                       (e) => e instanceof SpringBonesError && e.code === 'module-load-failed');
  await assert.rejects(inline.createSpringBones(42), TypeError);
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
