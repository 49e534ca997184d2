// The per-frame page: for a rig of scripts/benchmarks/lib/bench_rigs.mjs and a library, the cost of a frame
// paced by requestAnimationFrame (the work inside each callback, timed in batches) and in a tight
// loop (as the Node benchmark). Exposes window.benchFrames for scripts/benchmarks/lib/bench_browser.mjs.
import { createSpringBones } from '../../../web/springbones.js';
import { RIGS, median, setupAdapter, setupSolver, setupThreeVrm, tightLoop, tightLoopSplit, wearableGltf } from '../lib/bench_rigs.mjs';
import { conditions, requireIsolation } from './conditions.mjs';

let sb;
try {
  requireIsolation();
  sb = await createSpringBones({ crowd: true });  // a page with a crowd loads the crowd module
} catch (error) {
  window.benchError = `${error.message}\n${error.stack ?? ''}`;
  throw error;
}

/** Resolves with the callback timestamps of `count` animation frames (nothing else done in them). */
const rafTimestamps = (count) => new Promise((resolve) => {
  const stamps = [];
  const tick = (t) => {
    stamps.push(t);
    if (stamps.length < count) requestAnimationFrame(tick);
    else resolve(stamps);
  };
  requestAnimationFrame(tick);
});

/**
 * One frame's work per requestAnimationFrame callback, as a page runs it: `warmup` callbacks,
 * then `batches` batches of `batchSize`. Each callback's update (and its whole work, animation
 * included) is timed; a batch's value is the sum over its callbacks divided by batchSize, so one
 * callback's timer step hardly matters. Returns the medians over the batches and the median
 * interval between callbacks.
 */
function rafPaced(animate, update, { warmup, batches, batchSize }) {
  return new Promise((resolve) => {
    const updateMs = [], frameMs = [], stamps = [];
    let n = 0, sumUpdate = 0, sumFrame = 0;
    const tick = (timestamp) => {
      stamps.push(timestamp);
      const t0 = performance.now();
      animate(n);
      const t1 = performance.now();
      update(n);
      const t2 = performance.now();
      if (n >= warmup) {
        sumUpdate += t2 - t1;
        sumFrame += t2 - t0;
        if ((n - warmup + 1) % batchSize === 0) {
          updateMs.push(sumUpdate / batchSize);
          frameMs.push(sumFrame / batchSize);
          sumUpdate = sumFrame = 0;
        }
      }
      n++;
      if (updateMs.length < batches) requestAnimationFrame(tick);
      else resolve({ updateMs: median(updateMs), frameMs: median(frameMs), intervalMs: median(stamps.slice(1).map((t, i) => t - stamps[i])) });
    };
    requestAnimationFrame(tick);
  });
}

const nothing = () => {};

/**
 * rigIndex into RIGS; library 'three-vrm', 'solver' or 'adapter'. rAF-paced first (after its own
 * warm-up), then the tight loop on the same setup. For the solver path, which has no three.js
 * scene, update and frame are the same work.
 */
async function run(rigIndex, library, { frames, runs, warmup, batches, batchSize }) {
  const rig = RIGS[rigIndex];
  const wearable = wearableGltf(rig[1], rig[2]);
  const setup = library === 'three-vrm' ? setupThreeVrm(rig, wearable)
    : library === 'solver' ? setupSolver(sb, rig, wearable)
      : library === 'adapter' ? setupAdapter(sb, rig, wearable) : null;
  if (!setup) throw new Error(`unknown library ${library}`);
  const animate = setup.animate ?? nothing;
  const update = setup.update ?? ((f) => setup.frame(f));
  const raf = await rafPaced(animate, update, { warmup, batches, batchSize });
  const tight = setup.frame
    ? { ms: tightLoop(setup.frame, { frames, runs }), updateMs: NaN }
    : tightLoopSplit(animate, update, { frames, runs });
  setup.dispose();
  const tightUpdate = setup.frame ? tight.ms : tight.updateMs;
  return {
    raf: { updateMs: raf.updateMs, frameMs: raf.frameMs, intervalMs: raf.intervalMs },
    tight: { updateMs: tightUpdate, frameMs: tight.ms },
  };
}

window.benchFrames = {
  rigs: RIGS,
  conditions: async () => {
    const stamps = await rafTimestamps(61);
    return { ...conditions(), rafIntervalMs: median(stamps.slice(1).map((t, i) => t - stamps[i])) };
  },
  run,
};
window.benchFramesReady = true;
