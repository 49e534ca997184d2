// Live tuning in three.js with the Babylon drop-in's semantics (issue 37): wearable.updateParams
// merges the edited entry over the current one, loads the rig again and every attachment switches
// to it keeping its motion (attachment.setRig carries it with instance.carryFrom). Measured the
// way tests/wasm/babylon_dropin.test.mjs measures the drop-in: against a twin never edited.
import assert from 'node:assert/strict';
import { before, describe, test } from 'node:test';
import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';
import * as SkeletonUtils from 'three/examples/jsm/utils/SkeletonUtils.js';
import { readFileSync } from 'node:fs';
import { createSpringBones } from '../../web/springbones.js';
import { SpringBonesLoaderPlugin } from '../../web/three/index.js';

const assets = new URL('../../web/demo/assets/', import.meta.url);
const read = (name) => new Uint8Array(readFileSync(new URL(name, assets)));
const metadata = JSON.parse(readFileSync(new URL('hair_wearable.metadata.json', assets), 'utf8'));
const hash = Object.keys(metadata.models)[0];
const entry = metadata.models[hash];
const wearableBytes = read('hair_wearable.glb');

let sb;
let avatarGltf;
before(async () => {
  sb = await createSpringBones();
  avatarGltf = await new GLTFLoader().parseAsync(read('avatar.glb').slice().buffer, '');
});

/**
 * The angle (radians) between two rotations. The quaternions come from float32 rotations and are
 * not quite unit: the dot product is divided by their lengths, else a quaternion would be 1e-3
 * rad from itself.
 */
const turn = (a, b) => {
  const dot = a.x * b.x + a.y * b.y + a.z * b.z + a.w * b.w;
  return 2 * Math.acos(Math.min(1, Math.abs(dot) / (a.length() * b.length())));
};

/** The sample loaded with the plugin and worn on a clone of the avatar, with a swaying head. */
async function worn() {
  const loader = new GLTFLoader();
  loader.register((parser) => new SpringBonesLoaderPlugin(parser, { sb, springBones: metadata, contentHash: hash }));
  const wearable = (await loader.parseAsync(wearableBytes.slice().buffer, '')).userData.springBones;
  const avatar = SkeletonUtils.clone(avatarGltf.scene);
  const attachment = wearable.wear(avatar);
  let head = null;
  avatar.traverse((o) => { if ((o.userData.name ?? o.name) === 'Avatar_Head') head = o; });
  const springs = attachment.jointObjects;
  /** A frame of the head swaying and turning (an emote). */
  const frame = (f) => {
    head.position.x = 0.15 * Math.sin(f * 0.15);
    head.rotation.y = 0.5 * Math.sin(f * 0.11);
    avatar.updateMatrixWorld(true);
    attachment.update(1 / 60);
  };
  const pose = () => attachment.jointObjects.map((o) => o.quaternion.clone());
  return { wearable, attachment, frame, pose, springs };
}

const apartOf = (a, b) => Math.max(...a.map((q, i) => turn(q, b[i])));

describe('wearable.updateParams keeps the motion, as the Babylon drop-in does', () => {
  test('the same entry changes nothing: as a twin never updated; a restart (carry: false) would not', async (t) => {
    const updated = await worn();
    const twin = await worn();
    const restarted = await worn();
    for (let f = 0; f < 60; f++) for (const w of [updated, twin, restarted]) w.frame(f);
    updated.wearable.updateParams(structuredClone(entry));
    const again = sb.loadRig(restarted.wearable.gltf.parser.json, metadata, { contentHash: hash });
    restarted.attachment.setRig(again, { carry: false });
    let apart = 0;
    let restartApart = 0;
    let moving = 0;
    for (let f = 60; f < 120; f++) {
      const before = updated.pose();
      for (const w of [updated, twin, restarted]) w.frame(f);
      apart = Math.max(apart, apartOf(updated.pose(), twin.pose()));
      restartApart = Math.max(restartApart, apartOf(restarted.pose(), twin.pose()));
      moving = Math.max(moving, apartOf(updated.pose(), before));
    }
    t.diagnostic(`same entry: ${apart} rad from the twin (restart: ${restartApart} rad), a frame moves up to ${moving}`);
    assert.ok(moving > 1e-3, `the chains keep moving (${moving})`);
    assert.ok(apart < 1e-5, `within ${apart} rad of the twin`);
    assert.ok(restartApart > 100 * Math.max(apart, 1e-6), `a restart is ${restartApart} rad from the twin`);
    for (const w of [updated, twin, restarted]) w.wearable.dispose();
    again.dispose();
  });

  test('an edit: no pop, untouched chains go on exactly, the new value in the rig, fields merged', async (t) => {
    const { wearable, frame, pose, springs } = await worn();
    const chains = wearable.rig.chains.length;
    const twin = await worn();
    let ordinary = 0;
    let last = pose();
    for (let f = 0; f < 90; f++) {
      frame(f);
      twin.frame(f);
      const now = pose();
      if (f >= 30) ordinary = Math.max(ordinary, apartOf(now, last));
      last = now;
    }
    const edited = { ...entry, SpringBone_ponytail: { ...entry.SpringBone_ponytail, stiffness: 1.5 } };
    wearable.updateParams(edited);
    frame(90);
    twin.frame(90);
    const ponytail = springs.map((o) => (o.userData.name ?? o.name).startsWith('SpringBone_ponytail'));
    const fromTwin = pose().map((q, i) => turn(q, twin.pose()[i]));
    const pop = apartOf(pose(), last);
    t.diagnostic(`stiffness 1.2 -> 1.5: the edit frame turns a joint by ${pop} rad (a steady frame: up to ${ordinary}); ` +
      `the edited chain is ${Math.max(...fromTwin.filter((_, i) => ponytail[i]))} rad from the twin`);
    assert.ok(Math.max(...fromTwin.filter((_, i) => !ponytail[i])) < 1e-6, `untouched chains: ${fromTwin}`);
    assert.ok(pop <= 2 * ordinary, `the edit frame turns a joint by ${pop}: a steady frame up to ${ordinary}`);
    assert.equal(wearable.rig.joints.find((j) => j.name === 'SpringBone_ponytail').params.stiffness, 1.5);
    wearable.updateParams({ ...edited, hair_springbone_l: { drag: 0.45 } });  // no isRoot: merged over the old entry
    const merged = wearable.rig.joints.find((j) => j.name === 'hair_springbone_l');
    assert.equal(merged.params.drag, 0.45);
    assert.equal(merged.params.stiffness, entry.hair_springbone_l.stiffness, 'the other fields kept');
    assert.equal(wearable.rig.chains.length, chains, 'still a root (isRoot merged from before)');
    assert.equal(wearable.attachments[0].rig, wearable.rig, 'the attachment runs the new rig');
    wearable.dispose();
    twin.wearable.dispose();
  });

  test('bad params are a TypeError; loadRig\'s error for the edit leaves the running rig as it was', async () => {
    const { wearable } = await worn();
    const rig = wearable.rig;
    assert.throws(() => wearable.updateParams(null), TypeError);
    assert.throws(() => wearable.updateParams([]), TypeError);
    assert.throws(() => wearable.updateParams({ SpringBone_ponytail: { isRoot: true, stiffness: 10n } }), /BigInt/);
    assert.equal(wearable.rig, rig);
    assert.equal(rig.disposed, false);
    wearable.dispose();
    assert.throws(() => wearable.updateParams(entry), /disposed/);
  });
});
