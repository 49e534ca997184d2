// Warming the load path while a page waits. WebAssembly functions are compiled on their first
// call, so a page's first loadRig, createInstance and step pay for compiling the loaders, the
// instance set-up and the lane kernel, in the same main-thread task as the load itself. Run once
// on a built-in two-joint rig in an idle period (a page waiting for its GLB to download), that
// compiling happens in a task of its own, and the first real load is left with its own work.
// Only where requestIdleCallback exists (browsers): the callback never runs ahead of a frame
// the page has work for, and Node has no idle time to use.
//
// The rig goes in as a parsed glTF object, the typed path a preview takes (its loader parsed the
// glTF): bytes would need the readers module, which a preview never loads, and the load would
// throw before compiling anything. What the idle warm-up did, or the error that stopped it, is
// kept for warmUpOutcome(): a failure changes nothing for the page (its own load reports its
// errors), but it is never silent to whoever asks.

const kWarmUpGltf = {
  asset: { version: '2.0' },
  nodes: [
    { name: 'Avatar_Head', children: [1] },
    { name: 'springbone_warm_up', translation: [0, 0, 0.05], children: [2] },
    { name: 'springbone_warm_up_tip', translation: [0, -0.05, 0] },
  ],
};
const kWarmUpSpringBones = { version: 1, models: { 'warm-up': { springbone_warm_up: { isRoot: true } } } };

// sb -> { report } or { error }, once its idle warm-up ran.
const outcomes = new WeakMap();

/**
 * Loads the built-in rig on `sb`, steps an instance of it (a first step that seeds it, a second
 * with its driver moved), and frees both; throws whatever the API throws. Returns what ran: the rig's joint count, and how far the
 * step turned the first joint (a quaternion's largest component change; above 0 when the kernel
 * ran).
 */
export function warmUp(sb) {
  const rig = sb.loadRig(kWarmUpGltf, kWarmUpSpringBones, { contentHash: 'warm-up' });
  try {
    const instance = rig.createInstance();
    try {
      instance.step(1 / 60);  // the first step seeds the chain at rest under its driver
      const before = Array.from(instance.rotations.subarray(0, 4));
      instance.driverMatrices[12] = 0.01;
      instance.step(1 / 60);  // the lane kernel, the driver moved
      const after = instance.rotations;
      const turned = Math.max(...before.map((value, i) => Math.abs(after[i] - value)));
      return { joints: rig.joints.length, turned };
    } finally {
      instance.dispose();
    }
  } finally {
    rig.dispose();
  }
}

/** What the idle warm-up of `sb` did: undefined until it ran, then { report } or { error }. */
export function warmUpOutcome(sb) {
  return outcomes.get(sb);
}

/** Runs warmUp(sb) when the page is next idle, and keeps its outcome. */
export function warmUpWhenIdle(sb) {
  if (typeof requestIdleCallback !== 'function') return;
  requestIdleCallback(() => {
    try {
      outcomes.set(sb, { report: warmUp(sb) });
    } catch (error) {
      outcomes.set(sb, { error });
    }
  });
}
