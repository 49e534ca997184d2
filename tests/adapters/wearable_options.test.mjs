// Both adapters take loadRig's option object and hand it over as it is (web/wearable/rig_life.js):
// a `limits` option reaches the simulation through the three.js loader plugin and the Babylon
// drop-in alike (a joint under a 20 degree cone stays inside it), an option loadRig does not know
// is its TypeError, and wear() / attachWearable, where a rig option could only be ignored, refuse
// it.
import assert from 'node:assert/strict';
import { before, describe, test } from 'node:test';
import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';
import * as SkeletonUtils from 'three/examples/jsm/utils/SkeletonUtils.js';
import { babylonKit, readAsset, readJsonAsset } from './babylon_kit.mjs';
import { createSpringBones } from '../../web/springbones.js';
import { SpringBonesLoaderPlugin, attachWearable, wearableNodes } from '../../web/three/index.js';
import { SpringBoneSimulation } from '../../web/babylon/index.js';

const metadata = readJsonAsset('hair_wearable.metadata.json');
const hash = Object.keys(metadata.models)[0];
const wearableBytes = readAsset('hair_wearable.glb');
const kCone = (20 * Math.PI) / 180;
const kLimited = 'SpringBone_ponytail_1';
// Heavy sideways gravity: without its limit the joint leans far past the cone.
const sideways = structuredClone(metadata);
for (const entry of Object.values(sideways.models[hash])) Object.assign(entry, { gravityPower: 4, gravityDir: [1, 0, 0], stiffness: 0.1 });
const options = { springBones: sideways, contentHash: hash, limits: { [kLimited]: { cone: { angle: kCone } } } };

let sb;
let avatarGltf;
let kit;
before(async () => {
  sb = await createSpringBones();
  avatarGltf = await new GLTFLoader().parseAsync(readAsset('avatar.glb').slice().buffer, '');
  kit = await babylonKit('current');
});

/** The angle (radians) between two rotations given as quaternions [x, y, z, w], not quite unit (float32). */
const turn = (a, b) => {
  const dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
  return 2 * Math.acos(Math.min(1, Math.abs(dot) / (Math.hypot(...a) * Math.hypot(...b))));
};

async function loadThree(pluginOptions) {
  const loader = new GLTFLoader();
  loader.register((parser) => new SpringBonesLoaderPlugin(parser, { sb, onWarning: () => {}, ...pluginOptions }));
  return (await loader.parseAsync(wearableBytes.slice().buffer, '')).userData.springBones;
}

/** Largest turn of the limited joint from its rest rotation over 2 s, in three.js. */
async function threeSwing(pluginOptions) {
  const wearable = await loadThree(pluginOptions);
  const avatar = SkeletonUtils.clone(avatarGltf.scene);
  const worn = wearable.wear(avatar);
  const joint = worn.jointObjects[worn.rig.joints.findIndex((j) => j.name === kLimited)];
  const rest = joint.quaternion.toArray();
  let most = 0;
  for (let f = 0; f < 120; f++) {
    avatar.updateMatrixWorld(true);
    worn.update(1 / 60);
    most = Math.max(most, turn(joint.quaternion.toArray(), rest));
  }
  const limit = worn.rig.joints.find((j) => j.name === kLimited).limit;
  wearable.dispose();
  return { most, limit };
}

/** The same in the Babylon drop-in, registered with the same option object. */
async function babylonSwing(params) {
  const scene = kit.scene({ rightHanded: true });
  const container = await kit.load(scene, wearableBytes);
  container.addAllToScene();
  const simulation = new SpringBoneSimulation(sb);
  simulation.registerWearable(scene, container, 'item', params);
  simulation.start(scene);
  const joint = container.transformNodes.find((n) => n.name === kLimited);
  const q = () => [joint.rotationQuaternion.x, joint.rotationQuaternion.y, joint.rotationQuaternion.z, joint.rotationQuaternion.w];
  const rest = q();
  let most = 0;
  for (let f = 0; f < 120; f++) {
    scene.render();
    most = Math.max(most, turn(q(), rest));
  }
  const limit = simulation.rigOf('item').joints.find((j) => j.name === kLimited).limit;
  const warnings = simulation.warnings;
  simulation.dispose(scene);
  scene.getEngine().dispose();
  return { most, limit, warnings };
}

describe('loadRig\'s options reach the simulation through both adapters', () => {
  test('limits: the joint stays inside its 20 degree cone in three.js and in Babylon, and swings past it without', async (t) => {
    const { limits, ...unlimited } = options;
    const free = await threeSwing(unlimited);
    assert.ok(free.most > 1.5 * kCone, `without the limit the joint turns ${free.most} rad`);
    const three = await threeSwing(options);
    const babylon = await babylonSwing(options);
    t.diagnostic(`the limited joint turns at most ${three.most} rad in three.js, ${babylon.most} in Babylon (cone ${kCone}); ${free.most} without the limit`);
    assert.deepEqual(three.limit, babylon.limit);
    assert.ok(three.limit?.cone, 'the rig has the cone');
    // The cone bounds the bone's direction against its rest direction; a twist about the bone
    // adds little here (gravity pulls sideways), so the turn stays near the angle.
    for (const [name, swing] of [['three.js', three], ['Babylon', babylon]]) {
      assert.ok(swing.most < kCone * 1.05, `${name}: the joint turns ${swing.most} rad under a ${kCone} rad cone`);
      assert.ok(swing.most > kCone * 0.5, `${name}: and it does lean (${swing.most})`);
    }
    assert.deepEqual(babylon.warnings, []);
    assert.equal(limits[kLimited].cone.angle, kCone);
  });

  test('an option loadRig does not know is its TypeError in both adapters; createInstance\'s go under instance', async () => {
    await assert.rejects(loadThree({ ...options, integrator: 'xpbd' }), (e) => e instanceof TypeError && /integrator/.test(e.message));
    // Babylon's registerWearable never throws for metadata: loadRig's TypeError is its rig-failed.
    const scene = kit.scene();
    const container = await kit.load(scene, wearableBytes);
    const simulation = new SpringBoneSimulation(sb);
    const warn = console.warn;
    console.warn = () => {};
    try {
      simulation.registerWearable(scene, container, 'item', { ...options, integrator: 'xpbd' });
    } finally {
      console.warn = warn;
    }
    assert.deepEqual(simulation.warnings.map((w) => w.code), ['rig-failed']);
    assert.match(simulation.warnings[0].message, /TypeError.*integrator/);
    simulation.dispose();
    // The plugin's instance options are wear()'s default: 'xpbd' steps at 120 Hz, two steps a frame.
    const stepsPerFrame = async (pluginOptions) => {
      const wearable = await loadThree(pluginOptions);
      const worn = wearable.wear(SkeletonUtils.clone(avatarGltf.scene));
      worn.update(1 / 60);
      worn.update(1 / 60);
      const steps = worn.instance.lastSteps;
      wearable.dispose();
      return steps;
    };
    assert.equal(await stepsPerFrame(options), 1);
    assert.equal(await stepsPerFrame({ ...options, instance: { integrator: 'xpbd' } }), 2);
  });

  test('wear() and attachWearable refuse rig options, which would go nowhere', async () => {
    const wearable = await loadThree(options);
    for (const key of ['limits', 'colliders', 'hitRadius', 'springBones']) {
      assert.throws(() => wearable.wear(SkeletonUtils.clone(avatarGltf.scene), { [key]: {} }),
        (e) => e instanceof TypeError && new RegExp(`^wear: unknown option ${key} .*SpringBonesLoaderPlugin`).test(e.message));
    }
    const copy = SkeletonUtils.clone(wearable.gltf.scene);
    assert.throws(() => attachWearable(SkeletonUtils.clone(avatarGltf.scene), copy, wearable.rig, { nodes: wearableNodes(wearable.gltf, copy), limits: {} }),
      (e) => e instanceof TypeError && /^attachWearable: unknown option limits/.test(e.message));
    assert.throws(() => attachWearable(SkeletonUtils.clone(avatarGltf.scene), copy, wearable.rig, null), /options must be an object/);
    assert.equal(wearable.attachments.length, 0, 'nothing was worn');
    wearable.dispose();
  });
});
