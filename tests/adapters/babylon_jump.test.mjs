// No whip on a jump: an animation group starting to play (the avatar snaps to its first pose) and
// a teleport of the avatar told with simulation.jump() leave the hair calm, and so does the same
// snap untold, which the core notices as a jump of the drivers; with that detection off
// (jumpDistance and jumpAngle 0) the untold snap whips. The simulation carries its instances
// across with instance.jump() (carryAcrossJump in web/babylon/springBoneSimulation.js).
import assert from 'node:assert/strict';
import { before, describe, test } from 'node:test';
import { createSpringBones } from '../../web/springbones.js';
import { SpringBoneSimulation } from '../../web/babylon/index.js';
import { babylonKit, kBabylonVersions, readAsset, readJsonAsset } from './babylon_kit.mjs';

const metadata = readJsonAsset('hair_wearable.metadata.json');
const [hash] = Object.keys(metadata.models);
const glb = readAsset('hair_wearable.glb');
const SETTLE = 60;
const AFTER = 40;

let sb;
before(async () => {
  sb = await createSpringBones();
});

/** The angle (radians) between two unit quaternions. */
const angle = (a, b) => 2 * Math.acos(Math.min(1, Math.abs(a.x * b.x + a.y * b.y + a.z * b.z + a.w * b.w)));

for (const which of kBabylonVersions) {
  describe(`Babylon ${which}`, () => {
    let kit;
    before(async () => {
      kit = await babylonKit(which);
    });

    /**
     * The sample settled at rest, then `snap(context)` before one frame, then AFTER frames: the
     * largest angle of a ponytail joint from its rest rotation over those frames.
     */
    async function whipAfter(snap, setup = () => null, { detect = true } = {}) {
      const scene = kit.scene();
      const container = await kit.load(scene, glb);
      container.addAllToScene();
      const simulation = new SpringBoneSimulation(sb);
      const thresholds = detect ? {} : { jumpDistance: 0, jumpAngle: 0 };
      simulation.registerWearable(scene, container, hash, { springBones: metadata, contentHash: hash, ...thresholds });
      simulation.start(scene);
      const byName = (name) => container.transformNodes.find((n) => n.name === name);
      const joints = ['SpringBone_ponytail', 'SpringBone_ponytail_1', 'SpringBone_ponytail_2', 'SpringBone_ponytail_3', 'SpringBone_ponytail_4'].map(byName);
      const prepared = setup({ scene, byName, BABYLON: kit.BABYLON });
      for (let f = 0; f < SETTLE; f++) scene.render();
      const settled = joints.map((j) => j.rotationQuaternion.clone());
      snap({ scene, byName, simulation, BABYLON: kit.BABYLON, prepared });
      let worst = 0;
      for (let f = 0; f < AFTER; f++) {
        scene.render();
        joints.forEach((j, i) => {
          worst = Math.max(worst, angle(j.rotationQuaternion, settled[i]));
        });
      }
      simulation.dispose(scene);
      return worst;
    }

    /** The head turned 100 degrees about its up axis, as a pose. */
    const turnedHead = (BABYLON, head) => head.rotationQuaternion.multiply(BABYLON.Quaternion.RotationAxis(new BABYLON.Vector3(0, 1, 0), 1.75));

    test('an animation group starting to play leaves the hair calm, as the core noticing the snap does; with detection off the snap whips', async () => {
      const snapHead = ({ byName, BABYLON }) => {
        const head = byName('Avatar_Head');
        head.rotationQuaternion = turnedHead(BABYLON, head);
      };
      const untold = await whipAfter(snapHead, undefined, { detect: false });
      const noticed = await whipAfter(snapHead);
      const emote = ({ scene, byName, BABYLON }) => {
        const head = byName('Avatar_Head');
        const pose = turnedHead(BABYLON, head);
        const animation = new BABYLON.Animation('turn', 'rotationQuaternion', 60,
          BABYLON.Animation.ANIMATIONTYPE_QUATERNION, BABYLON.Animation.ANIMATIONLOOPMODE_CONSTANT);
        animation.setKeys([{ frame: 0, value: pose }, { frame: 60, value: pose }]);
        const group = new BABYLON.AnimationGroup('emote', scene);
        group.addTargetedAnimation(animation, head);
        return group;
      };
      // A group made and played between two frames, and one the scene had all along.
      const played = await whipAfter((context) => emote(context).play(false));
      const playedLater = await whipAfter(({ prepared }) => prepared.play(false), emote);
      assert.ok(untold > 0.3, `an untold snap swings the ponytail by ${untold} rad`);
      assert.ok(noticed < untold / 3, `the core noticing the snap: ${noticed} rad against ${untold} untold`);
      assert.ok(played < untold / 3, `after a new group starts: ${played} rad against ${untold} untold`);
      assert.ok(playedLater < untold / 3, `after a known group starts: ${playedLater} rad against ${untold} untold`);
    });

    test('a teleport, told with jump() or noticed by the core, leaves the hair calm; with detection off it whips', async () => {
      const teleport = (byName) => {
        byName('Armature').position.z += 3;
      };
      const untold = await whipAfter(({ byName }) => teleport(byName), undefined, { detect: false });
      const noticed = await whipAfter(({ byName }) => teleport(byName));
      const told = await whipAfter(({ byName, simulation }) => {
        teleport(byName);
        simulation.jump();
      });
      assert.ok(untold > 0.3, `an untold teleport swings the ponytail by ${untold} rad`);
      assert.ok(noticed < untold / 3, `the core noticing the teleport: ${noticed} rad against ${untold} untold`);
      assert.ok(told < untold / 3, `told: ${told} rad against ${untold} untold`);
    });

    test('reset() and jump() name a wearable or take all; an unknown one does nothing and warns once', async () => {
      const simulation = new SpringBoneSimulation(sb);
      const warn = console.warn;
      const warned = [];
      console.warn = (message) => warned.push(message);
      try {
        simulation.reset('nothing');
        simulation.jump('nothing');
        simulation.jump('nothing');
      } finally {
        console.warn = warn;
      }
      assert.equal(warned.length, 1, warned.join('\n'));
      assert.match(warned[0], /unknown-item.*reset: no wearable is registered as "nothing"/);
      assert.deepEqual(simulation.warnings.map((w) => [w.code, w.itemId]), [['unknown-item', 'nothing']]);
      simulation.reset();
      simulation.jump();
      simulation.dispose();
    });
  });
}
