// Cold start with springbones: the API and the three.js adapter, createSpringBones, then loadRig
// and attachWearable as the demo wears the sample (web/demo/js/main.js), one attachment.update.
// The page draws first: it wears and draws the item without waiting for the module
// (attachWearable gets the rig as a promise, README "three.js"); the module's download starts when
// the page's fetch order says (cold_start.mjs), compiled by createSpringBones as it streams in; the
// springs take over once it is there.
// Both pages' first modules name `three` themselves (cold_threevrm.mjs for Vector3), as a page's
// own module does: the browser then finds three.module.js beside cold_start.mjs rather than a
// round trip after it. A trace of the cold page on slow 4G (scripts/benchmarks/trace_cold_page.mjs)
// showed that hop as most of the drawable frame's gap when only the three-vrm page had it.
import 'three';
import { coldStart } from './cold_start.mjs';

const MODULE = new URL('../../../web/dist/springbones_wasm.wasm', import.meta.url);
// The orders that start the module after the drawing import the API then too: before the drawing
// the page needs the adapter alone (attachWearable), so the API's bytes wait with the module's.
const ORDER = new URLSearchParams(location.search).get('fetch') ?? 'after-draw';
const API_BEFORE_DRAWING = !['after-draw', 'after-downloads', 'at-wear'].includes(ORDER);
const importApi = () => import('../../../web/springbones.js');
// `?wasm=api`: the API finds and fetches the module itself, createSpringBones() without options, as
// the adapters' page module (web/page_module.js) calls it; by default the page fetches it beside
// the API's import and hands the download over (README "three.js").
const PAGE_FETCHES_WASM = new URLSearchParams(location.search).get('wasm') !== 'api';

coldStart({
  name: 'springbones',
  importLibrary: async () => {
    const [api, adapter] = await Promise.all([API_BEFORE_DRAWING ? importApi() : null, import('../../../web/three/springBonesThree.js')]);
    return { api, adapter };
  },
  start: async (lib, { priority }) => {
    const wasm = PAGE_FETCHES_WASM ? fetch(MODULE, priority ? { priority } : {}) : undefined;
    const api = lib.api ?? await importApi();
    return api.createSpringBones(wasm ? { wasm } : {});
  },
  wear: (lib, { avatar, wearable, springBones, contentHash }, started) => {
    let loadStart = 0, loadRigMs = 0;
    const rig = started.then((sb) => {
      loadStart = performance.now();
      // The glTF JSON GLTFLoader already parsed, as the loader plugin hands it over.
      const loaded = sb.loadRig(wearable.parser.json, springBones, { contentHash });
      loadRigMs = performance.now() - loadStart;
      return loaded;
    });
    // Wearing the item (bone matching, ADR-57) is the adapter's attachWearable: part of this
    // page's library time (wearMs); the three-vrm page has no such step.
    const attachment = lib.adapter.attachWearable(avatar.scene, wearable, rig);
    return attachment.ready.then(() => ({
      joints: attachment.rig.joints.length,
      step: (dt) => attachment.update(dt),
      loadMs: performance.now() - loadStart,  // loadRig and the instance
      details: { loadRigMs },
    }));
  },
});
