// Builder edits through the JS API: sb.detectSpringBones lists the candidates of a GLB with the
// values to prefill, sb.setSpringBoneParams writes one node's parameters under the right GLB
// hash. Neither touches the GLB bytes nor the objects passed in.
import assert from 'node:assert/strict';
import { describe, test } from 'node:test';

import { createSpringBones, SpringBonesError } from '../../web/springbones.js';
import { contentHashOf, fixture, springRig } from './helpers.mjs';

const sb = await createSpringBones();
const tools = await sb.creatorTools();  // validation and the Builder edits

const kBaseMale = 'urn:decentraland:off-chain:base-avatars:BaseMale';
const kBaseFemale = 'urn:decentraland:off-chain:base-avatars:BaseFemale';
const kDefaults = { stiffness: 2, gravityPower: 0, gravityDir: [0, -1, 0], drag: 0.5 };

const hairGlb = fixture('avatar_hair.glb');
const hairMetadata = JSON.parse(fixture('avatar_hair.metadata.json').toString('utf8'));
const hairHash = contentHashOf('avatar_hair.glb');

// A catalyst entity whose representations wear `files` ({bodyShape: [file, hash]}).
function entityWearing(files, springBones = null) {
  const content = [];
  const representations = [];
  for (const [shape, [file, hash]] of Object.entries(files)) {
    if (!content.some((c) => c.file === file)) content.push({ file, hash });
    representations.push({ bodyShapes: [shape], mainFile: file, contents: [file] });
  }
  content.push({ file: 'thumbnail.png', hash: 'QmThumbnail' });
  return { content, metadata: { data: { representations, springBones } } };
}

describe('detectSpringBones', () => {
  test('every node whose name contains "springbone", parents first, prefilled from the GLB\'s entry', () => {
    const before = Uint8Array.from(hairGlb);
    const candidates = tools.detectSpringBones(hairGlb, hairMetadata);
    assert.deepEqual(Uint8Array.from(hairGlb), before, 'the GLB bytes are untouched');
    assert.ok(candidates.length > 10);
    for (const [i, c] of candidates.entries()) {
      assert.match(c.name, /springbone/i);
      assert.ok(c.parent < i, 'a candidate comes after its candidate ancestor');
    }
    const entries = hairMetadata.models[hairHash];
    for (const c of candidates) {
      const entry = entries[c.name];
      assert.equal(c.hasEntry, entry !== undefined, c.name);
      if (entry) {
        // The values as the runtime reads them: gravityDir normalised.
        const { gravityDir, ...scalars } = c.params;
        assert.deepEqual(scalars, { stiffness: entry.stiffness, gravityPower: entry.gravityPower, drag: entry.drag }, c.name);
        const length = Math.hypot(...entry.gravityDir);
        gravityDir.forEach((v, k) => assert.ok(Math.abs(v - entry.gravityDir[k] / length) < 1e-6, c.name));
        assert.equal(c.isRoot, entry.isRoot ?? false, c.name);
        if ('center' in entry) assert.equal(c.center, entry.center, c.name);
        else assert.ok(!('center' in c), c.name);
      } else {
        assert.deepEqual(c.params, kDefaults, c.name);
      }
    }
    const earring = candidates.find((c) => c.name === 'springbone_earring_r');
    assert.equal(earring.center, 'Avatar_Hips');
  });

  test('without an entry for the GLB: defaults, and the top-most candidates are roots', () => {
    for (const springBones of [undefined, null, { version: 1, models: { other: {} } }]) {
      const candidates = tools.detectSpringBones(hairGlb, springBones);
      assert.ok(candidates.length > 10);
      for (const c of candidates) {
        assert.equal(c.hasEntry, false);
        assert.deepEqual(c.params, kDefaults);
        assert.equal(c.isRoot, c.parent === -1, c.name);
      }
    }
  });

  test('the models key comes from contentHash or the entity, as in loadRig', () => {
    const { glb, springBones, hash } = springRig({ chains: 2, hash: 'QmRig', params: { stiffness: 3.5 } });
    assert.ok(tools.detectSpringBones(glb, springBones).every((c) => !c.hasEntry));
    const byHash = tools.detectSpringBones(glb, springBones, { contentHash: hash });
    assert.deepEqual(byHash.filter((c) => c.hasEntry).map((c) => [c.name, c.params.stiffness]),
                     [['SpringBone_0_0', 3.5], ['SpringBone_1_0', 3.5]]);
    const entity = entityWearing({ [kBaseMale]: ['rig.glb', hash] });
    assert.deepEqual(tools.detectSpringBones(glb, springBones, { entity, bodyShape: 'BaseMale' }), byHash);
  });

  test('bad input: TypeError before crossing, SpringBonesError after, the module keeps working', () => {
    const before = sb.stats();
    const toolsBefore = tools.stats();
    for (const bad of [undefined, 'x', [1], new Float32Array(2)]) assert.throws(() => tools.detectSpringBones(bad), TypeError);
    assert.throws(() => tools.detectSpringBones(hairGlb, 42), TypeError);
    assert.throws(() => tools.detectSpringBones(hairGlb, null, { hash: 'x' }), TypeError);
    assert.throws(() => tools.detectSpringBones(hairGlb, null, { contentHash: '' }), RangeError);
    assert.throws(() => tools.detectSpringBones(new Uint8Array([1, 2, 3, 4]), null),
                  (e) => e instanceof SpringBonesError && e.code === 'glb-bad-magic');
    assert.throws(() => tools.detectSpringBones(hairGlb, '{"version": 1, '),
                  (e) => e instanceof SpringBonesError && e.code === 'metadata-bad-json');
    assert.throws(() => tools.detectSpringBones(hairGlb, null, { entity: {}, bodyShape: 'BaseMale' }), SpringBonesError);
    assert.deepEqual(sb.stats(), before);
    assert.deepEqual(tools.stats(), toolsBefore);
    assert.ok(tools.detectSpringBones(hairGlb, hairMetadata).length > 10);
  });
});

describe('setSpringBoneParams', () => {
  const params = { stiffness: 1.25, gravityPower: 0.5, gravityDir: [0, -1, 0], drag: 0.3, isRoot: true };

  test('writes under the main file hash of the body shape\'s representation; the inputs are unchanged', () => {
    const entity = entityWearing({ [kBaseMale]: ['male.glb', 'QmMale'], [kBaseFemale]: ['female.glb', 'QmFemale'] });
    const springBones = { version: 1, models: { QmMale: { Tail_springbone: { ...params, stiffness: 4 } } } };
    const entityCopy = structuredClone(entity);
    const springBonesCopy = structuredClone(springBones);
    const out = tools.setSpringBoneParams(springBones, entity, kBaseFemale, 'Hair_springbone', params);
    assert.deepEqual(entity, entityCopy);
    assert.deepEqual(springBones, springBonesCopy);
    assert.deepEqual(out, {
      version: 1,
      models: { QmFemale: { Hair_springbone: params }, QmMale: { Tail_springbone: { ...params, stiffness: 4 } } },
    });
    // The result validates against the same entity.
    assert.deepEqual(tools.validateSpringBones({ ...entity, metadata: { data: { ...entity.metadata.data, springBones: out } } }), []);
  });

  test('a GLB shared by both body shapes gets one entry, whichever shape is edited', () => {
    const entity = entityWearing({ [kBaseMale]: ['shared.glb', 'QmShared'], [kBaseFemale]: ['shared.glb', 'QmShared'] });
    const first = tools.setSpringBoneParams(null, entity, 'BaseMale', 'Hair_springbone', params);
    const second = tools.setSpringBoneParams(first, entity, 'BaseFemale', 'Hair_springbone', { ...params, drag: 0.9 });
    assert.deepEqual(Object.keys(second.models), ['QmShared']);
    assert.deepEqual(second.models.QmShared, { Hair_springbone: { ...params, drag: 0.9 } });
  });

  test('entries under hashes no representation uses are dropped (a re-uploaded GLB)', () => {
    const entity = entityWearing({ [kBaseMale]: ['male.glb', 'QmNew'] });
    const springBones = { version: 1, models: { QmOld: { Hair_springbone: params }, QmThumbnail: { Hair_springbone: params } } };
    const out = tools.setSpringBoneParams(springBones, entity, kBaseMale, 'Ear_SpringBone', params);
    assert.deepEqual(out, { version: 1, models: { QmNew: { Ear_SpringBone: params } } });
  });

  test('params null removes the entry', () => {
    const entity = entityWearing({ [kBaseMale]: ['male.glb', 'QmMale'] });
    const springBones = { version: 1, models: { QmMale: { Hair_springbone: params, Tail_springbone: params } } };
    const out = tools.setSpringBoneParams(springBones, JSON.stringify(entity), kBaseMale, 'Hair_springbone', null);
    assert.deepEqual(out, { version: 1, models: { QmMale: { Tail_springbone: params } } });
  });

  test('what it writes is what loadRig reads, and the GLB is untouched', () => {
    const { glb, hash } = springRig({ chains: 1, hash: 'unused' });
    const glbHash = sb.contentHash(glb);
    const entity = entityWearing({ [kBaseMale]: ['rig.glb', glbHash] });
    const before = Uint8Array.from(glb);
    const springBones = tools.setSpringBoneParams(null, entity, kBaseMale, 'SpringBone_0_0', params);
    assert.notEqual(hash, glbHash);
    assert.deepEqual(glb, before);
    const rig = sb.loadRig(glb, springBones, { entity, bodyShape: kBaseMale });
    assert.equal(rig.contentHash, glbHash);
    assert.equal(rig.joints.length, 3);
    assert.deepEqual(rig.joints[0].params, { stiffness: 1.25, gravityPower: 0.5, gravityDir: [0, -1, 0], drag: 0.3 });
    rig.dispose();
  });

  test('bad input: TypeError / RangeError before crossing, SpringBonesError after, the module keeps working', () => {
    const entity = entityWearing({ [kBaseMale]: ['male.glb', 'QmMale'] });
    const before = sb.stats();
    const toolsBefore = tools.stats();
    const expectType = (type, fn) => assert.throws(fn, (e) => e instanceof type && !(e instanceof SpringBonesError));
    expectType(TypeError, () => tools.setSpringBoneParams(42, entity, kBaseMale, 'a_springbone', params));
    expectType(TypeError, () => tools.setSpringBoneParams(null, null, kBaseMale, 'a_springbone', params));
    expectType(TypeError, () => tools.setSpringBoneParams(null, entity, 3, 'a_springbone', params));
    expectType(RangeError, () => tools.setSpringBoneParams(null, entity, '', 'a_springbone', params));
    expectType(TypeError, () => tools.setSpringBoneParams(null, entity, kBaseMale, undefined, params));
    expectType(RangeError, () => tools.setSpringBoneParams(null, entity, kBaseMale, '', params));
    expectType(TypeError, () => tools.setSpringBoneParams(null, entity, kBaseMale, 'a_springbone', 'stiff'));
    expectType(TypeError, () => tools.setSpringBoneParams(null, entity, kBaseMale, 'a_springbone', [1]));
    expectType(TypeError, () => tools.setSpringBoneParams(null, entity, kBaseMale, 'a_springbone', undefined));
    expectType(RangeError, () => tools.setSpringBoneParams(null, entity, kBaseMale, 'a_springbone', { ...params, drag: NaN }));
    expectType(RangeError, () => tools.setSpringBoneParams(null, entity, kBaseMale, 'a_springbone', { ...params, gravityDir: [0, Infinity, 0] }));
    const expectCode = (code, fn) => assert.throws(fn, (e) => e instanceof SpringBonesError && e.code === code && e.message.length > 0);
    expectCode('invalid-argument', () => tools.setSpringBoneParams(null, entity, kBaseMale, 'Avatar_Head', params));
    expectCode('invalid-argument', () => tools.setSpringBoneParams(null, entity, kBaseFemale, 'a_springbone', params));
    expectCode('metadata-invalid', () => tools.setSpringBoneParams('[1]', entity, kBaseMale, 'a_springbone', params));
    expectCode('metadata-bad-json', () => tools.setSpringBoneParams('{', entity, kBaseMale, 'a_springbone', params));
    expectCode('entity-bad-json', () => tools.setSpringBoneParams(null, '{', kBaseMale, 'a_springbone', params));
    const deep = '{"a":'.repeat(100000) + '1' + '}'.repeat(100000);
    expectCode('metadata-invalid', () => tools.setSpringBoneParams(deep, entity, kBaseMale, 'a_springbone', params));
    assert.deepEqual(sb.stats(), before);
    assert.deepEqual(tools.stats(), toolsBefore);
    assert.deepEqual(tools.setSpringBoneParams(null, entity, kBaseMale, 'a_springbone', params).models.QmMale, { a_springbone: params });
  });
});
