// Warming the load path while a page waits. WebAssembly functions are compiled on their first
// call, so a page's first loadRig, createInstance and step pay for compiling the loaders, the
// instance set-up and the lane kernel, in the same main-thread task as the load itself. Run once
// on a built-in two-joint rig in an idle period (a page waiting for its GLB to download), that
// compiling happens in a task of its own, and the first real load is left with its own work.
// Only where requestIdleCallback exists (browsers): the callback never runs ahead of a frame
// the page has work for, and Node has no idle time to use.

const kWarmUpGltf = JSON.stringify({
  asset: { version: '2.0' },
  nodes: [
    { name: 'Avatar_Head', children: [1] },
    { name: 'springbone_warm_up', translation: [0, 0, 0.05], children: [2] },
    { name: 'springbone_warm_up_tip', translation: [0, -0.05, 0] },
  ],
});
const kWarmUpSpringBones = { version: 1, models: { 'warm-up': { springbone_warm_up: { isRoot: true } } } };

/** Loads, steps and frees the built-in rig on `sb` when the page is next idle. */
export function warmUpWhenIdle(sb) {
  if (typeof requestIdleCallback !== 'function') return;
  requestIdleCallback(() => {
    let rig;
    let instance;
    try {
      rig = sb.loadRig(new TextEncoder().encode(kWarmUpGltf), kWarmUpSpringBones, { contentHash: 'warm-up' });
      instance = rig.createInstance();
      instance.driverMatrices[12] = 0.01;
      instance.step(1 / 60);
    } catch {
      // A warm-up that fails changes nothing: the page's own load reports its errors.
    } finally {
      instance?.dispose();
      rig?.dispose();
    }
  });
}
