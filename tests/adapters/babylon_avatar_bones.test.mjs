// The Babylon drop-in measures the 'dcl-body' shapes on the avatar in the scene (the skeleton
// with the whole armature, as the body shape's container holds it in Decentraland's preview),
// not on the bones the wearable's GLB carries: the demo's hair registered next to the demo's
// avatar gets all eight shapes with no warning, in Babylon 4.2 and the current major, whichever
// of the two containers is added first; under a fast half turn and a jump, driven through the
// drop-in, no ponytail tail gets more than 1 mm into the chest, shoulder or upper-arm shapes with
// either integrator. Without an avatar in the scene it measures on the GLB's bones as before.
import assert from 'node:assert/strict';
import { before, describe, test } from 'node:test';
import { createSpringBones } from '../../web/springbones.js';
import { SpringBoneSimulation } from '../../web/babylon/index.js';
import { copyWorldMatrix, isMirroredScene } from '../../web/babylon/handedness.js';
import { avatarNode, findAvatarSkeleton } from '../../web/babylon/avatarSkeleton.js';
import { babylonKit, kBabylonVersions, readAsset, readJsonAsset } from './babylon_kit.mjs';
import { DeepestTails, describeDepths, holderPose, kBodyShapes, kFrames, kHitRadius, mm } from './turn_and_jump.mjs';

const metadata = readJsonAsset('hair_wearable.metadata.json');
const [hash] = Object.keys(metadata.models);
const kDclBody = { colliders: 'dcl-body', hitRadius: kHitRadius };
const registration = (extra = {}) => ({ springBones: metadata, contentHash: hash, ...extra });

let sb;
before(async () => {
  sb = await createSpringBones();
});

for (const which of kBabylonVersions) {
  describe(`Babylon ${which}`, () => {
    let kit;
    before(async () => {
      kit = await babylonKit(which);
    });

    /** The avatar and the hair in one scene, both under a holder node that carries the motion. */
    async function avatarAndHair({ rightHanded = false } = {}) {
      const scene = kit.scene({ rightHanded });
      const avatar = await kit.load(scene, readAsset('avatar.glb'));
      const hair = await kit.load(scene, readAsset('hair_wearable.glb'));
      const holder = new kit.BABYLON.TransformNode('holder', scene);
      const add = (container) => {
        for (const group of container.animationGroups) group.stop();  // Babylon 4.2's loader starts the first one
        container.addAllToScene();
        container.meshes.find((m) => m.name === '__root__').parent = holder;
      };
      return { scene, avatar, hair, holder, add };
    }

    test("the hair next to the avatar gets all eight shapes with no warning; the avatar's bones carry the ones the GLB lacks", async () => {
      for (const rightHanded of [false, true]) {
        const { scene, avatar, hair, add } = await avatarAndHair({ rightHanded });
        add(avatar);
        add(hair);
        const simulation = new SpringBoneSimulation(sb);
        simulation.registerWearable(scene, hair, hash, registration(kDclBody));
        const rig = simulation.rigOf(hash);
        assert.deepEqual(rig.colliders.map((c) => c.node), kBodyShapes);
        assert.deepEqual(rig.warnings, []);
        assert.deepEqual(simulation.warnings, []);
        const wearable = simulation.internalsForTests.wearable(hash);
        const skeleton = findAvatarSkeleton(scene, hair);
        assert.equal(skeleton, avatar.skeletons[0]);
        for (const name of ['Avatar_LeftShoulder', 'Avatar_RightArm']) {
          const d = rig.drivers.findIndex((x) => x.name === name);
          assert.equal(rig.drivers[d].node, -1);
          assert.equal(wearable.driverNodes[d], avatarNode(skeleton, name));
          assert.ok(avatar.transformNodes.includes(wearable.driverNodes[d]), `${name} is the avatar's node`);
        }
        // The shapes match those the three.js adapter and loadRig measure (the same bind pose).
        simulation.updateParams(hash, { SpringBone_ponytail: { stiffness: 2, isRoot: true } });
        assert.deepEqual(simulation.rigOf(hash).colliders.map((c) => c.node), kBodyShapes);
        simulation.dispose(scene);
      }
    });

    test('registered before the avatar is in the scene, the hair is measured again when the avatar is registered', async () => {
      const { scene, avatar, hair, add } = await avatarAndHair();
      add(hair);
      const simulation = new SpringBoneSimulation(sb);
      simulation.registerWearable(scene, hair, hash, registration(kDclBody));
      // No avatar yet: the GLB's bones, as before, with the warning.
      assert.equal(simulation.rigOf(hash).colliders.length, 4);
      assert.ok(simulation.rigOf(hash).warnings.some((w) => w.code === 'body-collider-skipped'));
      add(avatar);
      simulation.registerWearable(scene, avatar, 'body-shape');  // the preview registers every asset
      assert.deepEqual(simulation.rigOf(hash).colliders.map((c) => c.node), kBodyShapes);
      assert.deepEqual(simulation.rigOf(hash).warnings, []);
      assert.deepEqual(simulation.rigOf('body-shape').colliders, [], 'the body shape asked for no colliders');
      simulation.dispose(scene);
    });

    test('registered before the avatar is in the scene, the hair is measured again at start()', async () => {
      const { scene, avatar, hair, add } = await avatarAndHair();
      add(hair);
      const simulation = new SpringBoneSimulation(sb);
      simulation.registerWearable(scene, hair, hash, registration(kDclBody));
      assert.equal(simulation.rigOf(hash).colliders.length, 4);
      add(avatar);  // not registered: start() finds it
      simulation.start(scene);
      assert.deepEqual(simulation.rigOf(hash).colliders.map((c) => c.node), kBodyShapes);
      for (let f = 0; f < 10; f++) scene.render();
      assert.ok(simulation.internalsForTests.wearable(hash).instance.worldMatrices.every(Number.isFinite), 'the rebuilt instance steps');
      simulation.dispose(scene);
    });

    test('with the module still on its way, the hair is measured on the avatar when it comes', async () => {
      const { scene, avatar, hair, add } = await avatarAndHair();
      add(avatar);
      add(hair);
      const simulation = new SpringBoneSimulation(Promise.resolve(sb));
      simulation.registerWearable(scene, hair, hash, registration(kDclBody));
      assert.equal(simulation.rigOf(hash), null);
      await simulation.ready;
      assert.deepEqual(simulation.rigOf(hash).colliders.map((c) => c.node), kBodyShapes);
      assert.deepEqual(simulation.warnings, []);
      simulation.dispose(scene);
    });

    test('an avatar that truly lacks a bone leaves its shapes out, and the warning names the bone', async () => {
      const { scene, avatar, hair, add } = await avatarAndHair();
      add(avatar);
      add(hair);
      avatar.skeletons[0].bones.find((b) => b.name === 'Avatar_LeftForeArm').name = 'Avatar_LeftForeArm_renamed';
      const simulation = new SpringBoneSimulation(sb);
      simulation.registerWearable(scene, hair, hash, registration(kDclBody));
      const rig = simulation.rigOf(hash);
      assert.equal(rig.colliders.length, 7);
      const skipped = rig.warnings.filter((w) => w.code === 'body-collider-skipped');
      assert.equal(skipped.length, 1);
      assert.match(skipped[0].message, /left-upper-arm \(the avatar lacks Avatar_LeftForeArm\)/);
      simulation.dispose(scene);
    });

    /** The hair registered through the drop-in under the turn and the jump: the deepest ponytail tails. */
    async function deepestUnderTurnAndJump(integrator, options, shapes) {
      const { scene, avatar, hair, holder, add } = await avatarAndHair();
      add(avatar);
      add(hair);
      const simulation = new SpringBoneSimulation(sb);
      simulation.registerWearable(scene, hair, hash, registration({ ...options, instance: { integrator } }));
      simulation.start(scene);
      const { instance } = simulation.internalsForTests.wearable(hash);
      const rig = simulation.rigOf(hash);
      const deepest = new DeepestTails(rig, shapes);
      const skeleton = avatar.skeletons[0];
      const mirrored = isMirroredScene(scene);
      const matrix = new Float64Array(16);
      // Each ancestor forced in turn, parents first: Babylon 4.2 forces a node alone, and nothing
      // else brings an avatar bone that is not a driver up to date before a frame is drawn.
      const carrier = (name) => {
        const chain = [];
        for (let node = avatarNode(skeleton, name); node; node = node.parent) chain.unshift(node);
        for (const node of chain) node.computeWorldMatrix(true);
        copyWorldMatrix(chain.at(-1).getWorldMatrix().m, matrix, 0, mirrored);
        return matrix;
      };
      holder.rotationQuaternion = new kit.BABYLON.Quaternion();
      for (let f = 0; f < kFrames; f++) {
        const { yaw, height } = holderPose(f);
        kit.BABYLON.Quaternion.RotationYawPitchRollToRef(yaw, 0, 0, holder.rotationQuaternion);
        holder.position.set(0, height, 0);
        scene.render();
        deepest.measure(instance.worldMatrices, carrier);
      }
      simulation.dispose(scene);
      return deepest.result;
    }

    describe('under a fast half turn and a jump, through the drop-in', () => {
      for (const integrator of ['vrm', 'xpbd']) {
        test(`${integrator}: no ponytail tail gets more than 1 mm into the chest, shoulder or upper-arm shapes`, async (t) => {
          const { scene, avatar, hair, add } = await avatarAndHair();
          add(avatar);
          add(hair);
          const measuring = new SpringBoneSimulation(sb);
          measuring.registerWearable(scene, hair, hash, registration(kDclBody));
          const shapes = measuring.rigOf(hash).colliders;
          measuring.dispose(scene);
          const without = await deepestUnderTurnAndJump(integrator, {}, shapes);
          const worn = await deepestUnderTurnAndJump(integrator, kDclBody, shapes);
          t.diagnostic(`${integrator}, deepest ponytail tail (negative: outside): without colliders ${describeDepths(without)}; with 'dcl-body' ${describeDepths(worn)}`);
          assert.ok(without.all > 0.01, `without colliders the deepest tail is only ${mm(without.all)} inside: the motion does not test the shapes`);
          assert.ok(worn.all <= 0.001, `with 'dcl-body' a tail went ${mm(worn.all)} in`);
        });
      }
    });
  });
}
