// Fetching, compiling and instantiating one of the WebAssembly modules (the runtime for
// createSpringBones, the creator tools for sb.creatorTools) from the options both take: `wasm` (a
// download the page started), `wasmBinary` (the bytes) or `wasmUrl` (where the .wasm is).
//
// In Node the .wasm is read with fs and handed to the glue as wasmBinary (the glue is built for
// the web only, see wasm/CMakeLists.txt); in browsers the glue fetches it with streaming
// compilation, unless the page started that fetch itself and hands over the Response.

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

  let factory;
  try {
    ({ default: factory } = await importGlue());
  } catch (cause) {
    throw withCause(new SpringBonesError('module-not-found',
        `the WebAssembly module (${glueFile}) could not be imported; build it ` +
        `with scripts/build wasm (${cause?.message ?? cause})`), cause);
  }

  // What is read, for the error: the option that gave the module, or the URL fetched or read.
  const loading = {
    source: wasm !== undefined ? 'the wasm option'
      : wasmBinary !== undefined ? (options[kBinarySource] ?? 'the wasmBinary option') : url.href,
  };
  const moduleOptions = {};
  try {
    // The glue waits for the instance forever if instantiateWasm fails: the race reports it.
    let instantiationFailed = new Promise(() => {});
    if (wasm !== undefined) {
      const compiled = await compileGiven(wasm, loading);
      instantiationFailed = new Promise((_, reject) => {
        moduleOptions.instantiateWasm = (imports, receiveInstance) => {
          WebAssembly.instantiate(compiled, imports).then((instance) => receiveInstance(instance, compiled)).catch(reject);
          return {};
        };
      });
    } else if (wasmBinary !== undefined) {
      moduleOptions.wasmBinary = wasmBinary;
    } else if (kIsNode && url.protocol === 'file:') {
      const { readFile } = await import(/* webpackIgnore: true */ /* @vite-ignore */ 'node:fs/promises');
      moduleOptions.wasmBinary = await readFile(url);
    } else {
      moduleOptions.locateFile = () => url.href;
    }
    const module = await Promise.race([factory(moduleOptions), instantiationFailed]);
    sources.set(module, loading.source);
    return module;
  } catch (cause) {
    throw loadFailed(loading.source, cause);
  }
}

/** The 'module-load-failed' error for a module from `source` (a URL or the option's name). */
export function loadFailed(source, cause) {
  return withCause(new SpringBonesError('module-load-failed',
      `the WebAssembly module (${source}) could not be loaded: ${cause?.message ?? cause}`), cause);
}

const isResponse = (x) => typeof Response === 'function' && x instanceof Response;

/**
 * The `wasm` option as a compiled module: a Response (or its promise, e.g. a fetch the page started
 * before importing this library) compiles while it streams; a server that does not send
 * application/wasm gets the bytes compiled instead.
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
  if (!given.ok) throw new Error(`HTTP ${given.status} ${given.statusText}`.trim());
  const streams = typeof WebAssembly.compileStreaming === 'function' &&
      (given.headers.get('Content-Type') ?? '').split(';')[0].trim() === 'application/wasm';
  return streams ? WebAssembly.compileStreaming(given) : WebAssembly.compile(await given.arrayBuffer());
}
