// esbuild does not copy files named by new URL(..., import.meta.url): import the .wasm through the
// package's `springbones/wasm` entry (the `file` loader copies it and gives its path, relative to
// the bundle) and pass its URL.
import { createSpringBones } from 'springbones';
import wasmUrl from 'springbones/wasm';
import { wearSample } from './wearSample.js';

createSpringBones({ wasmUrl: new URL(wasmUrl, import.meta.url) }).then(wearSample).catch((error) => {
  document.title = 'failed';  // tests/package/ stops waiting; the error reaches the console
  throw error;
});
