// Cold start with springbones: the API and the three.js adapter, createSpringBones, then loadRig
// and attachWearable as the demo wears the sample (web/demo/js/main.js), one attachment.update.
// As the demo does, the module's download starts first (the HTML preloads it) and createSpringBones
// takes that download: what "start" times is what is left of the module's start by then.
import { coldStart } from './cold_start.mjs';

const moduleDownload = fetch(new URL('../../web/dist/springbones_wasm.wasm', import.meta.url));
moduleDownload.catch(() => {});  // reported by createSpringBones

coldStart({
  name: 'springbones',
  importLibrary: async () => {
    const [api, adapter] = await Promise.all([import('../../web/springbones.js'), import('../../web/three/springBonesThree.js')]);
    return { api, adapter, sb: null };
  },
  start: async (lib) => {
    lib.sb = await lib.api.createSpringBones({ wasm: moduleDownload });
  },
  load: (lib, { avatar, wearable, wearableBytes, springBones, contentHash }) => {
    const t0 = performance.now();
    const rig = lib.sb.loadRig(wearableBytes, springBones, { contentHash });
    const loadRigMs = performance.now() - t0;
    // Wearing the item (bone matching, ADR-57) is part of the adapter's attachWearable, so it is
    // in this page's load time; the three-vrm page has no such step. Shown apart as attachMs.
    const t1 = performance.now();
    const attachment = lib.adapter.attachWearable(avatar.scene, wearable, rig);
    const attachMs = performance.now() - t1;
    return { joints: rig.joints.length, step: (dt) => attachment.update(dt), details: { loadRigMs, attachMs } };
  },
});
