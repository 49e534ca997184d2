// Every way loading can fail: one test per class of bad input, each checking the error's type and
// code, that nothing leaked across the boundary, and that a valid load right after succeeds.
import assert from 'node:assert/strict';
import { before, describe, test } from 'node:test';

import { createSpringBones, SpringBonesError } from '../../web/springbones.js';
import { glbOfDoc, glbOfJson, gltfBytes } from '../../scripts/lib/fixtures/glb.mjs';
import { fixture, loadFixtureRig, springRig } from './helpers.mjs';

let sb;
before(async () => {
  sb = await createSpringBones();
});

const valid = springRig({ chains: 2 });
const kDoc = valid.doc;

// A GLB of `json` (the valid rig by default) with the header fields given overwritten.
function glbWith({ magic, version, declared, chunkLength, chunkType, json = JSON.stringify(kDoc) }) {
  const out = glbOfJson(json);
  const view = new DataView(out.buffer);
  const fields = [[0, magic], [4, version], [8, declared], [12, chunkLength], [16, chunkType]];
  for (const [offset, value] of fields) if (value !== undefined) view.setUint32(offset, value, true);
  return out;
}

// Loads bad input, expects a SpringBonesError with `code`, then checks the module still loads and
// steps a valid rig and that the failure left no handle and no memory behind.
function expectLoadError(code, glb, springBones = valid.springBones, options = { contentHash: valid.hash }) {
  const before = sb.stats();
  assert.throws(() => sb.loadRig(glb, springBones, options), (e) => {
    assert.ok(e instanceof SpringBonesError, `${e}`);
    assert.ok(e instanceof Error);
    assert.equal(e.name, 'SpringBonesError');
    assert.equal(e.code, code, e.message);
    assert.equal(typeof e.message, 'string');
    assert.ok(e.message.length > 0);
    assert.equal(typeof e.path, 'string');
    return true;
  });
  const after = sb.stats();
  assert.equal(after.rigs, before.rigs);
  assert.equal(after.heapInUse, before.heapInUse, 'a failed load frees everything it allocated');
  expectStillWorking();
}

function expectStillWorking() {
  const rig = sb.loadRig(valid.glb, valid.springBones, { contentHash: valid.hash });
  const inst = rig.createInstance();
  inst.driverMatrices[12] += 0.1;
  inst.step(1 / 60);
  assert.equal(rig.joints.length, 6);
  assert.ok(inst.rotations.every(Number.isFinite));
  inst.dispose();
  rig.dispose();
}

describe('bad GLB bytes: SpringBonesError with the core\'s code', () => {
  before(() => expectStillWorking());  // warms up one-time allocations before heap comparisons

  test('empty input is glb-truncated', () => expectLoadError('glb-truncated', new Uint8Array(0)));
  test('three bytes are glb-truncated', () => expectLoadError('glb-truncated', new Uint8Array([0x67, 0x6c, 0x54])));
  test('a PNG is glb-bad-magic', () => expectLoadError('glb-bad-magic', new Uint8Array([0x89, 0x50, 0x4e, 0x47, 13, 10, 26, 10])));
  test('a GLB header alone is glb-truncated', () => expectLoadError('glb-truncated', glbWith({}).subarray(0, 12)));
  test('a GLB declaring more bytes than it has is glb-truncated', () => expectLoadError('glb-truncated', glbWith({ declared: 1 << 20 })));
  test('a JSON chunk longer than the file is glb-truncated', () => expectLoadError('glb-truncated', glbWith({ chunkLength: 1 << 20 })));
  test('GLB version 1 is glb-bad-chunk', () => expectLoadError('glb-bad-chunk', glbWith({ version: 1 })));
  test('a first chunk that is not JSON is glb-bad-chunk', () => expectLoadError('glb-bad-chunk', glbWith({ chunkType: 0x004e4942 })));
  test('a JSON chunk that does not parse is gltf-bad-json', () => expectLoadError('gltf-bad-json', glbWith({ json: '{"asset": {"version": "2.0"}, "nodes": [' })));
  test('glTF text that does not parse is gltf-bad-json', () => expectLoadError('gltf-bad-json', new TextEncoder().encode('{"asset": ')));
  test('glTF without asset.version is gltf-invalid', () => expectLoadError('gltf-invalid', gltfBytes({ nodes: [{ name: 'a' }] })));
  test('nodes that are not an array are gltf-invalid', () => expectLoadError('gltf-invalid', gltfBytes({ asset: { version: '2.0' }, nodes: {} })));
  test('a translation of two numbers is gltf-invalid', () => expectLoadError('gltf-invalid', gltfBytes({ asset: { version: '2.0' }, nodes: [{ translation: [0, 1] }] })));
  test('a child index past the end is gltf-invalid', () => expectLoadError('gltf-invalid', glbOfDoc({ asset: { version: '2.0' }, nodes: [{ children: [5] }] })));
  test('a cycle is hierarchy-cycle', () => expectLoadError('hierarchy-cycle', fixture('cycle.gltf')));
  test('a node with two parents is hierarchy-multiple-parents', () => expectLoadError('hierarchy-multiple-parents', fixture('two_parents.gltf')));
});

describe('bad springBones: SpringBonesError with a JSON path where there is one', () => {
  test('JSON text that does not parse is metadata-bad-json', () => expectLoadError('metadata-bad-json', valid.glb, '{"version": 1, models: }'));
  test('empty text is metadata-bad-json', () => expectLoadError('metadata-bad-json', valid.glb, ''));
  test('a number (as JSON text) is metadata-invalid', () => expectLoadError('metadata-invalid', valid.glb, '42'));
  test('an array is metadata-invalid', () => expectLoadError('metadata-invalid', valid.glb, []));
  test('models that is not an object is metadata-invalid at /models', () => {
    assert.throws(() => sb.loadRig(valid.glb, { version: 1, models: [1] }), (e) => e.code === 'metadata-invalid' && e.path === '/models');
    expectLoadError('metadata-invalid', valid.glb, { version: 1, models: 'x' });
  });
  test('models[hash] that is not an object is metadata-invalid at its path', () => {
    assert.throws(() => sb.loadRig(valid.glb, { version: 1, models: { h: 3 } }, { contentHash: 'h' }),
                  (e) => e.code === 'metadata-invalid' && e.path === '/models/h');
  });
});

describe('bad entity: SpringBonesError from the hash lookup', () => {
  const entity = {
    content: [{ file: 'a.glb', hash: 'hash-a' }],
    metadata: { data: { representations: [{ bodyShapes: ['urn:decentraland:off-chain:base-avatars:BaseMale'], mainFile: 'a.glb' }] } },
  };
  test('an unknown body shape is invalid-argument with a path into the entity', () => {
    assert.throws(() => sb.loadRig(valid.glb, valid.springBones, { entity, bodyShape: 'BaseFemale' }),
                  (e) => e instanceof SpringBonesError && e.code === 'invalid-argument' && e.path.startsWith('/metadata'));
    expectStillWorking();
  });
  test('a main file missing from content is invalid-argument', () => {
    const broken = { ...entity, content: [] };
    expectLoadError('invalid-argument', valid.glb, valid.springBones, { entity: broken, bodyShape: 'BaseMale' });
  });
  test('entity JSON text that does not parse is entity-bad-json', () => {
    expectLoadError('entity-bad-json', valid.glb, valid.springBones, { entity: '{"content": [', bodyShape: 'BaseMale' });
  });
});

describe('wrong argument types and values: TypeError / RangeError before crossing into WASM', () => {
  function expectThrowsBeforeCrossing(fn, type) {
    const before = sb.stats();
    assert.throws(fn, (e) => e instanceof type && !(e instanceof SpringBonesError));
    assert.deepEqual(sb.stats(), before);
  }

  test('glbBytes must be a Uint8Array or an ArrayBuffer', () => {
    for (const bad of [undefined, null, 'glTF', 42, [0x67, 0x6c], new Float32Array(4), new DataView(new ArrayBuffer(4)), {}]) {
      expectThrowsBeforeCrossing(() => sb.loadRig(bad, null), TypeError);
    }
  });

  test('springBones must be an object, JSON text, null or undefined', () => {
    for (const bad of [42, true, 1n, Symbol('x')]) {
      expectThrowsBeforeCrossing(() => sb.loadRig(valid.glb, bad), TypeError);
    }
    const cyclic = {};
    cyclic.self = cyclic;
    expectThrowsBeforeCrossing(() => sb.loadRig(valid.glb, cyclic), TypeError);
  });

  test('load options are checked', () => {
    const { glb, springBones } = valid;
    expectThrowsBeforeCrossing(() => sb.loadRig(glb, springBones, 'hash'), TypeError);
    expectThrowsBeforeCrossing(() => sb.loadRig(glb, springBones, { contentHash: 5 }), TypeError);
    expectThrowsBeforeCrossing(() => sb.loadRig(glb, springBones, { contentHash: '' }), RangeError);
    expectThrowsBeforeCrossing(() => sb.loadRig(glb, springBones, { hash: 'typo' }), TypeError);
    expectThrowsBeforeCrossing(() => sb.loadRig(glb, springBones, { bodyShape: 'BaseMale' }), TypeError);
    expectThrowsBeforeCrossing(() => sb.loadRig(glb, springBones, { entity: {} }), TypeError);
    expectThrowsBeforeCrossing(() => sb.loadRig(glb, springBones, { entity: {}, bodyShape: 3 }), TypeError);
    expectThrowsBeforeCrossing(() => sb.loadRig(glb, springBones, { entity: {}, bodyShape: '' }), RangeError);
    expectThrowsBeforeCrossing(() => sb.loadRig(glb, springBones, { entity: 12, bodyShape: 'BaseMale' }), TypeError);
    expectThrowsBeforeCrossing(() => sb.contentHash('text'), TypeError);
  });

  test('instance options are checked', () => {
    const rig = loadFixtureRig(sb, 'avatar_hair.glb');
    for (const [options, type] of [
      ['60', TypeError], [{ stepHz: '60' }, TypeError], [{ stepHz: 0 }, RangeError], [{ stepHz: 1001 }, RangeError],
      [{ stepHz: NaN }, RangeError], [{ stepHz: Infinity }, RangeError], [{ maxSubsteps: 0 }, RangeError],
      [{ maxSubsteps: 65 }, RangeError], [{ maxSubsteps: 2.5 }, RangeError], [{ maxSubsteps: '4' }, TypeError],
      [{ integrator: 'pbd' }, RangeError], [{ integrator: 1 }, TypeError], [{ stepHZ: 30 }, TypeError],
      [{ xpbdIterations: 4 }, RangeError], [{ integrator: 'xpbd', xpbdIterations: 0 }, RangeError],
      [{ integrator: 'xpbd', xpbdIterations: 65 }, RangeError], [{ integrator: 'xpbd', xpbdIterations: 1.5 }, RangeError],
      [{ integrator: 'xpbd', xpbdIterations: '4' }, TypeError],
    ]) {
      expectThrowsBeforeCrossing(() => rig.createInstance(options), type);
    }
    for (const ok of [undefined, null, {}, { stepHz: 1 }, { stepHz: 1000, maxSubsteps: 64 }, { maxSubsteps: 1 },
                      { integrator: 'vrm' }, { integrator: 'xpbd' }, { integrator: 'xpbd', xpbdIterations: 64, stepHz: 240 }]) {
      rig.createInstance(ok).dispose();
    }
    rig.dispose();
  });

  test('step(dt): dt must be a finite number', () => {
    const rig = loadFixtureRig(sb, 'avatar_hair.glb');
    const inst = rig.createInstance();
    inst.step(1 / 60);
    const rotations = Float32Array.from(inst.rotations);
    for (const bad of ['0.016', undefined, null, 1n, {}]) assert.throws(() => inst.step(bad), TypeError);
    for (const bad of [NaN, Infinity, -Infinity]) assert.throws(() => inst.step(bad), RangeError);
    assert.deepEqual(inst.rotations, rotations);
    inst.step(1 / 60);  // still steps
    inst.dispose();
    rig.dispose();
  });
});

test('a long sequence of failures of every kind leaves the module working and nothing allocated', () => {
  const rig0 = loadFixtureRig(sb, 'avatar_hair.glb');
  rig0.dispose();
  const before = sb.stats();
  const bad = [
    () => sb.loadRig(new Uint8Array(0), null),
    () => sb.loadRig(fixture('cycle.gltf'), null),
    () => sb.loadRig(valid.glb, '{'),
    () => sb.loadRig(valid.glb, '"x"'),
    () => sb.loadRig(valid.glb, valid.springBones, { entity: '[', bodyShape: 'x' }),
    () => sb.loadRig(42),
    () => sb.loadRig(valid.glb, null, { contentHash: '' }),
  ];
  for (let round = 0; round < 50; ++round) {
    for (const fn of bad) assert.throws(fn);
  }
  assert.deepEqual(sb.stats(), before);
  const rig = loadFixtureRig(sb, 'avatar_hair.glb');
  assert.ok(rig.joints.length > 10);
  rig.dispose();
});
