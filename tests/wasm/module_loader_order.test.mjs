// instantiateModule (web/module_loader.js) asks for the .wasm while the glue is being imported, not
// after it (one round trip fewer on a page: docs/performance.md, "Cold start of a preview"), and a
// glue that cannot be imported is still the error reported, with a module that fails as well.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { test } from 'node:test';
import { pathToFileURL } from 'node:url';

import { SpringBonesError } from '../../web/errors.js';
import { instantiateModule } from '../../web/module_loader.js';
import { root } from './helpers.mjs';

const glueUrl = pathToFileURL(join(root, 'web', 'dist', 'springbones_wasm.js')).href;
const defaultUrl = pathToFileURL(join(root, 'web', 'dist', 'springbones_wasm.wasm'));
const wasmBytes = readFileSync(defaultUrl);

test('the module is asked for before the glue has arrived', async () => {
  let askedForModule = false;
  let askedWhileGlueLoading = null;
  // A promise of the module whose then() is called once the loader waits for the download.
  const download = WebAssembly.compile(wasmBytes);
  const wasm = { then: (resolve, reject) => { askedForModule = true; return download.then(resolve, reject); } };
  const module = await instantiateModule('createSpringBones', { wasm }, {
    importGlue: async () => {
      await new Promise((resolve) => setTimeout(resolve, 20));  // the glue's round trip
      askedWhileGlueLoading = askedForModule;
      return import(glueUrl);
    },
    glueFile: 'web/dist/springbones_wasm.js',
    defaultUrl,
  });
  assert.equal(askedWhileGlueLoading, true, 'the module was not asked for until the glue had arrived');
  assert.equal(typeof module._sb_limitsJson, 'function', 'the instantiated module');
});

test('a glue that cannot be imported is the error, with a module that fails too, and nothing is left unhandled', async () => {
  const unhandled = [];
  const onUnhandled = (reason) => unhandled.push(reason);
  process.on('unhandledRejection', onUnhandled);
  try {
    await assert.rejects(instantiateModule('createSpringBones', { wasmUrl: pathToFileURL(join(root, 'no-such.wasm')) }, {
      importGlue: () => Promise.reject(new Error('Cannot find module springbones_wasm.js')),
      glueFile: 'web/dist/springbones_wasm.js',
      defaultUrl,
    }), (error) => {
      assert.ok(error instanceof SpringBonesError);
      assert.equal(error.code, 'module-not-found');
      assert.match(error.message, /web\/dist\/springbones_wasm\.js\) could not be imported; build it with scripts\/build wasm \(Cannot find module/);
      return true;
    });
    await new Promise((resolve) => setTimeout(resolve, 50));  // the module's failure, settled meanwhile
    assert.deepEqual(unhandled, []);
  } finally {
    process.off('unhandledRejection', onUnhandled);
  }
});
