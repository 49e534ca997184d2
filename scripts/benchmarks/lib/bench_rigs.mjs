// The rigs and per-frame work of the springbones vs three-vrm benchmark, shared by the Node run
// (scripts/benchmarks/bench.mjs) and the Chromium page (scripts/benchmarks/pages/frames.html), so that both
// measure the same thing by construction. Runs in either: `three` and
// `@pixiv/three-vrm-springbone` are bare specifiers (node_modules in Node, an import map in the
// page), the adapter a relative import, and springbones itself is passed in as `sb`.
//
// Rigs: A avatars x C chains x J joints; each chain hangs under its own parent bone, which moves
// with a sinusoidal translation and rotation every frame. Parameters: stiffness 1, gravityPower
// 0.5, drag 0.4; one step per frame (dt = 1/60).
import * as THREE from 'three';
import { VRMSpringBoneJoint, VRMSpringBoneManager } from '@pixiv/three-vrm-springbone';
import { SpringBonesGroup, attachWearable } from '../../../web/three/springBonesThree.js';

/** [A, C, J]; the 5,000-joint rig (100x10x5) is the one the speedups quote. */
export const RIGS = [[1, 3, 5], [1, 10, 5], [10, 10, 5], [100, 10, 5], [100, 20, 10]];
const DT = 1 / 60;
const PARAMS = { stiffness: 1, gravityPower: 0.5, gravityDir: [0, -1, 0], drag: 0.4 };
const BONE = 0.05;
// three-vrm steps once per update; our instances step at a fixed rate, set to the frame rate here.
const ONE_STEP_PER_FRAME = { stepHz: 1 / DT };

export const rigName = ([A, C, J]) => `${A}x${C}x${J}`;
export const median = (xs) => [...xs].sort((a, b) => a - b)[xs.length >> 1];

/**
 * The tight loop: one warm-up run, then `runs` runs of `frames` frames, each run timed as a whole
 * (never one frame: a browser's timer has 5-100 us steps). Returns the median ms per frame.
 */
export function tightLoop(frame, { frames = 600, runs = 5 } = {}) {
  for (let f = 0; f < frames; f++) frame(f);
  const perFrame = [];
  for (let r = 0; r < runs; r++) {
    const t0 = performance.now();
    for (let f = 0; f < frames; f++) frame(f);
    perFrame.push((performance.now() - t0) / frames);
  }
  return median(perFrame);
}

/**
 * tightLoop for a frame of two parts: scene work both libraries share (animating the parent
 * bones, updateMatrixWorld) and the library's own update. Returns the whole frame's ms and the
 * update's ms alone (its per-frame times summed over each run), each the median over the runs.
 */
export function tightLoopSplit(animate, update, { frames = 600, runs = 5 } = {}) {
  const updateRuns = new Array(runs + 1).fill(0);
  let frame = 0;
  const ms = tightLoop((f) => {
    animate(f);
    const t0 = performance.now();
    update();
    updateRuns[Math.floor(frame++ / frames)] += performance.now() - t0;
  }, { frames, runs });
  return { ms, updateMs: median(updateRuns.slice(1)) / frames };
}

/** The parent bone motion of chain c on frame f: position and rotation about z. */
function motion(c, f) {
  const t = f * DT;
  return { x: c * 0.1 + 0.05 * Math.sin(6 * t + c), y: 1 + 0.03 * Math.sin(4 * t), z: 0, angle: 0.5 * Math.sin(5 * t + c) };
}

/**
 * The wearable as glTF JSON (no buffers). Node 0 the root; per chain a parent "chain_c", J joints
 * "springbone_c_j" each BONE below the previous, and an end node (the last joint's tail).
 * Returns the bytes loadRig takes, the document, and its data.springBones.
 */
export function wearableGltf(C, J) {
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

/** Moves every chain's parent bone of one avatar to frame f. */
function animateParents(parents, f) {
  parents.forEach((p, c) => {
    const m = motion(c, f);
    p.position.set(m.x, m.y, m.z);
    p.rotation.z = m.angle;
  });
}

// ---------------------------------------------------------------------------------------------
// Each setup builds one library's rig of A avatars and returns its per-frame work: animate(f)
// (the scene work both libraries share) and update() (the library's own), or frame(f) for our
// solver path, which has no three.js scene. loadMs: the setup's load time.

/** three-vrm: a VRMSpringBoneJoint per joint on three.js bones, one manager for all avatars. */
export function setupThreeVrm([A, C, J], wearable) {
  const t0 = performance.now();
  const manager = new VRMSpringBoneManager();
  const avatars = [];
  for (let a = 0; a < A; a++) {
    const { gltf, objects } = threeWearable(wearable.doc);
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
  return {
    loadMs: performance.now() - t0,
    animate(f) {
      for (const av of avatars) {
        animateParents(av.parents, f);
        av.scene.updateMatrixWorld(true);
      }
    },
    update() { manager.update(DT); },
    dispose() {},
  };
}

/**
 * Our solver path: driver matrices in, one scene.step, rotations read. With a budget, avatar a
 * stands at x = a metres and only the `budget` nearest to the origin are simulated.
 */
export function setupSolver(sb, [A], wearable, budget = null) {
  const t0 = performance.now();
  // The parsed document, as a preview's loader hands it over (the bytes would need the readers).
  const rig = sb.loadRig(wearable.doc, wearable.springBones, { contentHash: 'bench' });
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
  const out = {
    loadMs,
    sink: 0,  // the rotations read, so no engine can skip the reads
    frame(f) {
      for (let d = 0; d < chainOfDriver.length; d++) {
        const m = motion(chainOfDriver[d], f);
        m4.compose(pos.set(m.x, m.y, m.z), q.setFromAxisAngle(z, m.angle), one);
        frameDrivers.set(m4.elements, 16 * d);
      }
      for (const inst of instances) inst.driverMatrices.set(frameDrivers);
      scene.step(DT);
      for (const inst of instances) out.sink += inst.rotations[0];
    },
    dispose() {
      scene.dispose();
      for (const inst of instances) inst.dispose();
      rig.dispose();
    },
  };
  return out;
}

/** The adapter's update (SpringBonesGroup: every avatar, one scene.step); budget as setupSolver. */
export function setupAdapter(sb, [A, C, J], wearable, budget = null) {
  const rig = sb.loadRig(wearable.doc, wearable.springBones, { contentHash: 'bench' });
  const group = new SpringBonesGroup(sb);
  group.scene.setBudget(budget, 0, 0, 0);
  const avatars = [];
  for (let a = 0; a < A; a++) {
    const { gltf, objects } = threeWearable(wearable.doc);
    const avatarRoot = new THREE.Group();
    avatarRoot.position.x = a;
    // The bench's avatars are bare groups, so every chain hangs from the avatar root: the
    // bone-not-matched warning is expected here, once per avatar, and would bury the numbers.
    const attachment = attachWearable(avatarRoot, gltf, rig, { instance: ONE_STEP_PER_FRAME, onWarning: () => {} });
    group.add(attachment);
    const parents = [];
    for (let c = 0, i = 1; c < C; c++, i += J + 2) parents.push(attachment.nodes[i] ?? objects[i]);
    avatars.push({ avatarRoot, attachment, parents });
  }
  return {
    animate(f) {
      for (const av of avatars) {
        animateParents(av.parents, f);
        av.avatarRoot.updateMatrixWorld(true);
      }
    },
    // drivers read from matrixWorld, one scene.step, bones written
    update() { group.update(DT); },
    dispose() {
      group.dispose();
      for (const av of avatars) av.attachment.dispose();
      rig.dispose();
    },
  };
}
