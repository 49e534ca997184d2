// Entities, springBones and params of every odd shape through validateSpringBones,
// detectSpringBones, setSpringBoneParams and loadRig's entity lookup: each call returns or throws
// a SpringBonesError (TypeError/RangeError for bad argument types), never anything else; the
// module keeps working and no memory or handle is left behind.
import assert from 'node:assert/strict';
import { test } from 'node:test';

import { createSpringBones, SpringBonesError } from '../../web/springbones.js';
import { seededRandom } from '../../scripts/lib/fixtures/random.mjs';
import { springRig } from './helpers.mjs';

const sb = await createSpringBones();
const tools = await sb.creatorTools();  // validation and the Builder edits

const random = seededRandom(0xbadc0de);
const pick = (list) => list[Math.floor(random() * list.length)];

// A value of a random shape, `depth` levels at most, biased towards the keys entities use.
const kKeys = ['content', 'contents', 'metadata', 'data', 'representations', 'springBones', 'models', 'version',
  'file', 'hash', 'mainFile', 'bodyShapes', 'stiffness', 'gravityDir', 'a_springbone', 'BaseMale', '', '/~'];
function value(depth) {
  const kind = depth <= 0 ? Math.floor(random() * 6) : Math.floor(random() * 8);
  switch (kind) {
    case 0: return null;
    case 1: return pick([true, false]);
    case 2: return pick([0, -1, 1.5, 1e308, -0, NaN, Infinity, 2 ** 53]);
    case 3: return pick(['', 'a.glb', 'QmA', 'urn:decentraland:off-chain:base-avatars:BaseMale', 'BaseMale', 'x'.repeat(300), '\u0000']);
    case 4: return pick(['a_springbone', 'Hair_SpringBone', 'plain']);
    case 5: return undefined;
    case 6: return Array.from({ length: Math.floor(random() * 4) }, () => value(depth - 1));
    default: {
      const out = {};
      for (let i = Math.floor(random() * 5); i > 0; --i) out[pick(kKeys)] = value(depth - 1);
      return out;
    }
  }
}

// Mostly well-formed entities with one part replaced by something random.
function entity() {
  const e = {
    content: [{ file: 'a.glb', hash: 'QmA' }, { file: 'b.glb', hash: 'QmB' }],
    metadata: { data: { representations: [{ bodyShapes: ['urn:decentraland:off-chain:base-avatars:BaseMale'], mainFile: 'a.glb' }],
      springBones: { version: 1, models: { QmA: { a_springbone: { stiffness: 1, gravityPower: 0, gravityDir: [0, -1, 0], drag: 0.5 } } } } } },
  };
  const targets = [
    () => { e.content = value(3); }, () => { e.content[0] = value(2); }, () => { e.metadata = value(3); },
    () => { e.metadata.data = value(3); }, () => { e.metadata.data.representations = value(3); },
    () => { e.metadata.data.representations[0] = value(2); }, () => { e.metadata.data.representations[0].bodyShapes = value(2); },
    () => { e.metadata.data.springBones = value(4); }, () => { e.metadata.data.springBones.models = value(3); },
    () => { e.metadata.data.springBones.models.QmA = value(3); }, () => { e[pick(kKeys)] = value(3); },
  ];
  for (let n = 1 + Math.floor(random() * 2); n > 0; --n) {
    try {
      pick(targets)();
    } catch {
      // an earlier replacement removed the part this one edits: keep what there is
    }
  }
  return e;
}

function expectReturnsOrSpringBonesError(fn, label) {
  try {
    return fn();
  } catch (error) {
    assert.ok(error instanceof SpringBonesError || error instanceof TypeError || error instanceof RangeError, `${label}: ${error}`);
    if (error instanceof SpringBonesError) {
      assert.equal(typeof error.code, 'string');
      assert.ok(error.message.length > 0);
    }
    return undefined;
  }
}

test('2,000 odd entities and edits: results or SpringBonesErrors, nothing leaks, the module keeps working', () => {
  const { glb, springBones } = springRig({ hash: 'QmA' });
  const cycle = (i) => {
    const e = entity();
    const errors = expectReturnsOrSpringBonesError(() => tools.validateSpringBones(e), `validate ${i}`);
    if (errors !== undefined) {
      assert.ok(Array.isArray(errors));
      for (const x of errors) assert.ok(typeof x.path === 'string' && typeof x.message === 'string' && x.message.length > 0);
    }
    const shape = pick(['BaseMale', 'urn:decentraland:off-chain:base-avatars:BaseFemale', 'x']);
    const out = expectReturnsOrSpringBonesError(
      () => tools.setSpringBoneParams(value(3), e, shape, pick(['a_springbone', 'b_SpringBone', 'plain']), pick([null, {}, value(2)])), `set ${i}`);
    if (out !== undefined) assert.equal(out.version, 1);
    expectReturnsOrSpringBonesError(() => tools.detectSpringBones(glb, value(4), pick([undefined, { entity: e, bodyShape: shape }])), `detect ${i}`);
    const rig = expectReturnsOrSpringBonesError(() => sb.loadRig(glb, springBones, { entity: e, bodyShape: shape }), `load ${i}`);
    rig?.dispose();
  };
  for (let i = 0; i < 50; ++i) cycle(i);
  const before = sb.stats();
  const toolsBefore = tools.stats();
  for (let i = 50; i < 2000; ++i) cycle(i);
  assert.deepEqual(sb.stats(), before);
  assert.deepEqual(tools.stats(), toolsBefore);
  const rig = sb.loadRig(glb, springBones, { contentHash: 'QmA' });
  assert.equal(rig.joints.length, 3);
  rig.dispose();
});
