// tools.validateSpringBones: the catalyst's answer for an entity's data.springBones. Two differential
// checks against @dcl/schemas' SpringBonesData validator (Ajv, a test dependency), run live:
//  - the 940 recorded cases of tests/fixtures/validation_cases.json (also used by the native test),
//    each in a catalyst entity and as a Builder item: our error list equals the recorded catalyst answer, and our accept/reject decision on the
//    schema equals SpringBonesData.validate run now on the same input;
//  - 600 documents generated here from a seed, as JavaScript values (NaN and Infinity included,
//    which JSON cannot carry), in entities where the cross-checks pass: the decision and the
//    error messages equal Ajv's.
import assert from 'node:assert/strict';
import { describe, test } from 'node:test';

import { SpringBonesData } from '@dcl/schemas';

import { createSpringBones, SpringBonesError } from '../../web/springbones.js';
import { seededRandom } from '../../scripts/lib/fixtures/random.mjs';
import { fixture } from './helpers.mjs';

const sb = await createSpringBones();
const tools = await sb.creatorTools();  // validation and the Builder edits

const kBaseMale = 'urn:decentraland:off-chain:base-avatars:BaseMale';

// A cross-check error (models key or bone name) rather than a schema error.
const isCrossCheck = (message) => message.startsWith('springBones.models key ') || message.startsWith('Bone name ');

// The recorded cases write non-finite numbers as {"$nonFinite": "NaN"}; turn them back.
function decodeNonFinite(value) {
  if (Array.isArray(value)) return value.map(decodeNonFinite);
  if (value === null || typeof value !== 'object') return value;
  const keys = Object.keys(value);
  if (keys.length === 1 && keys[0] === '$nonFinite') return Number(value.$nonFinite);
  const out = {};
  for (const key of keys) Object.defineProperty(out, key, { value: decodeNonFinite(value[key]), enumerable: true, writable: true, configurable: true });
  return out;
}

describe('the recorded cases (tests/fixtures/validation_cases.json)', () => {
  const cases = JSON.parse(fixture('validation_cases.json').toString('utf8'));

  test(`${cases.length} cases, as an entity and as a Builder item: the catalyst's errors, in order, and Ajv's decision live`, () => {
    assert.ok(cases.length >= 500);
    let schemaRejected = 0;
    let accepted = 0;
    for (const c of cases) {
      const input = decodeNonFinite(c.input);
      const entity = { content: c.content, metadata: { data: { representations: c.representations, springBones: input } } };
      const item = { contents: c.contents, data: { representations: c.representations, springBones: input } };
      const errors = tools.validateSpringBones(entity);
      // Documented difference (tests/native/validation_test.cpp RejectsFalsyValuesOtherThanNull):
      // the catalyst's rule skips false, 0 and '', but its Wearable schema rejects them first.
      const falsyNotNull = !input && input !== null && input !== undefined;
      assert.deepEqual(errors.map((e) => e.message), falsyNotNull ? ['springBones must be object'] : c.catalystErrors, c.name);
      // The Builder item form of the same wearable: the catalyst's answer once deployed, path for path.
      const itemErrors = tools.validateSpringBones(item);
      assert.deepEqual(itemErrors.map((e) => e.message), falsyNotNull ? ['springBones must be object'] : c.itemCatalystErrors, `${c.name} (item)`);
      assert.deepEqual(itemErrors, errors, `${c.name} (item)`);
      for (const e of errors) {
        assert.equal(typeof e.path, 'string', c.name);
        assert.ok(e.path === '' || e.path.startsWith('/'), `${c.name}: ${e.path}`);
      }
      // Absent or null springBones is not checked at all.
      if (input !== null && input !== undefined) {
        const ajvValid = SpringBonesData.validate(input);
        const oursValid = !errors.some((e) => !isCrossCheck(e.message));
        assert.equal(oursValid, ajvValid, c.name);
        if (!ajvValid) ++schemaRejected;
      }
      if (errors.length === 0) ++accepted;
    }
    // Both outcomes are well represented, so the comparison means something.
    assert.ok(schemaRejected > 200 && accepted > 100, `${schemaRejected} rejected, ${accepted} accepted`);
  });
});

// ---------------------------------------------------------------------------------------------
// Generated here

function generator(seed) {
  const random = seededRandom(seed);
  const int = (lo, hi) => lo + Math.floor(random() * (hi - lo + 1));
  const pick = (list) => list[Math.floor(random() * list.length)];
  const chance = (p) => random() < p;
  const inRange = (min, max) => pick([min, max, min + random() * (max - min), Math.round(min + random() * (max - min))]);
  const params = () => {
    const p = { drag: inRange(0, 1), stiffness: inRange(0, 4), gravityDir: [inRange(-10, 10), inRange(-10, 10), inRange(-10, 10)], gravityPower: inRange(0, 2) };
    if (chance(0.3)) p.center = pick(['Avatar_Hips', null, '']);
    if (chance(0.3)) p.isRoot = pick([true, false, null]);
    if (chance(0.1)) p.hitRadius = 0.02;  // unknown keys are allowed in a bone entry
    return p;
  };
  // No undefined: JSON (what a catalyst receives) has none, and the API drops such members as
  // JSON.stringify does, while Ajv on a live object counts the key as present.
  const kBad = [NaN, Infinity, -Infinity, -1, 4.0001, 2.5, 11, -10.5, '1', '', null, true, [], [0, -1, 0], {}];
  const kFields = ['stiffness', 'gravityPower', 'drag', 'gravityDir', 'center', 'isRoot'];
  const faults = [
    (d) => { d.version = pick([0, 2, 1.5, '1', null, NaN, Infinity, true, []]); },
    (d) => { delete d.version; },
    (d) => { delete d.models; },
    (d) => { d[pick(['extra', 'Version', 'colliders'])] = pick(kBad); },
    (d) => { d.models = pick([null, [], 'x', 3, NaN]); },
    (d, h) => { d.models[h] = pick([null, [], 'x', 3, -Infinity]); },
    (d, h, b) => { d.models[h][b] = pick([null, [], 'x', 3, NaN, {}]); },
    (d, h, b) => { d.models[h][b][pick(kFields)] = pick(kBad); },
    (d, h, b) => { delete d.models[h][b][pick(['stiffness', 'gravityPower', 'drag', 'gravityDir'])]; },
    (d, h, b) => { d.models[h][b].gravityDir = Array.from({ length: int(0, 5) }, () => (chance(0.6) ? inRange(-12, 12) : pick(kBad))); },
    (d, h, b) => { d.models[h][b][pick(['stiffness', 'gravityPower', 'drag'])] = inRange(-0.5, 4.5); },
  ];
  return () => {
    const models = {};
    for (let h = 0; h < int(0, 3); ++h) {
      const bones = {};
      for (let b = 0; b < int(0, 3); ++b) bones[`${pick(['Hair', 'Tail', 'Ear'])}_springbone_${b}`] = params();
      models[`Qm${h}`] = bones;
    }
    const doc = { version: 1, models };
    for (let f = int(0, 3); f > 0; --f) {
      const hashes = doc.models && typeof doc.models === 'object' && !Array.isArray(doc.models) ? Object.keys(doc.models) : [];
      const h = hashes.length ? pick(hashes) : undefined;
      const model = h === undefined ? undefined : doc.models[h];
      const bones = model && typeof model === 'object' && !Array.isArray(model) ? Object.keys(model) : [];
      const b = bones.length ? pick(bones) : undefined;
      const bone = b === undefined ? undefined : model[b];
      const boneIsObject = bone && typeof bone === 'object' && !Array.isArray(bone);
      const which = int(0, faults.length - 1);
      if (which === 5 && h === undefined) continue;
      if (which === 6 && b === undefined) continue;
      if (which >= 7 && !boneIsObject) continue;
      faults[which](doc, h, b);
    }
    return doc;
  };
}

// Every models key is the main file of a representation, so the cross-checks pass and only the
// schema decides.
function entityCovering(springBones) {
  const models = springBones?.models;
  const keys = models && typeof models === 'object' && !Array.isArray(models) ? Object.keys(models) : [];
  const content = keys.map((hash, i) => ({ file: `m${i}.glb`, hash }));
  const representations = keys.map((_, i) => ({ bodyShapes: [kBaseMale], mainFile: `m${i}.glb`, contents: [`m${i}.glb`] }));
  return { content, metadata: { data: { representations, springBones } } };
}

describe('documents generated as JavaScript values', () => {
  test('600 documents: accept/reject and the messages equal SpringBonesData.validate', () => {
    const next = generator(0x51bb0e5);
    let rejected = 0;
    let nonFinite = 0;
    for (let i = 0; i < 600; ++i) {
      const doc = next();
      const ajvValid = SpringBonesData.validate(doc);
      const expected = (SpringBonesData.validate.errors ?? []).map((e) => `springBones${e.instancePath} ${e.message}`);
      const errors = tools.validateSpringBones(entityCovering(doc));
      const label = `case ${i}: ${JSON.stringify(doc, (_k, v) => (typeof v === 'number' && !Number.isFinite(v) ? String(v) : v))}`;
      assert.equal(errors.length === 0, ajvValid, label);
      // Ajv orders some errors by the schema, we by the data's keys: compare as multisets.
      assert.deepEqual(errors.map((e) => e.message).sort(), expected.sort(), label);
      if (!ajvValid) ++rejected;
      if (/NaN|Infinity/.test(label)) ++nonFinite;
    }
    assert.ok(rejected > 250 && rejected < 550, `${rejected} of 600 rejected`);
    assert.ok(nonFinite > 30, `${nonFinite} documents hold non-finite numbers`);
  });
});

describe('the entity and the API', () => {
  const springBones = {
    version: 1,
    models: { Qm1: { Hair_springbone: { stiffness: 1, gravityPower: 0, gravityDir: [0, -1, 0], drag: 0.5 } } },
  };

  test('absent or null springBones is valid', () => {
    for (const value of [undefined, null]) {
      const entity = entityCovering(springBones);
      entity.metadata.data.springBones = value;
      assert.deepEqual(tools.validateSpringBones(entity), []);
    }
  });

  test('errors carry a JSON path into springBones', () => {
    const bad = structuredClone(springBones);
    bad.models.Qm1.Hair_springbone.drag = 2;
    bad.models.Qm1['a/b~c'] = { stiffness: NaN, gravityPower: 0, gravityDir: [0, -1, 0], drag: 0.5 };
    const errors = tools.validateSpringBones(entityCovering(bad));
    assert.deepEqual(errors, [
      { path: '/models/Qm1/Hair_springbone/drag', message: 'springBones/models/Qm1/Hair_springbone/drag must be <= 1' },
      { path: '/models/Qm1/a~1b~0c/stiffness', message: 'springBones/models/Qm1/a~1b~0c/stiffness must be number' },
    ]);
  });

  test('a stale models key and a bone without the token are the cross-check errors', () => {
    const entity = entityCovering(springBones);
    entity.metadata.data.springBones = {
      version: 1,
      models: { Qm1: springBones.models.Qm1, QmStale: { Hair_001: springBones.models.Qm1.Hair_springbone } },
    };
    const errors = tools.validateSpringBones(entity);
    assert.deepEqual(errors.map((e) => e.path), ['/models/QmStale', '/models/QmStale/Hair_001']);
    assert.ok(errors.every((e) => isCrossCheck(e.message)));
  });

  test('entity as JSON text gives the same answer', () => {
    const bad = structuredClone(springBones);
    bad.version = 2;
    const entity = entityCovering(bad);
    assert.deepEqual(tools.validateSpringBones(JSON.stringify(entity)), tools.validateSpringBones(entity));
    assert.equal(tools.validateSpringBones(entity).length, 1);
  });

  test('a string that looks like the non-finite marker stays a string', () => {
    const entity = entityCovering(structuredClone(springBones));
    entity.metadata.data.springBones.models.Qm1.Hair_springbone.center = '\u0000springbones-non-finite-x:NaN';
    assert.deepEqual(tools.validateSpringBones(entity), []);
  });

  test('a Builder item ({contents, data}) is validated as its entity is', () => {
    const item = { contents: { 'm.glb': 'Qm1' }, data: { representations: [{ bodyShapes: [kBaseMale], mainFile: 'm.glb' }], springBones } };
    assert.deepEqual(tools.validateSpringBones(item), []);
    // The case: stiffness 9 inside an item was answered [] (the item was never read).
    const bad = structuredClone(item);
    bad.data.springBones.models.Qm1.Hair_springbone.stiffness = 9;
    const errors = tools.validateSpringBones(bad);
    assert.deepEqual(errors, [{ path: '/models/Qm1/Hair_springbone/stiffness', message: 'springBones/models/Qm1/Hair_springbone/stiffness must be <= 4' }]);
    const entity = { content: [{ file: 'm.glb', hash: 'Qm1' }], metadata: { data: bad.data } };
    assert.deepEqual(tools.validateSpringBones(entity), errors);
    assert.deepEqual(tools.validateSpringBones(JSON.stringify(bad)), errors);
  });

  test('anything that is neither an entity nor a Builder item is invalid-argument, never []', () => {
    const before = tools.stats();
    for (const subject of [{}, [], { metadata: {} }, { metadata: { data: null } }, { data: { springBones } },
                           { contents: {}, data: 'x' }, springBones, '{}', '[1]', '42', '"entity"']) {
      assert.throws(() => tools.validateSpringBones(subject), (e) => e instanceof SpringBonesError && e.code === 'invalid-argument' &&
                    e.message.includes('catalyst entity') && e.message.includes('Builder item'), JSON.stringify(subject));
    }
    assert.deepEqual(tools.validateSpringBones(entityCovering(springBones)), []);
    assert.equal(tools.stats().heapInUse, before.heapInUse);
  });

  test('wrong argument types are TypeErrors; bad JSON text is entity-bad-json; the module keeps working', () => {
    const before = tools.stats();
    for (const bad of [undefined, null, 42, true, Symbol('x')]) assert.throws(() => tools.validateSpringBones(bad), TypeError);
    assert.throws(() => tools.validateSpringBones('{"content": ['),
                  (e) => e instanceof SpringBonesError && e.code === 'entity-bad-json' && e.message.length > 0);
    const deep = '['.repeat(100000) + ']'.repeat(100000);
    assert.ok(Array.isArray(tools.validateSpringBones(`{"metadata":{"data":{"springBones":${deep}}}}`)));
    assert.deepEqual(tools.validateSpringBones(entityCovering(springBones)), []);
    assert.equal(tools.stats().heapInUse, before.heapInUse);
  });
});
