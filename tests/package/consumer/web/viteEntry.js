// Vite: the package's default module location works in the bundle (Vite copies the .wasm that
// web/springbones.js points at with new URL(..., import.meta.url)).
import { createSpringBones } from 'springbones';
import { wearSample } from './wearSample.js';

createSpringBones().then(wearSample).catch((error) => {
  document.title = 'failed';  // tests/package/ stops waiting; the error reaches the console
  throw error;
});
