// The demo's sample assets and the creator panel's entity handling (web/demo/js/entity.js), in
// Node: the assets are what scripts/generate/make_sample_avatar.mjs writes, the metadata is keyed by the
// wearable's content hash, and the entity the panel builds for the API's validator and Builder
// edit judges the edited GLB the way a catalyst would.
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { mkdtempSync, readFileSync, readdirSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, join } from 'node:path';
import { describe, test } from 'node:test';
import { fileURLToPath } from 'node:url';
import hashing from '@dcl/hashing';
import { createSpringBones } from '../../web/springbones.js';
import { classifyJson, entityWearing, representationsOf, springBonesOf } from '../../web/demo/js/entity.js';

const root = join(dirname(fileURLToPath(import.meta.url)), '..', '..');
const assets = join(root, 'web', 'demo', 'assets');
const readJson = (path) => JSON.parse(readFileSync(path, 'utf8'));

/** The glTF JSON chunk of a GLB. */
function gltfJson(bytes) {
  const length = bytes.readUInt32LE(12);
  return JSON.parse(bytes.subarray(20, 20 + length).toString('utf8'));
}

describe('sample assets', () => {
  test('are exactly what scripts/generate/make_sample_avatar.mjs writes', () => {
    const out = mkdtempSync(join(tmpdir(), 'springbones-samples-'));
    try {
      execFileSync(process.execPath, [join(root, 'scripts', 'generate', 'make_sample_avatar.mjs'), '--out', out], { stdio: 'pipe' });
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
    const tools = await sb.creatorTools();
    assert.equal(sb.contentHash(glb), hash);
    const rig = sb.loadRig(glb, metadata);  // no hash given: the GLB's own
    assert.equal(rig.contentHash, hash);
    assert.equal(rig.joints.length, 15);
    assert.deepEqual(rig.warnings, []);
    // the entity carries the same data, points its representations at the GLB and would deploy
    const entity = readJson(join(assets, 'hair_wearable.entity.json'));
    assert.deepEqual(entity.metadata.data.springBones, metadata);
    assert.deepEqual(tools.validateSpringBones(entity), []);
    assert.deepEqual(representationsOf(entity).map((r) => r.mainFileHash), [hash]);
    const fromEntity = sb.loadRig(glb, entity.metadata.data.springBones, { entity, bodyShape: 'BaseFemale' });
    assert.equal(fromEntity.joints.length, 15);
  });

  test('every spring node of the wearable hangs under its own Avatar_Head copy', async () => {
    const bytes = readFileSync(join(assets, 'hair_wearable.glb'));
    const doc = gltfJson(bytes);
    const sb = await createSpringBones();
    const tools = await sb.creatorTools();
    const candidates = tools.detectSpringBones(bytes);
    assert.equal(candidates.length, 20);
    const rootNames = candidates.filter((c) => c.parent === -1).map((c) => c.name);
    assert.deepEqual(rootNames, ['SpringBone_ponytail', 'hair_springbone_l', 'hair_springbone_r', 'springbone_earring_l', 'springbone_earring_r']);
    const head = doc.nodes.findIndex((n) => n.name === 'Avatar_Head');
    for (const name of rootNames) assert.ok(doc.nodes[head].children.includes(doc.nodes.findIndex((n) => n.name === name)));
  });
});

describe('creator panel entity handling', () => {
  const male = 'urn:decentraland:off-chain:base-avatars:BaseMale';
  const female = 'urn:decentraland:off-chain:base-avatars:BaseFemale';
  const entry = { stiffness: 1, gravityPower: 0, gravityDir: [0, -1, 0], drag: 0.4, isRoot: true };

  test('tells springBones from entities', () => {
    assert.equal(classifyJson({ version: 1, models: {} }), 'springBones');
    assert.equal(classifyJson({ metadata: { data: { representations: [] } } }), 'entity');
    assert.equal(classifyJson({ data: { springBones: null } }), 'entity');
    assert.equal(classifyJson([1]), 'unknown');
    assert.equal(classifyJson({ hello: 1 }), 'unknown');
    assert.deepEqual(springBonesOf({ data: { springBones: { version: 1, models: {} } } }), { version: 1, models: {} });
    assert.equal(springBonesOf({ metadata: { data: {} } }), null);
  });

  test('without an entity: the GLB is the only model, other keys are stale', async () => {
    const sb = await createSpringBones();
    const tools = await sb.creatorTools();
    const springBones = { version: 1, models: { glbHash: { SpringBone_a: entry }, oldHash: { SpringBone_a: entry } } };
    const entity = entityWearing({ file: 'item.glb', hash: 'glbHash', springBones });
    assert.deepEqual(representationsOf(entity).map((r) => [r.bodyShapes.length, r.mainFileHash]), [[2, 'glbHash']]);
    const errors = tools.validateSpringBones(entity);
    assert.equal(errors.length, 1);
    assert.match(errors[0].message, /oldHash/);
    const exported = tools.setSpringBoneParams(springBones, entity, 'BaseMale', 'SpringBone_a', entry);
    assert.deepEqual(Object.keys(exported.models), ['glbHash']);
    assert.deepEqual(tools.validateSpringBones(entityWearing({ file: 'item.glb', hash: 'glbHash', springBones: exported })), []);
  });

  test('with an entity of two GLBs: the edited one gets the new hash, the other body shape\'s is kept', async () => {
    const sb = await createSpringBones();
    const tools = await sb.creatorTools();
    const entity = {
      content: [{ file: 'm.glb', hash: 'hm' }, { file: 'f.glb', hash: 'hf' }],
      metadata: { data: { representations: [
        { bodyShapes: [male], mainFile: 'm.glb' },
        { bodyShapes: [female], mainFile: 'f.glb' },
      ] } },
    };
    const springBones = { version: 1, models: { hm: { SpringBone_a: entry }, hf: { SpringBone_b: entry }, newHash: { SpringBone_a: entry } } };
    const wearing = entityWearing({ entity, bodyShape: male, file: 'edited.glb', hash: 'newHash', springBones });
    assert.deepEqual(representationsOf(wearing).map((r) => r.mainFileHash), ['newHash', 'hf']);
    assert.deepEqual(representationsOf(entity).map((r) => r.mainFileHash), ['hm', 'hf'], 'the input is not modified');
    const exported = tools.setSpringBoneParams(springBones, wearing, male, 'SpringBone_a', entry);
    assert.deepEqual(Object.keys(exported.models).sort(), ['hf', 'newHash'], 'the old male hash is stale');
    // a Builder item ({contents, data}) is patched the same way
    const item = { contents: { 'm.glb': 'hm' }, data: { representations: [{ bodyShapes: [male, female], mainFile: 'm.glb' }] } };
    assert.deepEqual(entityWearing({ entity: item, bodyShape: female, file: 'x.glb', hash: 'h2', springBones }).contents, { 'm.glb': 'h2' });
  });
});
