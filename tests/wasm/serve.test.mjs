// scripts/lib/serve.mjs, the demo's server: the headers a preview relies on (streaming compilation,
// cross-origin isolation) and revalidation, so that a rebuilt module is never served stale while
// an unchanged one is a 304; gzip for a request that accepts it, as a CDN serves files.
import assert from 'node:assert/strict';
import { mkdtempSync, rmSync, utimesSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { request } from 'node:http';
import { join } from 'node:path';
import { after, before, test } from 'node:test';
import { gunzipSync } from 'node:zlib';

import { startServer } from '../../scripts/lib/serve.mjs';

let root, server, url;
before(async () => {
  root = mkdtempSync(join(tmpdir(), 'springbones-serve-'));
  writeFileSync(join(root, 'm.wasm'), 'first build');
  ({ server, url } = await startServer({ port: 0, root }));
});
after(() => {
  server.close();
  rmSync(root, { recursive: true, force: true });
});

test('serves the module for streaming compilation, cross-origin isolated, revalidated on every use', async () => {
  const first = await fetch(new URL('m.wasm', url));
  assert.equal(first.status, 200);
  assert.equal(first.headers.get('content-type'), 'application/wasm');
  assert.equal(first.headers.get('cache-control'), 'no-cache');
  assert.equal(first.headers.get('cross-origin-opener-policy'), 'same-origin');
  assert.equal(first.headers.get('cross-origin-embedder-policy'), 'require-corp');
  assert.equal(await first.text(), 'first build');
  const etag = first.headers.get('etag');
  assert.match(etag, /^"[0-9a-z]+-[0-9a-z]+(-gz)?"$/);

  const unchanged = await fetch(new URL('m.wasm', url), { headers: { 'If-None-Match': etag } });
  assert.equal(unchanged.status, 304);
  assert.equal(unchanged.headers.get('etag'), etag);

  // A rebuild (new bytes, new mtime) is served in full under a new ETag.
  writeFileSync(join(root, 'm.wasm'), 'second build, longer');
  const later = new Date(Date.now() + 5000);
  utimesSync(join(root, 'm.wasm'), later, later);
  const rebuilt = await fetch(new URL('m.wasm', url), { headers: { 'If-None-Match': etag } });
  assert.equal(rebuilt.status, 200);
  assert.notEqual(rebuilt.headers.get('etag'), etag);
  assert.equal(await rebuilt.text(), 'second build, longer');
});

test('refuses paths outside its root and answers 404 for missing files', async () => {
  assert.equal((await fetch(new URL('missing.wasm', url))).status, 404);
  assert.equal((await fetch(`${url}..%2f..%2fetc%2fpasswd`)).status, 403);  // decoded after the URL is resolved
});

/** A GET with exactly these headers (fetch would add its own Accept-Encoding and decode). */
function get(path, headers = {}) {
  return new Promise((resolve, reject) => {
    request(new URL(path, url), { headers, agent: false }, (res) => {
      const chunks = [];
      res.on('data', (c) => chunks.push(c));
      res.on('end', () => resolve({ status: res.statusCode, headers: res.headers, body: Buffer.concat(chunks) }));
    }).on('error', reject).end();
  });
}

test('gzip when the request accepts it, with its own ETag and 304; identity otherwise', async () => {
  writeFileSync(join(root, 'g.js'), 'export const x = 1;\n'.repeat(200));
  const plain = await get('g.js');
  assert.equal(plain.headers['content-encoding'], undefined);
  assert.equal(plain.body.toString(), 'export const x = 1;\n'.repeat(200));
  const zipped = await get('g.js', { 'Accept-Encoding': 'br, gzip;q=0.8' });
  assert.equal(zipped.headers['content-encoding'], 'gzip');
  assert.equal(zipped.headers.vary, 'Accept-Encoding');
  assert.equal(Number(zipped.headers['content-length']), zipped.body.length);
  assert.ok(zipped.body.length < plain.body.length / 10, 'compressed');
  assert.equal(gunzipSync(zipped.body).toString(), plain.body.toString());
  assert.notEqual(zipped.headers.etag, plain.headers.etag, 'another representation, another ETag');
  const again = await get('g.js', { 'Accept-Encoding': 'gzip', 'If-None-Match': zipped.headers.etag });
  assert.equal(again.status, 304);
  assert.equal((await get('g.js', { 'Accept-Encoding': 'gzip;q=0' })).headers['content-encoding'], undefined);
  // A rebuilt file is compressed again, not served from the kept copy.
  writeFileSync(join(root, 'g.js'), 'export const y = 2;\n'.repeat(300));
  const later = new Date(Date.now() + 5000);
  utimesSync(join(root, 'g.js'), later, later);
  const rebuilt = await get('g.js', { 'Accept-Encoding': 'gzip', 'If-None-Match': zipped.headers.etag });
  assert.equal(rebuilt.status, 200);
  assert.equal(gunzipSync(rebuilt.body).toString(), 'export const y = 2;\n'.repeat(300));
});

test('isolated: false serves without the cross-origin isolation headers', async () => {
  const plain = await startServer({ port: 0, root, isolated: false });
  try {
    const response = await fetch(new URL('m.wasm', plain.url));
    assert.equal(response.status, 200);
    assert.equal(response.headers.get('cross-origin-opener-policy'), null);
    assert.equal(response.headers.get('cross-origin-embedder-policy'), null);
  } finally {
    plain.server.close();
  }
});

test('cacheControl: every file under that Cache-Control, still with its ETag; a bad value is refused', async () => {
  const cached = await startServer({ port: 0, root, isolated: false, cacheControl: 'max-age=600' });
  try {
    const response = await fetch(new URL('m.wasm', cached.url));
    assert.equal(response.status, 200);
    assert.equal(response.headers.get('cache-control'), 'max-age=600');
    assert.match(response.headers.get('etag'), /^"[0-9a-z]+-[0-9a-z]+(-gz)?"$/);
  } finally {
    cached.server.close();
  }
  for (const bad of ['', 'max-age=1\r\nX-Injected: 1', 600]) {
    assert.throws(() => startServer({ port: 0, root, cacheControl: bad }), /cacheControl must be a header value/);
  }
});
