// The benchmark of issue 7: springbones against @pixiv/three-vrm-springbone on the same synthetic
// rigs. Run through scripts/bench (which sets up and builds first). Prints a table, writes
// build/bench/<timestamp>.json and build/bench/latest.json; the last line is
//   speedup at 5000 joints: solver <X>x, three.js adapter <Y>x
//
// Rigs: A avatars x C chains x J joints; each chain hangs under its own parent bone, which moves
// with a sinusoidal translation and rotation every frame. Parameters: stiffness 1, gravityPower
// 0.5, drag 0.4. Each measurement: one warm-up run, then the median of 5 runs of 600 frames, one
// step per frame (dt = 1/60).
import { mkdirSync, readFileSync, writeFileSync } from 'node:fs';
import { gzipSync } from 'node:zlib';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { performance } from 'node:perf_hooks';
import * as THREE from 'three';
import { VRMSpringBoneJoint, VRMSpringBoneManager } from '@pixiv/three-vrm-springbone';
import { createSpringBones } from '../web/springbones.js';
import { SpringBonesGroup, attachWearable } from '../web/three/springBonesThree.js';

const root = join(dirname(fileURLToPath(import.meta.url)), '..');
const RIGS = [[1, 10, 5], [10, 10, 5], [100, 10, 5], [100, 20, 10]];
const FRAMES = Number(process.env.BENCH_FRAMES ?? 600), RUNS = 5, DT = 1 / 60;
const PARAMS = { stiffness: 1, gravityPower: 0.5, gravityDir: [0, -1, 0], drag: 0.4 };
const BONE = 0.05;
// three-vrm steps once per update; our instances step at a fixed rate, set to the frame rate here.
const ONE_STEP_PER_FRAME = { stepHz: 1 / DT };

const median = (xs) => [...xs].sort((a, b) => a - b)[xs.length >> 1];

/** Warm-up, then the median ms per frame of RUNS runs of FRAMES frames. */
function measure(frame) {
  for (let f = 0; f < FRAMES; f++) frame(f);
  const runs = [];
  for (let r = 0; r < RUNS; r++) {
    const t0 = performance.now();
    for (let f = 0; f < FRAMES; f++) frame(f);
    runs.push((performance.now() - t0) / FRAMES);
  }
  return median(runs);
}

/**
 * measure() for a frame of two parts: scene work both libraries share (animating the parent
 * bones, updateMatrixWorld) and the library's own update. Returns the whole frame's ms and the
 * update's ms alone, each the median over the measured runs.
 */
function measureSplit(animate, update) {
  const updateRuns = new Array(RUNS + 1).fill(0);
  let frame = 0;
  const ms = measure((f) => {
    animate(f);
    const t0 = performance.now();
    update();
    updateRuns[Math.floor(frame++ / FRAMES)] += performance.now() - t0;
  });
  return { ms, updateMs: median(updateRuns.slice(1)) / FRAMES };
}

/** The parent bone motion of chain c on frame f: position and rotation about z. */
function motion(c, f) {
  const t = f * DT;
  return { x: c * 0.1 + 0.05 * Math.sin(6 * t + c), y: 1 + 0.03 * Math.sin(4 * t), z: 0, angle: 0.5 * Math.sin(5 * t + c) };
}

// ---------------------------------------------------------------------------------------------
// The wearable: glTF JSON. Node 0 the root; per chain a parent "chain_c", J joints
// "springbone_c_j" each BONE below the previous, and an end node (the last joint's tail).
function wearableGltf(C, J) {
  const nodes = [{ name: 'root', children: [] }];
  const entries = {};
  for (let c = 0; c < C; c++) {
    const parent = nodes.length;
    nodes[0].children.push(parent);
    nodes.push({ name: `chain_${c}`, translation: [c * 0.1, 1, 0], children: [] });
    let prev = parent;
    for (let j = 0; j <= J; j++) {
      const index = nodes.length;
      nodes[prev].children.push(index);
      const name = j < J ? `springbone_${c}_${j}` : `end_${c}`;
      nodes.push({ name, translation: j === 0 ? [0, 0, 0] : [0, -BONE, 0], children: [] });
      if (j < J) entries[name] = j === 0 ? { ...PARAMS, isRoot: true } : { ...PARAMS };
      prev = index;
    }
  }
  for (const n of nodes) if (n.children.length === 0) delete n.children;
  const doc = { asset: { version: '2.0' }, scene: 0, scenes: [{ nodes: [0] }], nodes };
  return { bytes: new TextEncoder().encode(JSON.stringify(doc)), doc, springBones: { version: 1, models: { bench: entries } } };
}

/** three.js objects for the glTF nodes, and a GLTFLoader-like result for wearableNodes. */
function threeWearable(doc) {
  const objects = doc.nodes.map((n) => {
    const o = new THREE.Object3D();
    o.name = n.name;
    if (n.translation) o.position.fromArray(n.translation);
    return o;
  });
  const associations = new Map();
  doc.nodes.forEach((n, i) => {
    associations.set(objects[i], { nodes: i });
    for (const c of n.children ?? []) objects[i].add(objects[c]);
  });
  const scene = new THREE.Group();
  scene.add(objects[0]);
  return { gltf: { scene, scenes: [scene], parser: { associations } }, objects };
}

// ---------------------------------------------------------------------------------------------
function benchThreeVrm(A, C, J, doc) {
  const t0 = performance.now();
  const manager = new VRMSpringBoneManager();
  const avatars = [];
  for (let a = 0; a < A; a++) {
    const { gltf, objects } = threeWearable(doc);
    const parents = [];
    let i = 1;
    for (let c = 0; c < C; c++) {
      parents.push(objects[i]);
      for (let j = 0; j < J; j++) {
        const bone = objects[i + 1 + j], child = objects[i + 2 + j];
        manager.addJoint(new VRMSpringBoneJoint(bone, child, {
          stiffness: PARAMS.stiffness, gravityPower: PARAMS.gravityPower,
          gravityDir: new THREE.Vector3(0, -1, 0), dragForce: PARAMS.drag, hitRadius: 0,
        }));
      }
      i += J + 2;
    }
    gltf.scene.updateMatrixWorld(true);
    avatars.push({ scene: gltf.scene, parents });
  }
  manager.setInitState();
  const loadMs = performance.now() - t0;
  const { ms, updateMs } = measureSplit((f) => {
    for (const av of avatars) {
      av.parents.forEach((p, c) => { const m = motion(c, f); p.position.set(m.x, m.y, m.z); p.rotation.z = m.angle; });
      av.scene.updateMatrixWorld(true);
    }
  }, () => manager.update(DT));
  return { ms, updateMs, loadMs };
}

/**
 * Our solver path: driver matrices in, one scene.step, rotations read. With a budget, avatar a
 * stands at x = a metres and only the `budget` nearest to the origin are simulated.
 */
function benchSolver(sb, A, C, J, wearable, budget = null) {
  const t0 = performance.now();
  const rig = sb.loadRig(wearable.bytes, wearable.springBones, { contentHash: 'bench' });
  const loadMs = performance.now() - t0;
  const scene = sb.createScene();
  const instances = [];
  for (let a = 0; a < A; a++) { const inst = rig.createInstance(ONE_STEP_PER_FRAME); scene.add(inst); instances.push(inst); }
  for (let a = 0; a < A; a++) scene.positions[3 * a] = a;
  scene.setBudget(budget, 0, 0, 0);
  // The driver matrices of one avatar in driver order (every avatar moves alike): composed once
  // per frame, then copied into each instance, as a page copies each avatar's matrixWorld.
  const chainOfDriver = rig.drivers.map((d) => Number(d.name.slice('chain_'.length)));
  const frameDrivers = new Float32Array(16 * chainOfDriver.length);
  const m4 = new THREE.Matrix4(), q = new THREE.Quaternion(), pos = new THREE.Vector3(), one = new THREE.Vector3(1, 1, 1), z = new THREE.Vector3(0, 0, 1);
  let sink = 0;
  const ms = measure((f) => {
    for (let d = 0; d < chainOfDriver.length; d++) {
      const m = motion(chainOfDriver[d], f);
      m4.compose(pos.set(m.x, m.y, m.z), q.setFromAxisAngle(z, m.angle), one);
      frameDrivers.set(m4.elements, 16 * d);
    }
    for (const inst of instances) inst.driverMatrices.set(frameDrivers);
    scene.step(DT);
    for (const inst of instances) { const r = inst.rotations; sink += r[0]; }
  });
  const out = { ms, loadMs, sink };
  scene.dispose();
  for (const inst of instances) inst.dispose();
  rig.dispose();
  return out;
}

/** The adapter's update; with a budget, as benchSolver (avatar a at x = a). */
function benchAdapter(sb, A, C, J, wearable, budget = null) {
  const rig = sb.loadRig(wearable.bytes, wearable.springBones, { contentHash: 'bench' });
  const group = new SpringBonesGroup(sb);  // every avatar's attachment, one scene.step per frame
  group.scene.setBudget(budget, 0, 0, 0);
  const avatars = [];
  for (let a = 0; a < A; a++) {
    const { gltf, objects } = threeWearable(wearable.doc);
    const avatarRoot = new THREE.Group();
    avatarRoot.position.x = a;
    const attachment = attachWearable(avatarRoot, gltf, rig, { instance: ONE_STEP_PER_FRAME });
    group.add(attachment);
    const parents = [];
    for (let c = 0, i = 1; c < C; c++, i += J + 2) parents.push(attachment.nodes[i] ?? objects[i]);
    avatars.push({ avatarRoot, attachment, parents });
  }
  // ms: the whole frame (animation, updateMatrixWorld, group.update); updateMs: group.update alone
  // (drivers read from matrixWorld, one scene.step, bones written).
  const { ms, updateMs } = measureSplit((f) => {
    for (const av of avatars) {
      av.parents.forEach((p, c) => { const m = motion(c, f); p.position.set(m.x, m.y, m.z); p.rotation.z = m.angle; });
      av.avatarRoot.updateMatrixWorld(true);
    }
  }, () => group.update(DT));
  group.dispose();
  for (const av of avatars) av.attachment.dispose();
  rig.dispose();
  return { ms, updateMs };
}

// ---------------------------------------------------------------------------------------------
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

const results = [];
for (const [A, C, J] of RIGS) {
  const joints = A * C * J;
  const wearable = wearableGltf(C, J);
  const vrm = benchThreeVrm(A, C, J, wearable.doc);
  const solver = benchSolver(sb, A, C, J, wearable);
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
  const adapter = benchAdapter(sb, A, C, J, wearable);
  const ns = (ms) => (ms * 1e6) / joints;
  results.push({
    rig: `${A}x${C}x${J}`, joints,
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
  solverMs: benchSolver(sb, BA, BC, BJ, budgetWearable, BUDGET).ms,
  adapterUpdateMs: benchAdapter(sb, BA, BC, BJ, budgetWearable, BUDGET).updateMs,
};

const f = (x, d = 3) => x.toFixed(d).padStart(9);
console.log(`module: wasm ${moduleInfo.wasmBytes} B (${moduleInfo.wasmGzip} B gzip), js ${moduleInfo.jsBytes} B (${moduleInfo.jsGzip} B gzip), ` +
  `total ${((moduleInfo.wasmGzip + moduleInfo.jsGzip) / 1024).toFixed(1)} KB gzip; compile ${moduleInfo.compileMs.toFixed(2)} ms, ` +
  `compile+instantiate ${moduleInfo.compileInstantiateWarmMs.toFixed(2)} ms (first createSpringBones, with the glue import and file read: ${createMs.toFixed(2)} ms)`);
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
const report = { date: new Date().toISOString(), node: process.version, frames: FRAMES, runs: RUNS, module: moduleInfo, results, budget: budgetRun, speedupAt5000: { solver: solverX, adapter: adapterX } };
const outDir = join(root, 'build', 'bench');
mkdirSync(outDir, { recursive: true });
const json = JSON.stringify(report, null, 2);
writeFileSync(join(outDir, `${report.date.replace(/[:.]/g, '-')}.json`), json);
writeFileSync(join(outDir, 'latest.json'), json);
console.log(`speedup at 5000 joints: solver ${solverX.toFixed(1)}x, three.js adapter ${adapterX.toFixed(1)}x`);
