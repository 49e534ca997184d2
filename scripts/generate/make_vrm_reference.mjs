// Generates tests/fixtures/vrm_reference.json: single-joint trajectories computed by the published
// VRM spring-bone update as implemented by @pixiv/three-vrm-springbone 3.5.5, which the native
// solver tests compare against (one step per frame, stepHz = frame rate).
//
// Scenarios keep the joint's head fixed in world space (the parent only rotates about it):
// three-vrm measures the bone length from the child's previous-frame position, which only equals
// the true length when the head does not move, while springbones always uses the exact length.
//
//   node scripts/generate/make_vrm_reference.mjs
import { writeFileSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import * as THREE from 'three';
import { VRMSpringBoneJoint, VRMSpringBoneManager } from '@pixiv/three-vrm-springbone';

const fps = 60;
const frames = 240;

const scenarios = [
  {
    name: 'static-parent-gravity',
    jointRotation: [0, 0, 0, 1],
    tail: [0.5, 0, 0],
    params: { stiffness: 1, gravityPower: 1, gravityDir: [0, -1, 0], drag: 0.4 },
    center: false,
    parentAt: () => ({ axis: [0, 1, 0], angle: 0 }),
  },
  {
    name: 'spinning-parent',
    jointRotation: [0, 0, Math.sin(Math.PI / 12), Math.cos(Math.PI / 12)],
    tail: [0, 0.2, 0.05],
    params: { stiffness: 2, gravityPower: 0.5, gravityDir: [0.6, -0.8, 0], drag: 0.2 },
    center: false,
    parentAt: (f) => ({ axis: [0, 1, 0], angle: f < 2 ? 0 : 2.0 * (f - 1) / fps }),
  },
  {
    name: 'wobbling-parent-loose',
    jointRotation: [Math.sin(0.2), 0, 0, Math.cos(0.2)],
    tail: [0.1, -0.3, 0],
    params: { stiffness: 0.3, gravityPower: 0.2, gravityDir: [0, -1, 0], drag: 0.05 },
    center: false,
    parentAt: (f) => ({ axis: [0.6, 0, 0.8], angle: f < 2 ? 0 : 0.8 * Math.sin(3.0 * (f - 1) / fps) }),
  },
  {
    name: 'center-space',
    jointRotation: [0, 0, 0, 1],
    tail: [0, -0.25, 0.1],
    params: { stiffness: 1.5, gravityPower: 0.6, gravityDir: [0, -1, 0], drag: 0.3 },
    center: true,
    parentAt: (f) => ({ axis: [0, 0, 1], angle: f < 2 ? 0 : 1.2 * Math.sin(4.0 * (f - 1) / fps) }),
  },
];

function run(s) {
  const scene = new THREE.Scene();
  const parent = new THREE.Bone();
  parent.position.set(0.1, 1.2, -0.3);  // the head sits at the parent's origin
  const bone = new THREE.Bone();
  bone.quaternion.fromArray(s.jointRotation);
  const tip = new THREE.Bone();
  tip.position.fromArray(s.tail);
  scene.add(parent);
  parent.add(bone);
  bone.add(tip);
  scene.updateMatrixWorld(true);

  const joint = new VRMSpringBoneJoint(bone, tip, {
    stiffness: s.params.stiffness,
    gravityPower: s.params.gravityPower,
    gravityDir: new THREE.Vector3().fromArray(s.params.gravityDir),
    dragForce: s.params.drag,
    hitRadius: 0,
  });
  if (s.center) joint.center = parent;
  const manager = new VRMSpringBoneManager();
  manager.addJoint(joint);
  manager.setInitState();

  const out = { parentMatrices: [], rotations: [] };
  for (let f = 1; f <= frames; f++) {
    const { axis, angle } = s.parentAt(f);
    parent.quaternion.setFromAxisAngle(new THREE.Vector3().fromArray(axis).normalize(), angle);
    parent.updateMatrixWorld(true);
    manager.update(1 / fps);
    out.parentMatrices.push(parent.matrixWorld.elements.slice());
    out.rotations.push(bone.quaternion.toArray());
  }
  return out;
}

const result = {
  generator: 'scripts/generate/make_vrm_reference.mjs with @pixiv/three-vrm-springbone 3.5.5',
  fps,
  frames,
  scenarios: scenarios.map((s) => ({
    name: s.name,
    jointRotation: s.jointRotation,
    tail: s.tail,
    params: s.params,
    center: s.center,
    ...run(s),
  })),
};
const path = fileURLToPath(new URL('../../tests/fixtures/vrm_reference.json', import.meta.url));
writeFileSync(path, JSON.stringify(result) + '\n');
console.log(`wrote ${path}: ${result.scenarios.length} scenarios x ${frames} frames`);
