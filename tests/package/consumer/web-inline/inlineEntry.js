// springbones/inline with no configuration at all (no vite.config.js, no esbuild loader, no
// option): the runtime module is in the JavaScript, so nothing has to find or serve a .wasm.
import { createSpringBones } from 'springbones/inline';
import { wearSample } from '../web/wearSample.js';

createSpringBones().then(wearSample).catch((error) => {
  document.title = 'failed';  // tests/package/ stops waiting; the error reaches the console
  throw error;
});
