// Runs VRM files (GLB / .vrm, or glTF JSON text without external buffers) in springbones (loadVrm)
// and in @pixiv/three-vrm-springbone 3.5.5 (extended colliders on, its default), with the same
// animated drivers, one step per frame at 60 fps for 240 frames, and prints per file the largest
// difference of a local rotation's quaternion components, and how often each collider shape of
// three-vrm touched a tail. Two of the differences docs/semantics.md documents are made equal first
// (lib/three_vrm_equalized.mjs): bone lengths at the current pose, collider radii scaled with the
// collider node. For files made elsewhere (e.g. the team's shared real VRM files), which must not
// be copied into the repository: this reads them where they are.
//
//   node scripts/reference/compare_vrm_with_three_vrm.mjs [--stock] <file>...
//
// --stock: three-vrm as published (stale bone lengths, authored radii), to see how far the
// documented differences move it.
//
// The motion: every scene root that is not a joint (the body's root, or a free collider node)
// sways: it moves along X and Z by up to half the model's size (the largest distance of a
// node from the first scene root at rest) and turns up to 0.6 rad about Y and 0.3 rad about Z,
// each on a sine of its own frequency; frame 1 is the rest pose.
import { readFileSync } from 'node:fs';
import { basename } from 'node:path';
import * as THREE from 'three';
import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';
import { VRMSpringBoneLoaderPlugin } from '@pixiv/three-vrm-springbone';
import { createSpringBones } from '../../web/springbones.js';
import { countCollisions } from '../lib/three_vrm_collisions.mjs';
import { applyLimits } from '../lib/three_vrm_limits.mjs';
import { scaleColliderRadii, useExactBoneLength } from '../lib/three_vrm_equalized.mjs';

const fps = 60;
const frames = 240;

function sway(node, rest, size, f) {
  const t = (f - 1) / fps;
  const reach = 0.5 * size;
  node.position.copy(rest.position).add(new THREE.Vector3(reach * Math.sin(2 * Math.PI * 0.7 * t), 0, reach * Math.sin(2 * Math.PI * 0.45 * t)));
  const turn = new THREE.Quaternion().setFromEuler(new THREE.Euler(0, 0.6 * Math.sin(2 * Math.PI * 0.5 * t), 0.3 * Math.sin(2 * Math.PI * 0.9 * t)));
  node.quaternion.copy(turn).multiply(rest.quaternion);
}

async function compare(sb, file) {
  const bytes = readFileSync(file);
  const rig = sb.loadVrm(bytes);
  const instance = rig.createInstance({ stepHz: fps, maxSubsteps: 4 });

  const loader = new GLTFLoader();
  loader.register((parser) => new VRMSpringBoneLoaderPlugin(parser));
  const buffer = bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.length);
  const warn = console.warn;
  const threeWarnings = [];
  console.warn = (...args) => threeWarnings.push(args.join(' '));
  let gltf;
  try {
    gltf = await loader.parseAsync(buffer, '');
  } finally {
    console.warn = warn;
  }
  const manager = gltf.userData.vrmSpringBoneManager;
  if (!manager) throw new Error(`${file}: three-vrm found no spring bones`);
  gltf.scene.updateMatrixWorld(true);
  manager.setInitState();  // after the world matrices exist (see make_vrm_trajectories.mjs)
  if (!stock) scaleColliderRadii(manager);
  const collisions = countCollisions(manager, ({ shape }) => `${shape.type}${shape.inside ? ' inside' : ''}`);
  const nodes = await gltf.parser.getDependencies('node');
  // VRMC_springBone_limit: 3.5.5 does not read it; the rules of three-vrm's pull request do
  // (lib/three_vrm_limits.mjs; --stock: its rotation of a scaled matrix as written).
  const limited = applyLimits(manager, gltf.parser.json, nodes, { exactRotation: !stock });
  const jointNodes = new Set(rig.joints.map((j) => j.node));
  const swaying = gltf.parser.json.scenes[gltf.parser.json.scene ?? 0].nodes.filter((n) => !jointNodes.has(n)).map((n) => nodes[n]);
  const rest = swaying.map((n) => ({ position: n.position.clone(), quaternion: n.quaternion.clone() }));
  const origin = new THREE.Vector3().setFromMatrixPosition(gltf.scene.children[0].matrixWorld);
  const size = Math.max(...nodes.map((n) => new THREE.Vector3().setFromMatrixPosition(n.matrixWorld).distanceTo(origin)));

  let worst = 0, worstFrame = 0, worstJoint = '';
  for (let f = 1; f <= frames; f++) {
    swaying.forEach((n, i) => sway(n, rest[i], size, f));
    gltf.scene.updateMatrixWorld(true);
    manager.update(1 / fps);
    rig.drivers.forEach((d, i) => {
      if (d.node < 0) throw new Error(`${file}: driver ${d.name} is not a node of the file`);
      instance.driverMatrices.set(nodes[d.node].matrixWorld.elements, 16 * i);
    });
    instance.step(1 / fps);
    const r = instance.rotations;
    rig.joints.forEach((joint, j) => {
      const q = nodes[joint.node].quaternion;
      const want = [q.x, q.y, q.z, q.w];
      const sign = want.reduce((s, v, k) => s + v * r[4 * j + k], 0) < 0 ? -1 : 1;
      const d = Math.max(...want.map((v, k) => Math.abs(r[4 * j + k] - sign * v)));
      if (d > worst) [worst, worstFrame, worstJoint] = [d, f, joint.name ?? String(joint.node)];
    });
  }
  const shapes = rig.colliders.map((c) => `${c.shape}${c.inside ? ' inside' : ''}`).join(', ') || 'none';
  console.log(`${basename(file)}: ${rig.joints.length} joints, colliders [${shapes}], three-vrm contacts ` +
              `${JSON.stringify(collisions)}, limits ${JSON.stringify(limited)}: max |dq| ${worst.toExponential(2)} (frame ${worstFrame}, ${worstJoint})`);
  for (const w of rig.warnings) console.log(`  springbones warning ${w.code}: ${w.message}`);
  for (const w of threeWarnings) console.log(`  three-vrm: ${w}`);
  instance.dispose();
  rig.dispose();
  return worst;
}

const stock = process.argv.includes('--stock');
const files = process.argv.slice(2).filter((a) => a !== '--stock');
if (files.length === 0) {
  console.error('usage: node scripts/reference/compare_vrm_with_three_vrm.mjs [--stock] <file.vrm | file.gltf>...');
  process.exit(2);
}
const sb = await createSpringBones();
useExactBoneLength(!stock);
let worst = 0;
for (const file of files) worst = Math.max(worst, await compare(sb, file));
console.log(`max |dq| over ${files.length} file(s): ${worst.toExponential(2)}`);
