// The one warning step() gives: a frame of more than a second. step takes seconds, and such a
// frame runs at most maxSubsteps fixed steps (the substep cap) and drops the rest of its time, so
// the usual cause is a frame time in milliseconds (step(16) for step(0.016)), which would
// otherwise look like hair that moves in slow motion. Said once per module, on the console: a
// page that means it (a tab waking after a minute) sees it once, and the per-frame path costs one
// comparison.

export const kLongFrameSeconds = 1;

const warned = new WeakSet();  // the modules (the glue's Module objects) that have said it

/** Warns, the first time for module `m`, that `where` was given a frame of `dt` > 1 s. */
export function warnLongFrame(m, where, dt) {
  if (warned.has(m)) return;
  warned.add(m);
  console.warn(`springbones: ${where}(${dt}): a frame of more than ${kLongFrameSeconds} s; step takes seconds, and ` +
               'a frame longer than maxSubsteps fixed steps is clamped by that substep cap (the rest of its time is ' +
               `dropped). If it was milliseconds, pass ${dt / 1000}. (Said once.)`);
}
