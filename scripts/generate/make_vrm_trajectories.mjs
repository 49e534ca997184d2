// Generates tests/fixtures/vrm_trajectories.json: the VRM fixtures of scripts/generate/make_vrm_fixtures.mjs
// run by @pixiv/three-vrm-springbone 3.5.5 (three.js GLTFLoader + VRMSpringBoneLoaderPlugin, in
// Node: the files have no buffers or images, so GLTFLoader parses them without a DOM), one
// manager.update(1/60) per frame. tests/native/vrm_loader_test.cpp loads the same files with
// loadVrm, writes the recorded driver matrices and compares the joints' local rotations.
//
//   node scripts/generate/make_vrm_trajectories.mjs
//
// The body is animated through three nodes: J_Hips bobs and turns about Y, J_Spine rolls, J_Head
// nods (frame 1 is the rest pose, so both engines start from the same tails). Per frame the file
// records the world matrix of every node our loader turns into a driver (parents of spring roots,
// centers, collider nodes; found from the extension data the same way) and the local rotation of
// every simulated joint, keyed by glTF node index.
//
// After loading, the scene's world matrices are updated and manager.setInitState() is called again:
// three-vrm's VRMC_springBone import initialises the tails before GLTFLoader has computed any world
// matrix (its VRM 0.x import updates them first), which would start a 1.0 model from wrong tails.
//
// Two runs per model:
//  - `rotations`: three-vrm with its bone length measured at the current pose. Stock 3.5.5 reads
//    the length from the child's world matrix as it was at the end of the previous frame (a stale
//    bone length, listed in docs/semantics.md among our differences from three-vrm), which is off
//    whenever the joint's head moved since, i.e. for every joint below the first of a chain and
//    for roots whose parent translates. We refresh the child's world matrix first (the child's position only depends on
//    the joint's world matrix and the child's translation, so this is the exact current length,
//    the fixed length the VRM spec and springbones use). Nothing else in three-vrm is changed.
//  - `stockRotations`: unmodified three-vrm 3.5.5, to measure how far the stale length moves it.
import { readFileSync, writeFileSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import * as THREE from 'three';
import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';
import { VRMSpringBoneLoaderPlugin } from '@pixiv/three-vrm-springbone';
import { gltfOf } from '../lib/fixtures/glb.mjs';
import { countCollisions } from '../lib/three_vrm_collisions.mjs';
import { useExactBoneLength } from '../lib/three_vrm_equalized.mjs';

const fps = 60;
const frames = 240;
const fixtures = ['vrm10_springs.vrm', 'vrm0_springs.vrm', 'vrm10_extended_colliders.vrm'];
const fixturePath = (name) => fileURLToPath(new URL(`../../tests/fixtures/${name}`, import.meta.url));


const round = (x) => Number(x.toPrecision(10));

// The nodes springbones makes drivers of, from the extension data (no skipped nodes in these files).
function driverNodes(doc) {
  const parent = new Map();
  doc.nodes.forEach((node, i) => (node.children ?? []).forEach((c) => parent.set(c, i)));
  const out = new Set();
  const add = (i) => i !== undefined && i !== null && i >= 0 && out.add(i);
  const v1 = doc.extensions?.VRMC_springBone;
  if (v1) {
    const joints = new Set(v1.springs.flatMap((s) => s.joints.slice(0, -1).map((j) => j.node)));
    for (const s of v1.springs) {
      if (!joints.has(parent.get(s.joints[0].node))) add(parent.get(s.joints[0].node));
      add(s.center);
    }
    for (const c of v1.colliders) add(c.node);
  } else {
    const sa = doc.extensions.VRM.secondaryAnimation;
    for (const g of sa.boneGroups) {
      for (const b of g.bones) add(parent.get(b));
      add(g.center);
    }
    for (const g of sa.colliderGroups) add(g.node);
  }
  return [...out].sort((a, b) => a - b);
}

function pose(nodeOf, f) {
  const t = (f - 1) / fps;  // frame 1: rest
  const hips = nodeOf('J_Hips');
  hips.position.set(0, 0.95 + 0.03 * Math.sin(2 * Math.PI * 1.5 * t), 0.1 * Math.sin(2 * Math.PI * 0.25 * t));
  hips.quaternion.setFromAxisAngle(new THREE.Vector3(0, 1, 0), 0.7 * Math.sin(2 * Math.PI * 0.5 * t));
  nodeOf('J_Spine').quaternion.setFromAxisAngle(new THREE.Vector3(0, 0, 1), 0.3 * Math.sin(2 * Math.PI * 0.8 * t));
  nodeOf('J_Head').quaternion.setFromAxisAngle(new THREE.Vector3(1, 0, 0), 0.5 * Math.sin(2 * Math.PI * 1.1 * t));
}

async function run(name, exactLength) {
  useExactBoneLength(exactLength);
  const bytes = readFileSync(fixturePath(name));
  const doc = gltfOf(bytes);
  const loader = new GLTFLoader();
  loader.register((parser) => new VRMSpringBoneLoaderPlugin(parser));
  const buffer = bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.length);
  const gltf = await loader.parseAsync(buffer, '');
  const manager = gltf.userData.vrmSpringBoneManager;
  if (!manager) throw new Error(`${name}: three-vrm found no spring bones`);
  // The VRMC_springBone import calls setInitState before any world matrix is computed (its VRM 0.x
  // import updates the scene first), so tails would start as if every parent sat at the origin.
  // An app gets the same fix by updating the scene and calling setInitState (or reset) once.
  gltf.scene.updateMatrixWorld(true);
  manager.setInitState();
  const nodes = await gltf.parser.getDependencies('node');
  const byName = new Map(doc.nodes.map((n, i) => [n.name, i]));
  const nodeOf = (n) => nodes[byName.get(n)];
  const jointNodes = [...manager.joints].map((j) => nodes.indexOf(j.bone)).sort((a, b) => a - b);
  const drivers = driverNodes(doc);

  // Count collisions so the fixture is known to exercise the colliders.
  const collisions = countCollisions(manager, (collider) => `${collider.parent.name} ${collider.shape.type}`);

  const out = {
    drivers: Object.fromEntries(drivers.map((d) => [d, []])),
    rotations: Object.fromEntries(jointNodes.map((j) => [j, []])),
  };
  for (let f = 1; f <= frames; f++) {
    pose(nodeOf, f);
    manager.update(1 / fps);
    for (const d of drivers) out.drivers[d].push(nodes[d].matrixWorld.elements.map(round));
    for (const j of jointNodes) out.rotations[j].push(nodes[j].quaternion.toArray().map(round));
  }
  out.collisions = collisions;
  return out;
}

const result = {
  generator: 'scripts/generate/make_vrm_trajectories.mjs with @pixiv/three-vrm-springbone 3.5.5 and three ' + THREE.REVISION,
  fps,
  frames,
  models: [],
};
for (const file of fixtures) {
  const exact = await run(file, true);
  const stock = await run(file, false);
  result.models.push({
    file,
    collisions: exact.collisions,
    drivers: exact.drivers,
    rotations: exact.rotations,
    stockRotations: stock.rotations,
  });
  let worst = 0;
  for (const j of Object.keys(exact.rotations)) {
    exact.rotations[j].forEach((q, f) => q.forEach((v, i) => (worst = Math.max(worst, Math.abs(v - stock.rotations[j][f][i])))));
  }
  console.log(`${file}: ${Object.keys(exact.rotations).length} joints, drivers ${Object.keys(exact.drivers)}, ` +
              `collisions ${JSON.stringify(exact.collisions)}; stock three-vrm differs by up to ${worst.toExponential(2)}`);
}
useExactBoneLength(false);
const path = fixturePath('vrm_trajectories.json');
writeFileSync(path, JSON.stringify(result) + '\n');
console.log(`wrote ${path}`);
