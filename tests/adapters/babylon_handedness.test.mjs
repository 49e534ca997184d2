// The Babylon adapter in the glTF's space: the same wearable under the same scripted motion gives
// the same local rotations as the three.js adapter (within 1e-5), in a left-handed Babylon scene
// (the glTF loader's `__root__` mirrors the file) and in a `useRightHandedSystem` one, and a
// gravityDir of [1, 0, 0] pulls a chain toward the file's +X in both, as in three.js.
import assert from 'node:assert/strict';
import { before, describe, test } from 'node:test';
import { AnimationMixer, Scene } from 'three';
import * as SkeletonUtils from 'three/examples/jsm/utils/SkeletonUtils.js';
import { SpringBoneSimulation } from '../../web/babylon/index.js';
import { attachWearable, avatarArmature, wearableNodes } from '../../web/three/springBonesThree.js';
import { qaxis, qmul } from '../../scripts/lib/fixtures/vec.mjs';
import { babylonKit, kBabylonVersions, readAsset, readJsonAsset } from './babylon_kit.mjs';
import { loadSampleWearable } from '../wasm/sample_wearable.mjs';

const DT = 1 / 60;
const FRAMES = 150;
const metadata = readJsonAsset('hair_wearable.metadata.json');
const [hash] = Object.keys(metadata.models);
const glb = readAsset('hair_wearable.glb');

/** The sample's entries with gravity pulling hard toward +X: a mirrored space would show at once. */
const sideways = Object.fromEntries(Object.entries(metadata.models[hash])
  .map(([name, e]) => [name, { ...e, gravityDir: [1, 0, 0], gravityPower: 1.5 }]));

/** q = a * b, quaternions as [x, y, z, w]. */
/**
 * The scripted motion, in glTF local values: the armature walks a curve and turns, the upper
 * spine bends, the head nods and shakes. Returns node name -> { position, rotation } for frame f,
 * from each node's own rest values.
 */
function pose(rest, f) {
  const t = f * DT;
  const r = (name) => rest.get(name);
  return new Map([
    ['Armature', {
      position: [r('Armature').position[0] + 0.8 * Math.sin(t * 2), r('Armature').position[1] + 0.05 * Math.abs(Math.sin(t * 6)), r('Armature').position[2] + 0.6 * t],
      rotation: qmul(qaxis([0, 1, 0], 0.9 * Math.sin(t * 2.5)), r('Armature').rotation),
    }],
    ['Avatar_Spine2', { position: r('Avatar_Spine2').position, rotation: qmul(r('Avatar_Spine2').rotation, qaxis([0, 0, 1], 0.3 * Math.sin(t * 4))) }],
    ['Avatar_Head', { position: r('Avatar_Head').position, rotation: qmul(r('Avatar_Head').rotation, qaxis([1, 0, 0], 0.4 * Math.sin(t * 5 + 1))) }],
  ]);
}

const restOf = (nodes, get) => new Map(['Armature', 'Avatar_Spine2', 'Avatar_Head'].map((name) => [name, get(nodes(name))]));

let three;
before(async () => {
  three = await loadSampleWearable();
});

/** Local rotation per joint name, frame by frame, from the three.js adapter. */
function threeRun(sb, springBones) {
  const rig = sb.loadRig(three.wearableBytes, springBones);
  const scene = new Scene();
  const avatarRoot = SkeletonUtils.clone(three.avatarGltf.scene);
  scene.add(avatarRoot);
  const wearable = SkeletonUtils.clone(three.wearableGltf.scene);
  const attachment = attachWearable(avatarRoot, wearable, rig, { nodes: wearableNodes(three.wearableGltf, wearable) });
  new AnimationMixer(avatarRoot);  // no clip plays: the motion is the script's
  const armature = avatarArmature(avatarRoot);
  const rest = restOf((n) => armature.get(n), (o) => ({ position: o.position.toArray(), rotation: o.quaternion.toArray() }));
  const frames = [];
  for (let f = 0; f < FRAMES; f++) {
    for (const [name, { position, rotation }] of pose(rest, f)) {
      armature.get(name).position.fromArray(position);
      armature.get(name).quaternion.fromArray(rotation);
    }
    scene.updateMatrixWorld();
    attachment.update(DT);
    frames.push(new Map(attachment.jointObjects.map((o, j) => [rig.joints[j].name, o.quaternion.toArray()])));
  }
  attachment.dispose();
  rig.dispose();
  return frames;
}

for (const which of kBabylonVersions) {
  describe(`Babylon ${which} against three.js`, () => {
    let kit;
    before(async () => {
      kit = await babylonKit(which);
    });

    async function babylonRun(sb, entry, rightHanded) {
      const scene = kit.scene({ rightHanded, deltaMs: DT * 1000 });
      const container = await kit.load(scene, glb);
      container.addAllToScene();
      const byName = (name) => container.transformNodes.find((n) => n.name === name);
      const simulation = new SpringBoneSimulation(sb);
      simulation.registerWearable(scene, container, hash, entry);
      simulation.start(scene);
      const rig = simulation.rigOf(hash);
      const rest = restOf(byName, (n) => ({ position: [n.position.x, n.position.y, n.position.z], rotation: [n.rotationQuaternion.x, n.rotationQuaternion.y, n.rotationQuaternion.z, n.rotationQuaternion.w] }));
      const frames = [];
      for (let f = 0; f < FRAMES; f++) {
        for (const [name, { position, rotation }] of pose(rest, f)) {
          byName(name).position.copyFromFloats(...position);
          byName(name).rotationQuaternion.set(...rotation);
        }
        scene.render();
        frames.push(new Map(rig.joints.map((j) => {
          const q = byName(j.name).rotationQuaternion;
          return [j.name, [q.x, q.y, q.z, q.w]];
        })));
      }
      const root = container.meshes.find((m) => m.name === '__root__');
      simulation.dispose(scene);
      return { frames, root };
    }

    const compare = (a, b) => {
      let worst = 0;
      let bent = 0;
      a.forEach((frame, f) => {
        assert.equal(b[f].size, frame.size);
        for (const [name, q] of frame) {
          const other = b[f].get(name);
          for (let i = 0; i < 4; i++) worst = Math.max(worst, Math.abs(q[i] - other[i]));
          bent = Math.max(bent, 1 - Math.abs(q[3]));
        }
      });
      return { worst, bent };
    };

    for (const rightHanded of [false, true]) {
      const space = rightHanded ? 'a useRightHandedSystem scene' : 'a left-handed scene (the default)';
      test(`the same local rotations as three.js within 1e-5, in ${space}, with gravity down and toward +X`, async (t) => {
        const { sb } = three;
        for (const entry of [metadata.models[hash], sideways]) {
          const reference = threeRun(sb, { version: 1, models: { [hash]: entry } });
          const { frames, root } = await babylonRun(sb, entry, rightHanded);
          // The loader mirrors a left-handed scene's file with its __root__; a right-handed one it leaves.
          assert.equal(root.scaling.z, rightHanded ? 1 : -1);
          const { worst, bent } = compare(reference, frames);
          assert.ok(bent > 0.005, `the script bends the chains (${bent})`);
          assert.ok(worst < 1e-5, `largest difference from three.js: ${worst}`);
          t.diagnostic(`gravity ${entry === sideways ? '+X' : 'down'}: largest difference ${worst.toExponential(2)}, largest bend ${bent.toFixed(3)}`);
        }
      });
    }

    test('gravityDir [1, 0, 0] pulls the chains toward the file\'s +X, which a left-handed scene shows at -X', async () => {
      const { sb } = three;
      for (const rightHanded of [false, true]) {
        const scene = kit.scene({ rightHanded });
        const container = await kit.load(scene, glb);
        container.addAllToScene();
        const tip = container.transformNodes.find((n) => n.name === 'SpringBone_ponytail_tip');
        const head = container.transformNodes.find((n) => n.name === 'Avatar_Head');
        const offset = () => tip.getAbsolutePosition().x - head.getAbsolutePosition().x;
        scene.render();
        const before = offset();
        const simulation = new SpringBoneSimulation(sb);
        simulation.registerWearable(scene, container, hash, sideways);
        simulation.start(scene);
        for (let f = 0; f < 120; f++) scene.render();
        const moved = offset() - before;
        if (rightHanded) assert.ok(moved > 0.05, `toward Babylon +X in a right-handed scene (${moved})`);
        else assert.ok(moved < -0.05, `toward Babylon -X, the file's +X, in a left-handed scene (${moved})`);
        simulation.dispose(scene);
      }
    });
  });
}
