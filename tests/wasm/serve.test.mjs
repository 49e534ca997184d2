// scripts/serve.mjs, the demo's server: the headers a preview relies on (streaming compilation,
// cross-origin isolation) and revalidation, so that a rebuilt module is never served stale while
// an unchanged one is a 304.
import assert from 'node:assert/strict';
import { mkdtempSync, rmSync, utimesSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { after, before, test } from 'node:test';

import { startServer } from '../../scripts/serve.mjs';

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
  assert.match(etag, /^"[0-9a-z]+-[0-9a-z]+"$/);

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
