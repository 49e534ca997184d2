#!/usr/bin/env node
// Replays the VRM cases without angle limits (those whose `requires` lacks "vrm-limits": three-vrm
// 3.5.5 reads no VRMC_springBone_limit) on @pixiv/three-vrm-springbone, the way a three.js page runs
// it, and prints per case whether every expected rotation is met (README.md, "three-vrm").
//
//   node conformance/run_three_vrm.mjs [--exact-length] [case name ...]
//
// Each case's file is loaded with three.js's GLTFLoader and VRMSpringBoneLoaderPlugin; before the
// first frame the scene takes the first frame's pose and setInitState() records it (the pack's
// first step starts at rest under the first frame's drivers); then each frame poses the nodes it
// names, updates the world matrices and calls manager.update(dt). --exact-length measures the bone
// length at the current pose (scripts/lib/three_vrm_equalized.mjs), as the VRM specification and
// springbones do, where three-vrm 3.5.5 takes it from the previous frame.
import { readFileSync, readdirSync } from 'node:fs';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';
import * as THREE from 'three';
import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';
import { VRMSpringBoneLoaderPlugin } from '@pixiv/three-vrm-springbone';
import { useExactBoneLength } from '../scripts/lib/three_vrm_equalized.mjs';

const here = dirname(fileURLToPath(import.meta.url));

// 4 atan2(|a - b|, |a + b|) with b on a's side: the angle between two rotations (README.md, "Tolerance").
function angleBetween(a, b) {
  const s = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3] < 0 ? -1 : 1;
  return 4 * Math.atan2(Math.hypot(...a.map((v, i) => v - s * b[i])), Math.hypot(...a.map((v, i) => v + s * b[i])));
}

async function replay(file) {
  const c = JSON.parse(readFileSync(file, 'utf8'));
  const bytes = readFileSync(resolve(dirname(file), c.glb));
  const loader = new GLTFLoader();
  loader.register((parser) => new VRMSpringBoneLoaderPlugin(parser));
  const gltf = await loader.parseAsync(bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.length), '');
  const manager = gltf.userData.vrmSpringBoneManager;
  const nodes = await gltf.parser.getDependencies('node');
  const byName = new Map(nodes.map((n, i) => [gltf.parser.json.nodes[i].name, n]));
  const pose = (frame) => {
    for (const [name, matrix] of Object.entries(frame.pose)) {
      const node = byName.get(name);
      // The pack's nodes with a pose are scene roots: the local matrix is the world matrix.
      new THREE.Matrix4().fromArray(matrix).decompose(node.position, node.quaternion, node.scale);
    }
    gltf.scene.updateMatrixWorld(true);
  };
  pose(c.frames[0]);
  manager.setInitState();
  let worst = 0;
  let misses = 0;
  let first = '';
  c.frames.forEach((frame, k) => {
    pose(frame);
    manager.update(frame.dt);
    c.nodes.forEach((name, i) => {
      const q = byName.get(name).quaternion;
      const miss = angleBetween([q.x, q.y, q.z, q.w], frame.rotations[i]);
      worst = Math.max(worst, miss);
      if (!(miss <= c.tolerance)) {
        misses++;
        first ||= `frame ${k}, ${name}: off by ${miss.toExponential(2)} rad`;
      }
    });
  });
  return { name: c.name, worst, misses, first, total: c.frames.length * c.nodes.length };
}

const exact = process.argv.includes('--exact-length');
const names = process.argv.slice(2).filter((a) => a !== '--exact-length');
useExactBoneLength(exact);
const folder = join(here, 'vrm', 'cases');
const files = readdirSync(folder).filter((f) => f.endsWith('.json')).sort()
  .filter((f) => names.length === 0 || names.some((n) => f.includes(n)))
  .filter((f) => !JSON.parse(readFileSync(join(folder, f), 'utf8')).requires.includes('vrm-limits'));
let passed = 0;
for (const f of files) {
  const r = await replay(join(folder, f));
  if (r.misses === 0) passed++;
  console.log(r.misses === 0
    ? `ok    ${f} (largest difference ${r.worst.toExponential(2)} rad)`
    : `MISS  ${f}: ${r.misses} of ${r.total} rotations, largest ${r.worst.toExponential(2)} rad; first: ${r.first}`);
}
console.log(`${passed} of ${files.length} cases pass (@pixiv/three-vrm-springbone, ${exact ? 'bone length at the current pose' : 'as published'})`);
process.exitCode = passed === files.length ? 0 : 1;
