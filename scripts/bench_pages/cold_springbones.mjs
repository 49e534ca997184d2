// Cold start with springbones: the API and the three.js adapter, createSpringBones, then loadRig
// and attachWearable as the demo wears the sample (web/demo/js/main.js), one attachment.update.
import { coldStart } from './cold_start.mjs';

coldStart({
  name: 'springbones',
  importLibrary: async () => {
    const [api, adapter] = await Promise.all([import('../../web/springbones.js'), import('../../web/three/springBonesThree.js')]);
    return { api, adapter, sb: null };
  },
  start: async (lib) => {
    lib.sb = await lib.api.createSpringBones();
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
