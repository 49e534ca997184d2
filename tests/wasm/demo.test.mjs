// The demo's sample assets and the creator panel's metadata logic (web/demo/js/springBonesData.js),
// in Node: the assets are what scripts/make_sample_avatar.mjs writes, the metadata is keyed by the
// wearable's content hash, and the panel's validator makes the catalyst's accept/reject decisions
// on the shared validation cases.
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { mkdtempSync, readFileSync, readdirSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, join } from 'node:path';
import { describe, test } from 'node:test';
import { fileURLToPath } from 'node:url';
import hashing from '@dcl/hashing';
import { createSpringBones } from '../../web/springbones.js';
import {
  activeHashes, classifyJson, editorWarnings, effectiveParams, exportSpringBones, isSpringBoneName,
  prefillEntries, representationsOf, springBoneTree, validateForDeploy, validateSchema,
} from '../../web/demo/js/springBonesData.js';

const root = join(dirname(fileURLToPath(import.meta.url)), '..', '..');
const assets = join(root, 'web', 'demo', 'assets');
const readJson = (path) => JSON.parse(readFileSync(path, 'utf8'));

/** The glTF JSON chunk of a GLB. */
function gltfJson(bytes) {
  const length = bytes.readUInt32LE(12);
  return JSON.parse(bytes.subarray(20, 20 + length).toString('utf8'));
}

describe('sample assets', () => {
  test('are exactly what scripts/make_sample_avatar.mjs writes', () => {
    const out = mkdtempSync(join(tmpdir(), 'springbones-samples-'));
    try {
      execFileSync(process.execPath, [join(root, 'scripts', 'make_sample_avatar.mjs'), '--out', out], { stdio: 'pipe' });
      const files = readdirSync(out).sort();
      assert.deepEqual(files, readdirSync(assets).sort());
      for (const f of files) assert.ok(readFileSync(join(out, f)).equals(readFileSync(join(assets, f))), `${f} differs: rerun the script`);
    } finally {
      rmSync(out, { recursive: true, force: true });
    }
  });

  test('the avatar has the 62-bone Decentraland armature and the idle and walk clips', () => {
    const doc = gltfJson(readFileSync(join(assets, 'avatar.glb')));
    const names = doc.nodes.map((n) => n.name);
    const bones = names.filter((n) => n.startsWith('Avatar_'));
    assert.equal(bones.length, 62);
    const armature = doc.nodes[names.indexOf('Armature')];
    assert.deepEqual(armature.scale, [0.01, 0.01, 0.01]);
    assert.deepEqual(doc.animations.map((a) => a.name), ['idle', 'walk']);
    assert.equal(doc.skins[0].joints.length, 62);
  });

  test('the wearable metadata is keyed by the GLB content hash (core and @dcl/hashing agree)', async () => {
    const glb = new Uint8Array(readFileSync(join(assets, 'hair_wearable.glb')));
    const metadata = readJson(join(assets, 'hair_wearable.metadata.json'));
    const hash = await hashing.hashV1(glb);
    assert.deepEqual(Object.keys(metadata.models), [hash]);
    const sb = await createSpringBones();
    assert.equal(sb.contentHash(glb), hash);
    const rig = sb.loadRig(glb, metadata);  // no hash given: the GLB's own
    assert.equal(rig.contentHash, hash);
    assert.equal(rig.joints.length, 15);
    assert.deepEqual(rig.warnings, []);
    assert.deepEqual(validateForDeploy(metadata, [hash]), []);
    // the entity carries the same data and points its representations at the GLB
    const entity = readJson(join(assets, 'hair_wearable.entity.json'));
    assert.deepEqual(entity.metadata.data.springBones, metadata);
    assert.deepEqual(representationsOf(entity).map((r) => r.mainFileHash), [hash]);
    const fromEntity = sb.loadRig(glb, entity.metadata.data.springBones, { entity, bodyShape: 'BaseFemale' });
    assert.equal(fromEntity.joints.length, 15);
  });

  test('every spring node of the wearable hangs under its own Avatar_Head copy', () => {
    const doc = gltfJson(readFileSync(join(assets, 'hair_wearable.glb')));
    const tree = springBoneTree(doc);
    assert.equal(tree.candidates.length, 20);
    const rootNames = tree.candidates.filter((c) => c.parent === -1).map((c) => c.name);
    assert.deepEqual(rootNames, ['SpringBone_ponytail', 'hair_springbone_l', 'hair_springbone_r', 'springbone_earring_l', 'springbone_earring_r']);
    const head = doc.nodes.findIndex((n) => n.name === 'Avatar_Head');
    for (const name of rootNames) assert.ok(doc.nodes[head].children.includes(doc.nodes.findIndex((n) => n.name === name)));
    assert.ok(tree.otherNodes.includes('Avatar_Hips'));
  });
});

describe('creator panel metadata', () => {
  test('makes the catalyst\'s decisions on every shared validation case', () => {
    const cases = readJson(join(root, 'tests', 'fixtures', 'validation_cases.json'));
    assert.ok(cases.length > 900);
    for (const c of cases) {
      assert.equal(validateSchema(c.input).length === 0, c.valid, `schema: ${c.name}`);
      const entity = { content: c.content, metadata: { data: { representations: c.representations, springBones: c.input } } };
      const active = [...new Set(representationsOf(entity).map((r) => r.mainFileHash).filter((h) => h !== null))];
      assert.equal(validateForDeploy(c.input, active).length === 0, c.catalystErrors.length === 0, `catalyst: ${c.name}`);
    }
  });

  test('the discovery rule is ASCII case-insensitive', () => {
    for (const name of ['SpringBone_hair_left', 'hair_springbone_l', 'ponytail_SPRINGBONE', 'xSpRiNgBoNex']) assert.ok(isSpringBoneName(name), name);
    for (const name of ['skirt_1', 'spring_bone', 'ſpringbone', '', null]) assert.ok(!isSpringBoneName(name), String(name));
  });

  test('inherits parameters from the nearest entry up the chain, else the defaults', () => {
    const doc = gltfJson(readFileSync(join(assets, 'hair_wearable.glb')));
    const tree = springBoneTree(doc);
    const { models } = readJson(join(assets, 'hair_wearable.metadata.json'));
    const entries = Object.values(models)[0];
    const slot = (name) => tree.candidates.findIndex((c) => c.name === name);
    assert.equal(effectiveParams(tree, slot('SpringBone_ponytail_2'), entries).from, 'SpringBone_ponytail');
    assert.equal(effectiveParams(tree, slot('SpringBone_ponytail_4'), entries).from, 'SpringBone_ponytail_3');
    assert.equal(effectiveParams(tree, slot('SpringBone_ponytail_4'), entries).params.stiffness, 0.7);
    assert.deepEqual(effectiveParams(tree, slot('SpringBone_ponytail_4'), {}), {
      params: { stiffness: 2, gravityPower: 0, gravityDir: [0, -1, 0], drag: 0.5 }, from: null,
    });
    assert.deepEqual(Object.keys(prefillEntries(tree)), ['SpringBone_ponytail', 'hair_springbone_l', 'hair_springbone_r', 'springbone_earring_l', 'springbone_earring_r']);
  });

  test('export keys the entries by the GLB hash and drops stale hashes', () => {
    const entries = { SpringBone_a: { isRoot: true, drag: 0.4, stiffness: 1, gravityPower: 0, gravityDir: [0, -1, 0] } };
    const original = { version: 1, models: { old: { SpringBone_a: {} }, other: { SpringBone_b: { stiffness: 1 } }, new: { stale: true } } };
    const { data, dropped } = exportSpringBones({ glbHash: 'new', entries, original, active: ['new', 'other'] });
    assert.deepEqual(Object.keys(data.models), ['new', 'other']);
    assert.deepEqual(dropped, ['old']);
    assert.deepEqual(Object.keys(data.models.new.SpringBone_a), ['stiffness', 'gravityPower', 'gravityDir', 'drag', 'isRoot'], 'ADR field order');
    assert.deepEqual(exportSpringBones({ glbHash: 'h', entries: {} }).data, { version: 1, models: {} });
  });

  test('keeps the other body shape\'s model when the entity has two', () => {
    const entity = {
      content: [{ file: 'm.glb', hash: 'hm' }, { file: 'f.glb', hash: 'hf' }],
      metadata: { data: { representations: [
        { bodyShapes: ['urn:decentraland:off-chain:base-avatars:BaseMale'], mainFile: 'm.glb' },
        { bodyShapes: ['urn:decentraland:off-chain:base-avatars:BaseFemale'], mainFile: 'f.glb' },
      ] } },
    };
    assert.deepEqual(activeHashes('new', entity, 'urn:decentraland:off-chain:base-avatars:BaseMale'), ['new', 'hf']);
    assert.equal(classifyJson(entity), 'entity');
    assert.equal(classifyJson({ version: 1, models: {} }), 'springBones');
    assert.equal(classifyJson([1]), 'unknown');
  });

  test('warns about entries for missing nodes, bad centers, the Builder cap and no root', () => {
    const tree = springBoneTree({ nodes: [{ name: 'Avatar_Head', children: [1] }, { name: 'SpringBone_a', children: [2] }, { name: 'SpringBone_a_tip' }] });
    const messages = (entries) => editorWarnings(tree, entries).map((w) => w.message).join('\n');
    assert.match(messages({ SpringBone_x: { isRoot: true } }), /not a spring-bone node/);
    assert.match(messages({ SpringBone_a: { isRoot: true, center: 'SpringBone_a_tip' } }), /is a spring bone/);
    assert.match(messages({ SpringBone_a: { isRoot: true, center: 'Nowhere' } }), /not a node of this GLB/);
    assert.match(messages({ SpringBone_a: { isRoot: false } }), /no entry has isRoot: true/);
    assert.equal(messages({ SpringBone_a: { isRoot: true, center: 'Avatar_Head' } }), '');
  });
});
