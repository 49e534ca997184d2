// The benchmark: springbones against @pixiv/three-vrm-springbone on the same synthetic
// rigs (scripts/benchmarks/lib/bench_rigs.mjs), in Node and then in Chromium. Run through scripts/bench
// (which sets up and builds first). Prints the Node table, writes build/bench/<timestamp>.json and
// build/bench/latest.json, then runs the Chromium benchmark (scripts/benchmarks/lib/bench_browser.mjs), whose
// summary is the last line:
//   first visit: drawable +<ms> ms; simulated slow 4G +<ms> ms, 4G +<ms> ms, LAN +<ms> ms; longest task <ms> ms; bytes +<KB> KB; second visit <ms> vs <ms> ms; 5000 joints: solver <x>x, adapter <y>x
// `--browser` runs the Chromium part alone; `--node` the Node part alone.
//
// Node: each measurement is one warm-up run, then the median of 5 runs of 600 frames
// (BENCH_FRAMES), one step per frame (dt = 1/60).
import { mkdirSync, readFileSync, writeFileSync } from 'node:fs';
import { gzipSync } from 'node:zlib';
import { loadavg } from 'node:os';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { performance } from 'node:perf_hooks';
import { createSpringBones } from '../../web/springbones.js';
import { RIGS, median, rigName, setupAdapter, setupSolver, setupThreeVrm, tightLoop, tightLoopSplit, wearableGltf } from './lib/bench_rigs.mjs';
import { runBrowserBench } from './lib/bench_browser.mjs';
import { measureSampleLoad } from './lib/bench_sample_load.mjs';

const root = join(dirname(fileURLToPath(import.meta.url)), '..', '..');
const FRAMES = Number(process.env.BENCH_FRAMES ?? 600), RUNS = 5;
const LOOP = { frames: FRAMES, runs: RUNS };
const mode = process.argv[2] ?? '';
if (!['', '--browser', '--node'].includes(mode)) {
  console.error(`bench: unknown option ${mode} (--browser: Chromium only, --node: Node only)`);
  process.exit(2);
}


/** Load time, update and whole-frame ms of three-vrm on one rig. */
function measureThreeVrm(rig, wearable) {
  const run = setupThreeVrm(rig, wearable);
  const { ms, updateMs } = tightLoopSplit(run.animate, run.update, LOOP);
  run.dispose();
  return { ms, updateMs, loadMs: run.loadMs };
}

/** Our solver path: ms per frame, and the load time of one avatar's rig. */
function measureSolver(sb, rig, wearable, budget = null) {
  const run = setupSolver(sb, rig, wearable, budget);
  const ms = tightLoop(run.frame, LOOP);
  run.dispose();
  return { ms, loadMs: run.loadMs, sink: run.sink };
}

/** The adapter: ms of the whole frame (shared scene work included) and of its update alone. */
function measureAdapter(sb, rig, wearable, budget = null) {
  const run = setupAdapter(sb, rig, wearable, budget);
  const result = tightLoopSplit(run.animate, run.update, LOOP);
  run.dispose();
  return result;
}

/** The Node table; returns the report it also writes to build/bench/. */
async function runNodeBench() {
  const loadBefore = loadavg();
  const wasmPath = join(root, 'web', 'dist', 'springbones_wasm.wasm');
  const jsPath = join(root, 'web', 'dist', 'springbones_wasm.js');
  const wasmBytes = readFileSync(wasmPath), jsBytes = readFileSync(jsPath);
  const compileRuns = [];
  for (let r = 0; r < 5; r++) {
    const t0 = performance.now();
    await WebAssembly.compile(wasmBytes);
    compileRuns.push(performance.now() - t0);
  }
  // Cold: the first createSpringBones of the process (imports the glue, reads the file, compiles,
  // instantiates). Warm: compile + instantiate of the bytes already in memory, median of 5 modules.
  const t0 = performance.now();
  const sb = await createSpringBones();
  const createMs = performance.now() - t0;
  const instantiateRuns = [];
  for (let r = 0; r < 5; r++) {
    const s = performance.now();
    await createSpringBones({ wasmBinary: wasmBytes });
    instantiateRuns.push(performance.now() - s);
  }
  const moduleInfo = {
    wasmBytes: wasmBytes.length, jsBytes: jsBytes.length,
    wasmGzip: gzipSync(wasmBytes, { level: 9 }).length, jsGzip: gzipSync(jsBytes, { level: 9 }).length,
    compileMs: median(compileRuns), createSpringBonesMs: createMs, compileInstantiateWarmMs: median(instantiateRuns),
  };

  const sampleLoad = await measureSampleLoad();

  // The crowds below run on the crowd module (createSpringBones({ crowd: true })), as a page with a
  // crowd does; the load and create figures above are the runtime module's, what a preview loads.
  const crowd = await createSpringBones({ crowd: true });
  const results = [];
  for (const [A, C, J] of RIGS) {
    const joints = A * C * J;
    const wearable = wearableGltf(C, J);
    const vrm = measureThreeVrm([A, C, J], wearable);
    const solver = measureSolver(crowd, [A, C, J], wearable);
    // Warm load: the median of 5 loads of the A avatars' rig after the one above; the metadata as
    // the object a page has after JSON.parse of the entity it fetched, and as that JSON text.
    const loads = [], textLoads = [];
    for (let r = 0; r < 5; r++) {
      const big = wearableGltf(C * A, J);
      const text = JSON.stringify(big.springBones);
      const parsed = JSON.parse(text);
      const s = performance.now();
      sb.loadRig(big.bytes, parsed, { contentHash: 'bench' }).dispose();
      loads.push(performance.now() - s);
      const t = performance.now();
      sb.loadRig(big.bytes, text, { contentHash: 'bench' }).dispose();
      textLoads.push(performance.now() - t);
    }
    const adapter = measureAdapter(crowd, [A, C, J], wearable);
    const ns = (ms) => (ms * 1e6) / joints;
    results.push({
      rig: rigName([A, C, J]), joints,
      threeVrm: { updateMs: vrm.updateMs, nsPerJointStep: ns(vrm.updateMs), frameMs: vrm.ms, loadMs: vrm.loadMs },
      solver: { msPerFrame: solver.ms, nsPerJointStep: ns(solver.ms), loadMs: solver.loadMs, warmLoadAllJointsMs: median(loads), warmLoadAllJointsTextMs: median(textLoads) },
      adapter: { updateMs: adapter.updateMs, nsPerJointStep: ns(adapter.updateMs), frameMs: adapter.ms },
    });
  }

  // The crowd of the in-world renderer: only the nearest avatars simulated (scene.setBudget).
  const [BA, BC, BJ] = [100, 10, 5], BUDGET = 10;
  const budgetWearable = wearableGltf(BC, BJ);
  const budgetRun = {
    rig: `${BA}x${BC}x${BJ}`, budget: BUDGET,
    solverMs: measureSolver(crowd, [BA, BC, BJ], budgetWearable, BUDGET).ms,
    adapterUpdateMs: measureAdapter(crowd, [BA, BC, BJ], budgetWearable, BUDGET).updateMs,
  };

  const f = (x, d = 3) => x.toFixed(d).padStart(9);
  console.log(`module: wasm ${moduleInfo.wasmBytes} B (${moduleInfo.wasmGzip} B gzip), js ${moduleInfo.jsBytes} B (${moduleInfo.jsGzip} B gzip), ` +
    `total ${((moduleInfo.wasmGzip + moduleInfo.jsGzip) / 1024).toFixed(1)} KB gzip; compile ${moduleInfo.compileMs.toFixed(2)} ms, ` +
    `compile+instantiate ${moduleInfo.compileInstantiateWarmMs.toFixed(2)} ms (first createSpringBones, with the glue import and file read: ${createMs.toFixed(2)} ms)`);
  console.log(`sample wearable (web/demo/assets, ${sampleLoad.joints} joints): loadRig warm ${sampleLoad.warmMs.toFixed(2)} ms (target < 1); ` +
    `the first loadRig of a fresh process ${sampleLoad.firstMs.toFixed(1)} ms (median of ${sampleLoad.processes} processes, ` +
    `${sampleLoad.firstRangeMs.map((x) => x.toFixed(1)).join('-')}; target < 20)`);
  // Per library: its update alone (ms and ns per joint-step), then the whole frame with the scene
  // work both share (animating the parents, updateMatrixWorld) for three-vrm and the adapter.
  console.log('rig          joints | three-vrm update ms  ns/j  frame ms | solver ms  ns/j | adapter update ms  ns/j  frame ms | load ms: three-vrm  springbones(1 avatar)  springbones(all joints, warm: object / JSON text)');
  for (const r of results) {
    console.log(`${r.rig.padEnd(12)} ${String(r.joints).padStart(6)} |${f(r.threeVrm.updateMs)}${f(r.threeVrm.nsPerJointStep, 0)}${f(r.threeVrm.frameMs)} |` +
      `${f(r.solver.msPerFrame)}${f(r.solver.nsPerJointStep, 0)} |${f(r.adapter.updateMs)}${f(r.adapter.nsPerJointStep, 0)}${f(r.adapter.frameMs)} |` +
      `${f(r.threeVrm.loadMs, 2)}${f(r.solver.loadMs, 2)}${f(r.solver.warmLoadAllJointsMs, 2)}${f(r.solver.warmLoadAllJointsTextMs, 2)}`);
  }
  console.log(`budget: ${budgetRun.rig} with the nearest ${BUDGET} avatars simulated: solver ${budgetRun.solverMs.toFixed(3)} ms, ` +
    `adapter update ${budgetRun.adapterUpdateMs.toFixed(3)} ms per frame (the others hold their pose; the adapter writes only the simulated avatars' bones)`);
  // The speedups compare updates: three-vrm's VRMSpringBoneManager.update against our solver path
  // (driver matrices in, step, rotations read) and against the adapter's update.
  const at5000 = results.find((r) => r.joints === 5000);
  const solverX = at5000.threeVrm.updateMs / at5000.solver.msPerFrame;
  const adapterX = at5000.threeVrm.updateMs / at5000.adapter.updateMs;
  const load = { before: loadBefore, after: loadavg() };
  const report = { date: new Date().toISOString(), node: process.version, loadavg: load, frames: FRAMES, runs: RUNS, module: moduleInfo, sampleLoad, results, budget: budgetRun, speedupAt5000: { solver: solverX, adapter: adapterX } };
  const outDir = join(root, 'build', 'bench');
  mkdirSync(outDir, { recursive: true });
  const json = JSON.stringify(report, null, 2);
  writeFileSync(join(outDir, `${report.date.replace(/[:.]/g, '-')}.json`), json);
  writeFileSync(join(outDir, 'latest.json'), json);
  console.log(`Node speedup at 5000 joints: solver ${solverX.toFixed(1)}x, three.js adapter ${adapterX.toFixed(1)}x ` +
    `(load average ${load.before.map((x) => x.toFixed(2)).join(' ')} before, ${load.after.map((x) => x.toFixed(2)).join(' ')} after: a busy machine slows three-vrm and us unevenly)`);
  return report;
}

if (mode !== '--browser') {
  console.log(`== springbones vs three-vrm, Node ${process.version} ==`);
  await runNodeBench();
}
if (mode !== '--node') {
  console.log();
  const browser = await runBrowserBench({ log: (line) => console.log(line) });
  console.log(browser.summary);
}
