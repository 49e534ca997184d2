// Fetching, compiling and instantiating one of the WebAssembly modules (the runtime for
// createSpringBones, the readers, the creator tools for sb.creatorTools) from the options they all
// take: `wasm` (a download the page started), `wasmBinary` (the bytes) or `wasmUrl` (where the
// .wasm is).
//
// The .wasm is always compiled here and handed to the Emscripten glue compiled (its
// instantiateWasm hook), never fetched or compiled by the glue: a 404 or an HTML page where the
// module should be is then reported with the URL, the HTTP status and the content type, and none
// of the glue's own warnings ("wasm streaming compile failed", "falling back to ArrayBuffer
// instantiation") or abort texts ("Aborted(...)") reach the page. In Node a file: URL is read with
// fs (the glue is built for the web only, see wasm/CMakeLists.txt); elsewhere it is fetched and
// compiled while it streams when the server sends application/wasm.

import { checkKeys } from './arguments.js';
import { SpringBonesError, withCause } from './errors.js';

/**
 * A key of createSpringBones's options, for the entries that supply the module themselves
 * (inline.js): what a load error calls `wasmBinary` (e.g. 'the inline module'). A symbol, so that
 * it is no option a caller can give or misspell (checkKeys sees string keys only).
 */
export const kBinarySource = Symbol('springbones.binarySource');

// What each instantiated module was read from (its Module object -> a description), for errors
// after instantiation (createSpringBones reading the module's limits).
const sources = new WeakMap();

/** What `module` (an instantiateModule result) was read from, as load errors name it. */
export function moduleSource(module) {
  return sources.get(module) ?? 'the WebAssembly module';
}

export const kIsNode =
  typeof process === 'object' && process !== null && typeof process.versions === 'object' &&
  process.versions !== null && typeof process.versions.node === 'string';

/**
 * The instantiated module (the glue's Module object).
 * @param {string} where the public call, for messages ("createSpringBones", "creatorTools")
 * @param {object} options the caller's options, checked here
 * @param {{importGlue: () => Promise<{default: Function}>, glueFile: string, defaultUrl: URL}} module
 *   importGlue imports the module's Emscripten glue (a literal import() in the caller, so that
 *   bundlers see it); glueFile names it in messages; defaultUrl is the .wasm beside it.
 */
export async function instantiateModule(where, options, { importGlue, glueFile, defaultUrl }) {
  if (options === null || typeof options !== 'object') {
    throw new TypeError(`${where}: options must be an object`);
  }
  checkKeys(where, options, ['wasm', 'wasmBinary', 'wasmUrl']);
  const { wasm, wasmBinary, wasmUrl } = options;
  const given = [wasm, wasmBinary, wasmUrl].filter((x) => x !== undefined).length;
  if (given > 1) throw new TypeError(`${where}: give one of wasm, wasmBinary and wasmUrl`);
  if (wasm !== undefined && !(wasm instanceof WebAssembly.Module || isResponse(wasm) || typeof wasm?.then === 'function')) {
    throw new TypeError(`${where}: wasm must be a Response, a WebAssembly.Module or a promise of one`);
  }
  if (wasmBinary !== undefined && !(wasmBinary instanceof ArrayBuffer || wasmBinary instanceof Uint8Array)) {
    throw new TypeError(`${where}: wasmBinary must be an ArrayBuffer or a Uint8Array`);
  }
  if (wasmUrl !== undefined && typeof wasmUrl !== 'string' && !(wasmUrl instanceof URL)) {
    throw new TypeError(`${where}: wasmUrl must be a string or a URL`);
  }
  const url = wasmUrl === undefined ? defaultUrl : new URL(wasmUrl, defaultUrl);

  // What is read, for the error: the option that gave the module, or the URL fetched or read.
  const loading = {
    source: wasm !== undefined ? 'the wasm option'
      : wasmBinary !== undefined ? (options[kBinarySource] ?? 'the wasmBinary option') : url.href,
  };
  // The module is fetched and compiled while the glue is imported, not after it: each is a request
  // (on a page's second visit a revalidation), and one after the other they were two round trips
  // where one will do (docs/performance.md, "Cold start of a preview"). Its errors wait for the
  // glue's, which come first as before.
  const compiling = compiledModule({ wasm, wasmBinary, url }, loading);
  compiling.catch(() => {});  // awaited below

  let factory;
  try {
    ({ default: factory } = await importGlue());
  } catch (cause) {
    throw withCause(new SpringBonesError('module-not-found',
        `the WebAssembly module (${glueFile}) could not be imported; build it ` +
        `with scripts/build wasm (${cause?.message ?? cause})`), cause);
  }

  try {
    const compiled = await compiling;
    // The glue waits for the instance forever if instantiateWasm fails: the race reports it.
    let receive;
    const instantiationFailed = new Promise((_, reject) => {
      receive = (imports, receiveInstance) => {
        WebAssembly.instantiate(compiled, imports).then((instance) => receiveInstance(instance, compiled)).catch(reject);
        return {};
      };
    });
    const module = await Promise.race([factory({ instantiateWasm: receive }), instantiationFailed]);
    sources.set(module, loading.source);
    return module;
  } catch (cause) {
    throw loadFailed(loading.source, cause);
  }
}

// The module compiled from whichever option gave it (`url` when none did).
async function compiledModule({ wasm, wasmBinary, url }, loading) {
  if (wasm !== undefined) return compileGiven(wasm, loading);
  if (wasmBinary !== undefined) return compileBytes(wasmBinary);
  if (kIsNode && url.protocol === 'file:') {
    // A specifier built at run time: bundlers for the browser (Vite) then neither resolve nor warn about it.
    const { readFile } = await import(/* webpackIgnore: true */ /* @vite-ignore */ ['node:fs', 'promises'].join('/'));
    return compileBytes(await readFile(url));
  }
  let response;
  try {
    response = await fetch(url.href);
  } catch (cause) {
    throw withCause(new Error(`fetching it failed (${cause?.message ?? cause}), before any answer came`), cause);
  }
  return compileResponse(response, loading);
}

/** The 'module-load-failed' error for a module from `source` (a URL or the option's name). */
export function loadFailed(source, cause) {
  return withCause(new SpringBonesError('module-load-failed',
      `the WebAssembly module (${source}) could not be loaded: ${cause?.message ?? cause}`), cause);
}

const isResponse = (x) => typeof Response === 'function' && x instanceof Response;

/**
 * The `wasm` option as a compiled module: a Response (or its promise, e.g. a fetch the page started
 * before importing this library) compiles as compileResponse does.
 */
async function compileGiven(wasm, loading) {
  const given = await wasm;
  if (given instanceof WebAssembly.Module) {
    if (!WebAssembly.Module.exports(given).some((e) => e.kind === 'memory')) {
      throw new TypeError('the WebAssembly.Module given is not the springbones module (it exports no memory)');
    }
    return given;
  }
  if (!isResponse(given)) throw new TypeError('the wasm option resolved to neither a Response nor a WebAssembly.Module');
  loading.source = given.url || 'a Response';
  return compileResponse(given, loading);
}

/**
 * What a server answered, compiled: while it streams when it is application/wasm, else from its
 * bytes once they are checked to be WebAssembly. An answer that is not the module is an error that
 * says what came back: the HTTP status, the content type when it is not application/wasm, and for
 * a page served in the module's place (a 200 with an SPA's index.html) how its bytes begin.
 */
async function compileResponse(response, loading) {
  if (response.url) loading.source = response.url;
  const type = (response.headers.get('Content-Type') ?? '').split(';')[0].trim().toLowerCase();
  const answer = `the server answered HTTP ${`${response.status} ${response.statusText}`.trim()}` +
      (type === 'application/wasm' ? '' : ` (${type === '' ? 'no content type' : type}, not application/wasm)`);
  if (!response.ok) throw new Error(`${answer}; serve the .wasm at that URL, or give its URL as wasmUrl`);
  if (type === 'application/wasm' && typeof WebAssembly.compileStreaming === 'function') {
    try {
      return await WebAssembly.compileStreaming(response);
    } catch (cause) {
      throw withCause(new Error(`${answer} with application/wasm, and it does not compile (${cause?.message ?? cause})`), cause);
    }
  }
  return compileBytes(new Uint8Array(await response.arrayBuffer()), `${answer}, and `);
}

const kWasmMagic = [0x00, 0x61, 0x73, 0x6d];  // '\0asm', the first 4 bytes of every WebAssembly binary

/**
 * Bytes compiled once they are checked to begin as WebAssembly (the compiler's own message for a
 * page would be "expected magic word 00 61 73 6d, found 3c 21 64 6f"); `said` begins the error.
 */
async function compileBytes(bytes, said = '') {
  const view = bytes instanceof Uint8Array ? bytes : new Uint8Array(bytes);
  if (!kWasmMagic.every((b, i) => view[i] === b)) {
    throw new Error(`${said}it is not WebAssembly (${firstBytes(view)})`);
  }
  return WebAssembly.compile(view);
}

// How some bytes begin, as a person would recognise them: quoted text when they read as text (an
// HTML page, a JSON error), else hexadecimal.
function firstBytes(view) {
  if (view.length === 0) return 'it is empty';
  const head = view.subarray(0, 40);
  const printable = head.every((b) => b === 0x09 || b === 0x0a || b === 0x0d || (b >= 0x20 && b < 0x7f));
  if (printable) {
    const text = String.fromCharCode(...head).replace(/\s+/g, ' ').trim();
    return `it begins "${text}${view.length > head.length ? '...' : ''}"`;
  }
  return `it begins with the bytes ${Array.from(view.subarray(0, 8), (b) => b.toString(16).padStart(2, '0')).join(' ')}`;
}
