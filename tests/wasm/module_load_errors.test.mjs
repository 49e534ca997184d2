// A module that fails to load says what was fetched and what came back, in our words: the URL, the
// HTTP status, the content type when it is not application/wasm, and how a page served in the
// module's place begins. None of Emscripten's abort texts ("Aborted(...)", "-s ASSERTIONS=1") or
// its warnings ("wasm streaming compile failed", "falling back to ArrayBuffer instantiation")
// reach the caller or the console. A local server answers each case as a misconfigured host would.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { createServer } from 'node:http';
import { join } from 'node:path';
import { after, before, test } from 'node:test';

import { createSpringBones, SpringBonesError } from '../../web/springbones.js';
import { root } from './helpers.mjs';

const kPage = '<!doctype html>\n<html><head><title>My shop</title></head><body>Not here</body></html>\n';
const wasmBytes = readFileSync(join(root, 'web', 'dist', 'springbones_wasm.wasm'));

let server;
let base;
before(async () => {
  server = createServer((req, res) => {
    if (req.url === '/missing.wasm') res.writeHead(404, { 'content-type': 'text/html' }).end(kPage);
    else if (req.url === '/spa.wasm') res.writeHead(200, { 'content-type': 'text/html; charset=utf-8' }).end(kPage);
    else if (req.url === '/forbidden.wasm') res.writeHead(403, { 'content-type': 'application/wasm' }).end();
    else if (req.url === '/truncated.wasm') res.writeHead(200, { 'content-type': 'application/wasm' }).end(wasmBytes.subarray(0, 100));
    else if (req.url === '/octet.wasm') res.writeHead(200, { 'content-type': 'application/octet-stream' }).end(wasmBytes);
    else if (req.url === '/json.wasm') res.writeHead(200, { 'content-type': 'application/json' }).end('{"error":"no such object"}');
    else res.writeHead(500).end();
  });
  await new Promise((resolve) => server.listen(0, '127.0.0.1', resolve));
  base = `http://127.0.0.1:${server.address().port}`;
});
after(() => server.close());

// Runs `fn` with the console's output collected instead of printed.
async function consoleOutput(fn) {
  const printed = [];
  const saved = {};
  for (const level of ['log', 'info', 'warn', 'error', 'debug']) {
    saved[level] = console[level];
    console[level] = (...args) => printed.push(`${level}: ${args.join(' ')}`);
  }
  try {
    await fn();
  } finally {
    Object.assign(console, saved);
  }
  return printed;
}

// The load error for `options`, checked to be ours, with no Emscripten text in it or its causes
// and nothing printed.
async function loadError(options, load = createSpringBones) {
  let error;
  const printed = await consoleOutput(async () => {
    error = await load(options).then(() => null, (e) => e);
  });
  assert.ok(error instanceof SpringBonesError, `expected a SpringBonesError, got ${error}`);
  assert.equal(error.code, 'module-load-failed');
  for (let e = error; e; e = e.cause) {
    assert.doesNotMatch(String(e.message ?? e), /Aborted|ASSERTIONS|magic word|falling back|streaming compile failed/);
  }
  assert.deepEqual(printed, [], 'nothing printed on the console');
  return error;
}

test('a 404 names the URL fetched, the status and the content type that is not application/wasm', async () => {
  const e = await loadError({ wasmUrl: `${base}/missing.wasm` });
  assert.ok(e.message.includes(`${base}/missing.wasm`), e.message);
  assert.match(e.message, /HTTP 404 Not Found \(text\/html, not application\/wasm\)/);
  assert.match(e.message, /wasmUrl/, 'and says how to point at the module');
});

test('an HTML page served with 200 where the module should be says so and quotes how it begins', async () => {
  const e = await loadError({ wasmUrl: `${base}/spa.wasm` });
  assert.ok(e.message.includes(`${base}/spa.wasm`), e.message);
  assert.match(e.message, /HTTP 200 OK \(text\/html, not application\/wasm\)/);
  assert.match(e.message, /not WebAssembly \(it begins "<!doctype html> <html><head><title>My sh/);
});

test('other answers: a status with application/wasm, a JSON error, a module cut short', async () => {
  const forbidden = await loadError({ wasmUrl: `${base}/forbidden.wasm` });
  assert.match(forbidden.message, /HTTP 403 Forbidden;/, 'no content-type note when it is application/wasm');
  const json = await loadError({ wasmUrl: `${base}/json.wasm` });
  assert.match(json.message, /\(application\/json, not application\/wasm\).*it begins "\{"error":"no such object"\}"/);
  const truncated = await loadError({ wasmUrl: `${base}/truncated.wasm` });
  assert.match(truncated.message, /HTTP 200 OK with application\/wasm, and it does not compile/);
});

test('the same words for a Response the page fetched, and for bytes that are not a module', async () => {
  const e = await loadError({ wasm: fetch(`${base}/spa.wasm`) });
  assert.ok(e.message.includes(`${base}/spa.wasm`), e.message);
  assert.match(e.message, /HTTP 200 OK \(text\/html, not application\/wasm\).*it begins "<!doctype html>/);
  const bytes = await loadError({ wasmBinary: new TextEncoder().encode(kPage) });
  assert.match(bytes.message, /\(the wasmBinary option\).*not WebAssembly \(it begins "<!doctype/);
  const binary = await loadError({ wasmBinary: new Uint8Array([1, 2, 3, 250]) });
  assert.match(binary.message, /it begins with the bytes 01 02 03 fa/);
  const empty = await loadError({ wasmBinary: new Uint8Array(0) });
  assert.match(empty.message, /it is empty/);
});

test('the creator tools and the readers report a bad URL alike', async () => {
  const sb = await createSpringBones();
  const tools = await loadError({ wasmUrl: `${base}/missing.wasm` }, (options) => sb.creatorTools(options));
  assert.match(tools.message, /missing\.wasm.*HTTP 404 Not Found/);
  const { loadReaders } = await import('../../web/readers.js');
  const readers = await loadError({ wasmUrl: `${base}/spa.wasm` }, loadReaders);
  assert.match(readers.message, /spa\.wasm.*not WebAssembly/);
});

test('a server that sends the module as application/octet-stream still works, compiled from its bytes', async () => {
  let sb;
  const printed = await consoleOutput(async () => {
    sb = await createSpringBones({ wasmUrl: `${base}/octet.wasm` });
  });
  assert.deepEqual(printed, []);
  assert.equal(typeof sb.contentHash(new Uint8Array([1, 2, 3])), 'string');
});

test('a host that cannot be reached says the fetch failed before any answer', async () => {
  const closed = createServer();
  await new Promise((resolve) => closed.listen(0, '127.0.0.1', resolve));
  const { port } = closed.address();
  await new Promise((resolve) => closed.close(resolve));
  const e = await loadError({ wasmUrl: `http://127.0.0.1:${port}/springbones_wasm.wasm` });
  assert.match(e.message, new RegExp(`127\\.0\\.0\\.1:${port}/springbones_wasm\\.wasm.*fetching it failed`));
});
