// The solver path alone on one rig of scripts/lib/bench_rigs.mjs (default 100 x 10 x 5, 5,000
// joints): setupSolver's frame (driver matrices copied in, one scene.step, rotations read), one
// warm-up run, then 30 runs of 200 frames; prints the fastest and the median ms per frame, of wall
// time and of the process's CPU time. For a before/after of a change in the core, give the other
// build's .wasm (the glue is the same when only the core changed), and run the two in turn,
// several processes each.
//
//   node scripts/benchmarks/bench_solver.mjs [--wasm path/to/springbones_crowd.wasm] [A C J]   (after scripts/build wasm)
import { readFileSync } from 'node:fs';
import { performance } from 'node:perf_hooks';
import { createSpringBones } from '../../web/springbones.js';
import { median, rigName, setupSolver, wearableGltf } from './lib/bench_rigs.mjs';

const args = process.argv.slice(2);
let wasmPath = null;
if (args[0] === '--wasm') {
  wasmPath = args[1];
  args.splice(0, 2);
}
const rig = args.length ? args.map(Number) : [100, 10, 5];
if (rig.length !== 3 || !rig.every((n) => Number.isInteger(n) && n > 0)) {
  throw new Error(`usage: bench_solver.mjs [--wasm file] [A C J] (three positive integers), got ${args.join(' ')}`);
}
const FRAMES = 200, RUNS = 30;

// The crowd module, as a page with a crowd loads it (createSpringBones({ crowd: true })).
const sb = await createSpringBones(wasmPath ? { wasmBinary: readFileSync(wasmPath) } : { crowd: true });
const run = setupSolver(sb, rig, wearableGltf(rig[1], rig[2]));
for (let f = 0; f < FRAMES; f++) run.frame(f);
// Wall time, and the process's CPU time beside it: on a machine shared with other jobs, a run that
// waited for a core shows in the first and not in the second.
const perFrame = [], cpuPerFrame = [];
for (let r = 0; r < RUNS; r++) {
  const t0 = performance.now(), c0 = process.cpuUsage();
  for (let f = 0; f < FRAMES; f++) run.frame(f);
  const cpu = process.cpuUsage(c0);
  perFrame.push((performance.now() - t0) / FRAMES);
  cpuPerFrame.push((cpu.user + cpu.system) / 1000 / FRAMES);
}
run.dispose();
console.log(`solver ${rigName(rig)} (${rig[0] * rig[1] * rig[2]} joints)${wasmPath ? ` ${wasmPath}` : ''}: ` +
  `fastest ${Math.min(...perFrame).toFixed(4)} ms, median ${median(perFrame).toFixed(4)} ms per frame; CPU time ` +
  `fastest ${Math.min(...cpuPerFrame).toFixed(4)} ms, median ${median(cpuPerFrame).toFixed(4)} (${RUNS} runs of ${FRAMES} frames)`);
