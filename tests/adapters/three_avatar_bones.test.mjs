// The three.js adapter measures the 'dcl-body' shapes on the avatar a wearable is worn on
// (avatarRestBones: the inverse bind matrices of the avatar's skins), not on the bones the
// wearable's GLB carries: the demo's hair (Hips to Head) worn through the loader plugin gets all
// eight shapes with no warning, and under a fast half turn and a jump, driven through the adapter,
// no ponytail tail gets more than 1 mm into the chest, shoulder or upper-arm shapes with either
// integrator. An avatar that lacks a bone still leaves its shape out, with the warning naming it.
import assert from 'node:assert/strict';
import { describe, test } from 'node:test';
import { Group, Matrix4, Quaternion, Scene, Vector3 } from 'three';
import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';
import * as SkeletonUtils from 'three/examples/jsm/utils/SkeletonUtils.js';
import { avatarRestBones, SpringBonesLoaderPlugin } from '../../web/three/index.js';
import { restBonesFromInverseBinds } from '../../web/wearable/avatar_bones.js';
import { loadSampleWearable } from '../wasm/sample_wearable.mjs';
import { DeepestTails, describeDepths, holderPose, kBodyShapes, kDt, kFrames, kHitRadius, mm } from './turn_and_jump.mjs';

const { sb, avatarGltf, wearableBytes, metadata } = await loadSampleWearable();
const kDclBody = { colliders: 'dcl-body', hitRadius: kHitRadius };

async function loadWithPlugin(options) {
  const loader = new GLTFLoader();
  loader.register((parser) => new SpringBonesLoaderPlugin(parser, { sb, springBones: metadata, glb: wearableBytes, ...options }));
  return (await loader.parseAsync(wearableBytes.slice().buffer, '')).userData.springBones;
}

/** A clone of the avatar in a scene, under a holder group that carries the motion. */
function avatarInScene() {
  const scene = new Scene();
  const holder = new Group();
  scene.add(holder);
  const avatar = SkeletonUtils.clone(avatarGltf.scene);
  holder.add(avatar);
  return { scene, holder, avatar };
}

describe("the avatar's rest bones", () => {
  test("are the rest world matrices of the avatar's bones, whatever pose it is in when read", () => {
    const { avatar } = avatarInScene();
    avatar.updateMatrixWorld(true);
    const rest = {};
    avatar.traverse((o) => { if (o.name.startsWith('Avatar_') && !(o.name in rest)) rest[o.name] = [...o.matrixWorld.elements]; });
    // Posed before they are first read: the bind pose is read, not the pose.
    avatar.getObjectByName('Avatar_LeftArm').rotation.z += 1;
    avatar.parent.rotation.y = 2;
    avatar.parent.updateMatrixWorld(true);
    const bones = avatarRestBones(avatar);
    assert.deepEqual(Object.keys(bones).sort(), Object.keys(rest).sort());
    let worst = 0;
    for (const [name, m] of Object.entries(bones)) worst = Math.max(worst, ...m.map((v, k) => Math.abs(v - rest[name][k])));
    assert.ok(worst < 1e-6, `largest difference ${worst}`);
    assert.equal(avatarRestBones(avatar), bones, 'cached per avatar root');
    assert.equal(avatarRestBones(new Group()), null, 'no skins: no bones');
    assert.throws(() => avatarRestBones({}), TypeError);
  });
});

describe('wear() on the avatar', () => {
  test("the demo's hair gets all eight shapes, with no warning, on a rig shared by avatars of the same bones", async () => {
    const wearable = await loadWithPlugin(kDclBody);
    assert.equal(wearable.rig.colliders.length, 4, 'the GLB alone measures four');
    const first = wearable.wear(avatarInScene().avatar);
    const second = wearable.wear(avatarInScene().avatar);
    assert.deepEqual(first.rig.colliders.map((c) => c.node), kBodyShapes);
    assert.deepEqual(first.rig.warnings, []);
    assert.deepEqual(first.warnings, []);
    assert.deepEqual(wearable.warnings, []);
    assert.equal(second.rig, first.rig, 'one rig for both clones');
    // The shapes on bones the GLB lacks ride on the avatar's bones of those names.
    for (const name of ['Avatar_LeftShoulder', 'Avatar_RightArm']) {
      const d = first.rig.drivers.findIndex((x) => x.name === name);
      assert.equal(first.rig.drivers[d].node, -1);
      assert.equal(first.driverObjects[d], first.avatarRoot.getObjectByName(name));
    }
    // A live edit keeps them measured on the avatar.
    wearable.updateParams({ SpringBone_ponytail: { stiffness: 2, isRoot: true } });
    assert.deepEqual(first.rig.colliders.map((c) => c.node), kBodyShapes);
    assert.equal(second.rig, first.rig);
    const edited = first.rig;
    wearable.dispose();
    assert.equal(edited.disposed, true, 'the avatar\'s rig is the wearable\'s to dispose of');
  });

  test('with the module still on its way, the attachment gets the rig measured on its avatar when it comes', async () => {
    const wearable = await loadWithPlugin({ ...kDclBody, sb: Promise.resolve(sb) });
    const attachment = wearable.wear(avatarInScene().avatar);
    await attachment.ready;
    assert.deepEqual(attachment.rig.colliders.map((c) => c.node), kBodyShapes);
    assert.deepEqual(attachment.rig.warnings, []);
    wearable.dispose();
  });

  test('avatarBones given by the page win, and without colliders nothing is measured', async () => {
    const { Avatar_Head: head, Avatar_Neck: neck } = avatarRestBones(avatarInScene().avatar);
    const given = await loadWithPlugin({ ...kDclBody, avatarBones: { Avatar_Head: head, Avatar_Neck: neck } });
    const worn = given.wear(avatarInScene().avatar);
    assert.equal(worn.rig, given.rig);
    assert.equal(worn.rig.colliders.length, 2);
    given.dispose();
    const none = await loadWithPlugin({});
    assert.equal(none.wear(avatarInScene().avatar).rig, none.rig);
    assert.equal(none.rig.colliders.length, 0);
    none.dispose();
  });

  test('an avatar that truly lacks a bone leaves its shapes out, and the warning names the bone', async () => {
    const wearable = await loadWithPlugin(kDclBody);
    const { avatar } = avatarInScene();
    const foreArm = avatar.getObjectByName('Avatar_LeftForeArm');
    foreArm.name = 'Avatar_LeftForeArm_renamed';
    delete foreArm.userData.name;  // GLTFLoader keeps the glTF name there
    const attachment = wearable.wear(avatar);
    assert.equal(attachment.rig.colliders.length, 7);
    const skipped = attachment.rig.warnings.filter((w) => w.code === 'body-collider-skipped');
    assert.equal(skipped.length, 1);
    assert.match(skipped[0].message, /left-upper-arm \(the avatar lacks Avatar_LeftForeArm\)/);
    wearable.dispose();
  });
});

/** The hair worn through the plugin under the turn and the jump: the deepest ponytail tails. */
async function deepestUnderTurnAndJump(integrator, options, shapes) {
  const wearable = await loadWithPlugin(options);
  const { scene, holder, avatar } = avatarInScene();
  const attachment = wearable.wear(avatar, { instance: { integrator } });
  const deepest = new DeepestTails(attachment.rig, shapes);
  const carrier = (name) => avatar.getObjectByName(name).matrixWorld.elements;
  for (let f = 0; f < kFrames; f++) {
    const { yaw, height } = holderPose(f);
    holder.rotation.set(0, yaw, 0);
    holder.position.set(0, height, 0);
    scene.updateMatrixWorld(true);
    attachment.update(kDt);
    deepest.measure(attachment.instance.worldMatrices, carrier);
  }
  wearable.dispose();
  return deepest.result;
}

describe('under a fast half turn and a jump, through the adapter', () => {
  const shapes = (() => {
    const rig = sb.loadRig(wearableBytes, metadata, { colliders: 'dcl-body', avatarBones: avatarRestBones(avatarInScene().avatar) });
    const out = rig.colliders;
    rig.dispose();
    return out;
  })();
  for (const integrator of ['vrm', 'xpbd']) {
    test(`${integrator}: no ponytail tail gets more than 1 mm into the chest, shoulder or upper-arm shapes`, async (t) => {
      const without = await deepestUnderTurnAndJump(integrator, {}, shapes);
      const worn = await deepestUnderTurnAndJump(integrator, kDclBody, shapes);
      t.diagnostic(`${integrator}, deepest ponytail tail (negative: outside): without colliders ${describeDepths(without)}; worn with 'dcl-body' ${describeDepths(worn)}`);
      assert.ok(without.all > 0.01, `without colliders the deepest tail is only ${mm(without.all)} inside: the motion does not test the shapes`);
      assert.ok(worn.all <= 0.001, `worn with 'dcl-body' a tail went ${mm(worn.all)} in`);
    });
  }
});

test('the shared layer inverts inverse bind matrices as three.js does, and passes over what is no rest pose', () => {
  const inverseBind = new Matrix4().compose(new Vector3(0.1, 1.2, -0.3), new Quaternion(0.2, -0.4, 0.1, 0.88).normalize(), new Vector3(0.01, 0.02, 0.015));
  const bones = restBonesFromInverseBinds([
    { name: 'Avatar_Head', inverseBind: inverseBind.elements },
    { name: 'Avatar_Head', inverseBind: new Matrix4().elements },  // the first of a name counts
    { name: 'Avatar_Neck', inverseBind: new Matrix4().makeScale(0, 1, 1).elements },  // singular
    { name: 'Avatar_Spine', inverseBind: [...new Matrix4().elements.slice(0, 15), NaN] },
    { name: 'Avatar_Hips', inverseBind: [1, 0, 0, 0.5, ...new Matrix4().elements.slice(4)] },  // not affine
  ]);
  assert.deepEqual(Object.keys(bones), ['Avatar_Head']);
  const expected = inverseBind.clone().invert().elements;
  assert.ok(bones.Avatar_Head.every((v, k) => Math.abs(v - expected[k]) < 1e-9), `${bones.Avatar_Head} against ${expected}`);
  assert.equal(restBonesFromInverseBinds([]), null);
});
