// A tiny static HTTP server for the demo: serves the repository root (the page imports three from
// node_modules/ and the WebAssembly module from web/dist/), with the MIME types browsers insist
// on (application/wasm for streaming compilation, text/javascript for modules). A request that
// accepts gzip gets the file gzip-encoded, as a CDN serves it (images, already compressed, as they
// are); the compressed bytes are kept in memory per file version.
//
//   node scripts/lib/serve.mjs [--port 8080] [--host 127.0.0.1]
//
// Also imported by tests/browser/ and the benchmark (startServer) to serve on a free port
// in-process. No dependencies beyond node's own modules.
import { createReadStream, readFileSync, statSync } from 'node:fs';
import { createServer } from 'node:http';
import { extname, join, normalize, resolve, sep } from 'node:path';
import { fileURLToPath } from 'node:url';
import { gzipSync } from 'node:zlib';

const repoRoot = resolve(fileURLToPath(new URL('../..', import.meta.url)));

const MIME = {
  '.html': 'text/html; charset=utf-8',
  '.js': 'text/javascript; charset=utf-8',
  '.mjs': 'text/javascript; charset=utf-8',
  '.css': 'text/css; charset=utf-8',
  '.json': 'application/json; charset=utf-8',
  '.map': 'application/json; charset=utf-8',
  '.wasm': 'application/wasm',
  '.glb': 'model/gltf-binary',
  '.gltf': 'model/gltf+json',
  '.bin': 'application/octet-stream',
  '.png': 'image/png',
  '.jpg': 'image/jpeg',
  '.svg': 'image/svg+xml',
  '.ico': 'image/x-icon',
  '.txt': 'text/plain; charset=utf-8',
  '.md': 'text/markdown; charset=utf-8',
  '.ts': 'text/plain; charset=utf-8',  // .d.ts files, for reading in the browser
};

// Formats that are compressed already: sent as they are.
const kIncompressible = new Set(['.png', '.jpg', '.ico']);

/** `Accept-Encoding` allows gzip (no q=0 for it). */
function acceptsGzip(header) {
  return String(header ?? '').split(',').some((part) => {
    const [coding, ...params] = part.trim().toLowerCase().split(';');
    if (coding !== 'gzip' && coding !== '*') return false;
    const q = params.map((p) => p.trim()).find((p) => p.startsWith('q='));
    return q === undefined || Number(q.slice(2)) > 0;
  });
}

/**
 * Starts serving `root`; resolves to { server, url } once listening. port 0 picks a free port.
 * isolated (default true): COOP/COEP headers, so pages are cross-origin isolated (the demo's
 * 5 us timer); false serves like an ordinary host, e.g. a marketplace's preview iframe.
 * cacheControl (default 'no-cache', below): the Cache-Control of every file; the benchmark's second
 * visit also measures a host that lets browsers keep files without asking ('max-age=600').
 */
export function startServer({ port = 8080, host = '127.0.0.1', root = repoRoot, log = false, isolated = true, cacheControl = 'no-cache' } = {}) {
  if (typeof cacheControl !== 'string' || cacheControl === '' || /[\r\n]/.test(cacheControl)) {
    throw new TypeError('startServer: cacheControl must be a header value (e.g. "no-cache", "max-age=600")');
  }
  const gzipCache = new Map();  // file -> { etag, bytes }
  const gzipped = (file, etag) => {
    let entry = gzipCache.get(file);
    if (entry?.etag !== etag) {
      entry = { etag, bytes: gzipSync(readFileSync(file), { level: 9 }) };
      gzipCache.set(file, entry);
    }
    return entry.bytes;
  };
  const server = createServer((req, res) => {
    const send = (status, text) => {
      res.writeHead(status, { 'Content-Type': 'text/plain; charset=utf-8', 'Cache-Control': 'no-store' });
      res.end(req.method === 'HEAD' ? undefined : text);
    };
    if (req.method !== 'GET' && req.method !== 'HEAD') return send(405, 'method not allowed\n');
    let pathname;
    try {
      pathname = decodeURIComponent(new URL(req.url, 'http://localhost').pathname);
    } catch {
      return send(400, 'bad request\n');
    }
    if (pathname === '/') {
      res.writeHead(302, { Location: '/web/demo/' });
      return res.end();
    }
    // Resolve inside root only: no "..", no NUL, no escaping through an absolute path.
    const file = normalize(join(root, pathname));
    if (pathname.includes('\0') || (file !== root && !file.startsWith(root + sep))) return send(403, 'forbidden\n');
    let target = file;
    let stat;
    try {
      stat = statSync(target);
      if (stat.isDirectory()) {
        if (!pathname.endsWith('/')) {
          res.writeHead(301, { Location: pathname + '/' });
          return res.end();
        }
        target = join(target, 'index.html');
        stat = statSync(target);
      }
    } catch {
      if (log) console.log(`404 ${pathname}`);
      return send(404, `not found: ${pathname}\n`);
    }
    // Kept by the browser but revalidated on every use: a rebuilt file (new size or mtime) is
    // always the one served, and an unchanged one is a 304, so Chromium reuses its cached copy and,
    // for the .wasm, the machine code it cached from compiling it on an earlier visit.
    // The gzip encoding is another representation: its own ETag, and caches keyed on the header.
    const extension = extname(target).toLowerCase();
    const gzip = !kIncompressible.has(extension) && acceptsGzip(req.headers['accept-encoding']);
    const version = `${stat.size.toString(36)}-${Math.floor(stat.mtimeMs).toString(36)}`;
    const etag = gzip ? `"${version}-gz"` : `"${version}"`;
    const headers = {
      'Cache-Control': cacheControl,
      ETag: etag,
      Vary: 'Accept-Encoding',
    };
    if (isolated) {
      // Cross-origin isolation: everything is same-origin, and an isolated page gets a 5 us
      // performance.now() instead of 100 us, which the demo's per-frame solver readout needs.
      headers['Cross-Origin-Opener-Policy'] = 'same-origin';
      headers['Cross-Origin-Embedder-Policy'] = 'require-corp';
    }
    if (req.headers['if-none-match'] === etag) {
      res.writeHead(304, headers);
      return res.end();
    }
    const type = MIME[extension] ?? 'application/octet-stream';
    if (gzip) {
      let body;
      try {
        body = gzipped(target, etag);
      } catch {
        return send(404, `not found: ${pathname}\n`);
      }
      res.writeHead(200, { ...headers, 'Content-Type': type, 'Content-Encoding': 'gzip', 'Content-Length': body.length });
      return res.end(req.method === 'HEAD' ? undefined : body);
    }
    res.writeHead(200, { ...headers, 'Content-Type': type, 'Content-Length': stat.size });
    if (req.method === 'HEAD') return res.end();
    createReadStream(target).on('error', () => res.destroy()).pipe(res);
  });
  return new Promise((resolvePromise, reject) => {
    server.once('error', reject);
    server.listen(port, host, () => {
      const { port: actual } = server.address();
      const shownHost = host.includes(':') ? `[${host}]` : host;
      resolvePromise({ server, url: `http://${shownHost}:${actual}/` });
    });
  });
}

// Command line
if (process.argv[1] && resolve(process.argv[1]) === fileURLToPath(import.meta.url)) {
  const args = process.argv.slice(2);
  const option = (name, fallback) => {
    const i = args.indexOf(`--${name}`);
    return i >= 0 && i + 1 < args.length ? args[i + 1] : (process.env[name.toUpperCase()] ?? fallback);
  };
  const port = Number(option('port', 8080));
  const host = option('host', '127.0.0.1');
  if (!Number.isInteger(port) || port < 0 || port > 65535) {
    console.error(`serve: bad port ${option('port')}`);
    process.exit(2);
  }
  try {
    const { url } = await startServer({ port, host, log: true });
    console.log(`springbones demo: ${url}web/demo/`);
    console.log('(Ctrl+C to stop)');
  } catch (e) {
    console.error(`serve: cannot listen on ${host}:${port}: ${e.message}` +
      (e.code === 'EADDRINUSE' ? ' (try --port 0 for a free port)' : ''));
    process.exit(1);
  }
}
