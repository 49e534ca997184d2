// Hostile input through the JavaScript API, the same named cases as
// tests/native/hostile_input_test.cpp: each ends in a SpringBonesError with the core's code, or in
// a documented clamp with a warning; rotations are always finite unit quaternions; nothing traps
// (the WebAssembly stack is far smaller than a native one) and nothing leaks.
import assert from 'node:assert/strict';
import { describe, test } from 'node:test';

import { createSpringBones, SpringBonesError } from '../../web/springbones.js';
import { glbOfDoc, glbOfJson, gltfBytes } from '../../scripts/lib/fixtures/glb.mjs';
import { fixture } from './helpers.mjs';

const sb = await createSpringBones();
const tools = await sb.creatorTools();  // validation and the Builder edits

const kHash = 'bafkreihostile';
const encoder = new TextEncoder();

// The wearable of the native test: Avatar_Head driving a hair chain of two joints and an earring.
const hairDoc = {
  asset: { version: '2.0' },
  nodes: [
    { name: 'Avatar_Head', children: [1, 4], translation: [0, 1.6, 0] },
    { name: 'SpringBone_hair', children: [2], translation: [0.1, 0, 0] },
    { name: 'SpringBone_hair_1', children: [3], translation: [0, -0.1, 0] },
    { name: 'SpringBone_hair_tip', translation: [0, -0.1, 0] },
    { name: 'SpringBone_earring', children: [5], translation: [-0.1, 0, 0] },
    { name: 'SpringBone_earring_tip', translation: [0, -0.05, 0.01] },
  ],
};
const hairGlb = glbOfDoc(hairDoc);

function entry(stiffness, gravityPower, gravityDir, drag) {
  return { stiffness, gravityPower, gravityDir, drag, isRoot: true };
}

// [[[...1]]], `levels` arrays deep.
function deepArrays(levels) {
  let value = 1;
  for (let i = 0; i < levels; ++i) value = [value];
  return value;
}

function hairMetadata(hairEntry) {
  return {
    version: 1,
    models: { [kHash]: { SpringBone_hair: hairEntry, SpringBone_earring: entry(1, 1, [0, -1, 0], 0.4) } },
  };
}

function expectCode(code, fn) {
  const before = sb.stats();
  const toolsBefore = tools.stats();
  assert.throws(fn, (e) => {
    assert.ok(e instanceof SpringBonesError, `${e}`);
    assert.equal(e.code, code, e.message);
    assert.ok(e.message.length > 0);
    return true;
  });
  const after = sb.stats();
  assert.equal(after.rigs, before.rigs);
  assert.equal(after.heapInUse, before.heapInUse, 'a failed load frees everything it allocated');
  assert.equal(tools.stats().heapInUse, toolsBefore.heapInUse, 'a failed edit frees everything it allocated');
}

function assertFiniteUnit(rotations, when = '') {
  for (let j = 0; j < rotations.length; j += 4) {
    const [x, y, z, w] = rotations.subarray(j, j + 4);
    assert.ok([x, y, z, w].every(Number.isFinite), `joint ${j / 4} has a non-finite rotation ${when}`);
    assert.ok(Math.abs(Math.hypot(x, y, z, w) - 1) < 1e-4, `joint ${j / 4} is not unit ${when}`);
  }
}

function stepAndCheck(inst, frames = 10, dt = 1 / 60) {
  assertFiniteUnit(inst.rotations, 'before stepping');
  for (let i = 0; i < frames; ++i) {
    inst.step(dt);
    assertFiniteUnit(inst.rotations, `after frame ${i}`);
  }
}

function withRig(glb, springBones, fn) {
  const rig = sb.loadRig(glb, springBones, { contentHash: kHash });
  const inst = rig.createInstance();
  try {
    fn(rig, inst);
  } finally {
    inst.dispose();
    rig.dispose();
  }
}

// One chain of `depth` spring bones under Avatar_Hips, 1 cm apart, as glTF JSON text.
function deepChainText(depth, extras = '') {
  const parts = ['{"asset":{"version":"2.0"},"nodes":[{"name":"Avatar_Hips","children":[1]}'];
  for (let i = 1; i <= depth; ++i) {
    let node = `,{"name":"springbone_${i}","translation":[0,-0.01,0]`;
    if (i < depth) node += `,"children":[${i + 1}]`;
    if (extras) node += `,"extras":${extras}`;
    parts.push(`${node}}`);
  }
  parts.push(']}');
  return parts.join('');
}

describe('the GLB container', () => {
  test('a GLB header truncated at every length below 20 bytes is glb-truncated', () => {
    const glb = fixture('adr_example.glb');
    for (let size = 0; size < 20; ++size) {
      expectCode('glb-truncated', () => sb.loadRig(glb.subarray(0, size), null));
    }
  });

  test('oversized GLB lengths up to 0xFFFFFFFF are glb-truncated, never a read past the bytes', () => {
    for (const offset of [8, 12]) {
      for (const length of [fixture('adr_example.glb').length + 1, 0x7fffffff, 0xffffffff]) {
        const glb = new Uint8Array(fixture('adr_example.glb'));
        new DataView(glb.buffer).setUint32(offset, length, true);
        expectCode('glb-truncated', () => sb.loadRig(glb, null));
      }
    }
  });

  test('a wrong magic is glb-bad-magic', () => {
    const glb = new Uint8Array(fixture('adr_example.glb'));
    glb[0] = 0x78;
    expectCode('glb-bad-magic', () => sb.loadRig(glb, null));
  });

  test('a JSON chunk that is not JSON is gltf-bad-json', () => {
    for (const text of ['{not json at all', '{"asset":{"version":"2.0"},"nodes":[', '{"a":"\u0000"}', '{}}']) {
      expectCode('gltf-bad-json', () => sb.loadRig(glbOfJson(text), null));
    }
    expectCode('gltf-bad-json', () => sb.loadRig(glbOfJson(Uint8Array.from({ length: 256 }, (_, i) => i)), null));
  });

  test('a glTF JSON chunk of 64 MiB loads, one byte more is limit-exceeded', () => {
    const head = '{"asset":{"version":"2.0"},"nodes":[{"name":"a"}]}';
    const atLimit = encoder.encode(head + ' '.repeat((64 << 20) - head.length));
    const rig = sb.loadRig(atLimit, null);
    assert.equal(rig.nodeCount, 1);
    rig.dispose();
    const over = new Uint8Array(atLimit.length + 1).fill(0x20);
    over.set(atLimit);
    assert.throws(() => sb.loadRig(over, null), (e) => {
      assert.ok(e instanceof SpringBonesError, `${e}`);
      assert.equal(e.code, 'limit-exceeded');
      assert.match(e.message, /67108865 bytes.*67108864/);
      return true;
    });
    assert.equal(sb.stats().rigs, 0);
  });
});

describe('the hierarchy', () => {
  test('a node that is its own ancestor is hierarchy-cycle', () => {
    expectCode('hierarchy-cycle', () => sb.loadRig(fixture('cycle.gltf'), null));
    const self = { asset: { version: '2.0' }, nodes: [{ name: 'springbone_a', children: [0] }] };
    expectCode('hierarchy-cycle', () => sb.loadRig(gltfBytes(self), null));
    // A three-node loop that no root leads to, next to a healthy root.
    const loop = { asset: { version: '2.0' }, nodes: [{ name: 'root' }, { name: 'a', children: [2] }, { name: 'b', children: [3] }, { name: 'c', children: [1] }] };
    expectCode('hierarchy-cycle', () => sb.loadRig(gltfBytes(loop), null));
    assert.throws(() => sb.loadRig(gltfBytes(loop), null), /ancestor/);
  });

  test('a node with two parents is hierarchy-multiple-parents', () => {
    expectCode('hierarchy-multiple-parents', () => sb.loadRig(fixture('two_parents.gltf'), null));
    const twice = { asset: { version: '2.0' }, nodes: [{ name: 'p', children: [1, 1] }, { name: 'c' }] };
    expectCode('hierarchy-multiple-parents', () => sb.loadRig(gltfBytes(twice), null));
  });

  test('100,000 nodes load, and one more than the limit of 262,144 is limit-exceeded', () => {
    const nodes = [{ name: 'Avatar_Hips', children: Array.from({ length: 99999 }, (_, i) => i + 1) }];
    for (let i = 1; i < 100000; ++i) nodes.push({ name: `springbone_${i}` });
    withRig(glbOfDoc({ asset: { version: '2.0' }, nodes }), hairMetadata(entry(1, 1, [0, -1, 0], 0.5)), (rig, inst) => {
      assert.equal(rig.nodeCount, 100000);
      stepAndCheck(inst, 2);
    });
    const over = `{"asset":{"version":"2.0"},"nodes":[${Array(262145).fill('{}').join(',')}]}`;
    expectCode('limit-exceeded', () => sb.loadRig(encoder.encode(over), null));
  });

  test('a 10,000-deep hierarchy loads, steps and disposes without recursion', () => {
    const springBones = { version: 1, models: { [kHash]: { springbone_1: entry(0.5, 2, [1, 0, 0], 0.1) } } };
    withRig(encoder.encode(deepChainText(10000)), springBones, (rig, inst) => {
      assert.equal(rig.joints.length, 9999);
      stepAndCheck(inst, 30);
      inst.reset();
      stepAndCheck(inst, 2, 1e9);
    });
  });

  test('deeply nested extras and metadata values (200,000 levels) do not exhaust the WebAssembly stack', () => {
    const deep = '['.repeat(200000) + ']'.repeat(200000);
    const text = `{"asset":{"version":"2.0","extras":${deep}},"nodes":[{"name":"Avatar_Hips","children":[1],"extras":${deep}},` +
      `{"name":"springbone_a","children":[2],"translation":[0,-0.1,0]},{"name":"springbone_b","translation":[0,-0.1,0]}],"extras":${deep}}`;
    const metadata = `{"version":1,"models":{"${kHash}":{"springbone_a":{"stiffness":${deep},"gravityPower":1,` +
      `"gravityDir":[0,-1,0],"drag":0.5,"isRoot":true,"custom":${deep}}}}}`;
    withRig(encoder.encode(text), metadata, (rig, inst) => {
      assert.equal(rig.joints.length, 1);
      assert.ok(rig.warnings.some((w) => w.code === 'param-not-number'));
      stepAndCheck(inst);
    });
    expectCode('metadata-invalid', () => sb.loadRig(hairGlb, deep, { contentHash: kHash }));
    // 1,000 nodes with ten levels of extras each.
    const shallow = '['.repeat(10) + ']'.repeat(10);
    withRig(encoder.encode(deepChainText(1000, shallow)), null, () => {});
  });
});

describe('names', () => {
  test('invalid UTF-8 in a node name becomes U+FFFD, as TextDecoder decodes it; an escaped lone surrogate is gltf-invalid', () => {
    const prefix = encoder.encode('{"asset":{"version":"2.0"},"nodes":[{"name":"Avatar_Head","children":[1]},{"children":[2],"name":"springbone_');
    const suffix = encoder.encode('"},{"name":"t","translation":[0,-1,0]}]}');
    for (const bad of [[0xff, 0xfe], [0xc3], [0xed, 0xa0, 0x80], [0xc0, 0xaf]]) {
      const bytes = new Uint8Array([...prefix, ...bad, ...suffix]);
      // The page's own decoding of the same bytes is the ground truth: the name it would hand over.
      const expected = JSON.parse(new TextDecoder().decode(bytes)).nodes[1].name;
      assert.ok(expected.includes('\ufffd'));
      withRig(glbOfJson(bytes), { version: 1, models: { [kHash]: { [expected]: entry(1, 1, [0, -1, 0], 0.5) } } }, (rig) => {
        assert.equal(rig.joints[0].name, expected);
      });
    }
    expectCode('gltf-invalid', () => sb.loadRig(glbOfJson('{"asset":{"version":"2.0"},"nodes":[{"name":"a\\ud800"}]}'), null));
    // Well-formed odd names load and come back intact.
    const odd = 'springbone_\u0000\u{1F600}/~"\\';
    withRig(gltfBytes({ asset: { version: '2.0' }, nodes: [{ name: 'Avatar_Head', children: [1] }, { name: odd, children: [2] }, { name: 't', translation: [0, -1, 0] }] }),
      { version: 1, models: { [kHash]: { [odd]: entry(1, 1, [0, -1, 0], 0.5) } } }, (rig, inst) => {
        assert.equal(rig.joints[0].name, odd);
        stepAndCheck(inst);
      });
  });

  test('a lone surrogate in metadata is a RangeError that says where, as an object, as text or spelled as an escape', () => {
    const before = sb.stats().heapInUse;
    const refused = (e) => e instanceof RangeError && /lone surrogate/.test(e.message);
    assert.throws(() => sb.loadRig(hairGlb, { version: 1, models: { [kHash]: { 'springbone_\ud800': {} } } }, { contentHash: kHash }), refused);
    assert.throws(() => sb.loadRig(hairGlb, `{"version":1,"models":{"${kHash}":{"springbone_\ud800":{}}}}`, { contentHash: kHash }), refused);
    // JSON text may spell it as an escape: JSON.parse gives the same lone surrogate, refused alike.
    assert.throws(() => sb.loadRig(hairGlb, `{"version":1,"models":{"${kHash}":{"springbone_\\ud800":{}}}}`, { contentHash: kHash }), refused);
    assert.equal(sb.stats().heapInUse, before);
  });
});

describe('metadata', () => {
  test('10 MB of metadata loads, more than 16 MiB is limit-exceeded', () => {
    const filler = JSON.stringify({ stiffness: 1, gravityPower: 1, gravityDir: [0, -1, 0], drag: 0.5, pad: 'x'.repeat(900) });
    const parts = [`{"version":1,"models":{"${kHash}":{`];
    let size = parts[0].length;
    let count = 0;
    while (size < 10 << 20) {
      const part = `"springbone_unused_${count++}":${filler},`;
      parts.push(part);
      size += part.length;
    }
    parts.push(`"SpringBone_hair":${JSON.stringify(entry(1, 1, [0, -1, 0], 0.5))}}}}`);
    const text = parts.join('');
    withRig(hairGlb, text, (rig, inst) => {
      assert.equal(rig.joints.length, 2);
      assert.equal(rig.warnings.filter((w) => w.code === 'bone-not-found').length, count);
      stepAndCheck(inst);
    });
    expectCode('limit-exceeded', () => sb.loadRig(hairGlb, `{${' '.repeat(16 << 20)}}`, { contentHash: kHash }));
  });

  test('parameters as strings, null, arrays, booleans and ±1e308 are replaced or clamped with warnings', () => {
    // [value, warning, expected stiffness / gravityPower / drag]: the ADR defaults (2, 0, 0.5)
    // replace what is not a number; out-of-range values clamp to [0,4] / [0,2] / [0,1].
    const defaults = [2, 0, 0.5];
    const cases = [['2', 'param-not-number', defaults], [null, 'param-not-number', defaults],
      [[1], 'param-not-number', defaults], [true, 'param-not-number', defaults],
      [1e308, 'param-out-of-range', [4, 2, 1]], [-1e308, 'param-out-of-range', [0, 0, 0]],
      [Number.MIN_VALUE, null, [0, 0, 0]]];
    for (const [value, code, expected] of cases) {
      withRig(hairGlb, hairMetadata(entry(value, value, [0, -1, 0], value)), (rig, inst) => {
        const what = JSON.stringify(value);
        if (code) {
          const hits = rig.warnings.filter((w) => w.code === code);
          assert.deepEqual(hits.map((w) => w.path).sort(), ['drag', 'gravityPower', 'stiffness']
            .map((k) => `/models/${kHash}/SpringBone_hair/${k}`), what);
          assert.ok(hits.every((w) => w.message.length > 0));
        }
        assert.equal(rig.warnings.length, code ? 3 : 0, what);
        const p = rig.joints[0].params;
        assert.deepEqual([p.stiffness, p.gravityPower, p.drag], expected, what);
        stepAndCheck(inst, 20);
      });
    }
    // NaN and Infinity cross as numbers (typed input), and are named: not finite, the default.
    withRig(hairGlb, hairMetadata(entry(NaN, Infinity, [0, -1, 0], -Infinity)), (rig, inst) => {
      assert.equal(rig.warnings.filter((w) => w.code === 'param-not-finite').length, 3);
      const p = rig.joints[0].params;
      assert.deepEqual([p.stiffness, p.gravityPower, p.drag], defaults);
      stepAndCheck(inst);
    });
    // 1e309 in JSON text is Infinity to JSON.parse: not finite, the default.
    withRig(hairGlb, JSON.stringify(hairMetadata(entry(1, 1, [0, -1, 0], 0.5))).replace('"stiffness":1', '"stiffness":1e309'), (rig) => {
      assert.deepEqual(rig.warnings.map((w) => w.code), ['param-not-finite']);
      assert.equal(rig.joints[0].params.stiffness, 2);
    });
  });

  test('gravityDir of length 2 or 4 (or zero, huge, not an array) falls back with a warning', () => {
    // [gravityDir, warning, expected direction]: what is not 3 finite numbers is the default
    // [0,-1,0]; a huge vector keeps its direction (normalized, never overflowing).
    const down = [0, -1, 0];
    const diagonal = Math.fround(1 / Math.sqrt(3));
    const cases = [[[0, -1], 'param-not-vector', down], [[0, -1, 0, 0], 'param-not-vector', down],
      [[], 'param-not-vector', down], [[1e308, 1e308, 1e308], 'param-out-of-range', [diagonal, diagonal, diagonal]],
      [[0, 0, 0], 'gravity-dir-zero', down], ['down', 'param-not-vector', down], [null, 'param-not-vector', down],
      [[0, -1, '0'], 'param-not-vector', down]];
    for (const [dir, code, expected] of cases) {
      withRig(hairGlb, hairMetadata(entry(1, 2, dir, 0.5)), (rig, inst) => {
        const what = JSON.stringify(dir);
        const g = rig.joints[0].params.gravityDir;
        for (let k = 0; k < 3; ++k) assert.ok(Math.abs(g[k] - expected[k]) < 1e-6, `${what}: ${g}`);
        assert.deepEqual(rig.warnings.map((w) => [w.code, w.path]), [[code, `/models/${kHash}/SpringBone_hair/gravityDir`]], what);
        stepAndCheck(inst, 20);
      });
    }
  });
});

describe('Builder edits', () => {
  const entity = {
    content: [{ file: 'a.glb', hash: kHash }],
    metadata: { data: { representations: [{ bodyShapes: ['urn:decentraland:off-chain:base-avatars:BaseMale'], mainFile: 'a.glb' }] } },
  };
  const nest = (levels) => JSON.parse('['.repeat(levels) + ']'.repeat(levels));

  test('params or springBones nested deeper than 64 levels are errors, 64 levels are edited', () => {
    // params (1 level) + 63 arrays = 64 levels: allowed; one more is invalid-argument.
    const edited = tools.setSpringBoneParams(null, entity, 'BaseMale', 'SpringBone_hair', { stiffness: 1, custom: nest(63) });
    assert.deepEqual(edited.models[kHash].SpringBone_hair.custom, nest(63));
    expectCode('invalid-argument', () => tools.setSpringBoneParams(null, entity, 'BaseMale', 'SpringBone_hair', { stiffness: 1, custom: nest(64) }));
    // Existing metadata carried over by the edit: the same limit, metadata-invalid.
    const deepText = `{"version":1,"models":{"${kHash}":{"SpringBone_hair":{"custom":${'['.repeat(200000)}${']'.repeat(200000)}}}}}`;
    expectCode('metadata-invalid', () => tools.setSpringBoneParams(deepText, entity, 'BaseMale', 'SpringBone_hair', { stiffness: 1 }));
    // A JavaScript object nested 200,000 deep cannot even be serialized (JSON.stringify runs out
    // of stack): invalid-argument like the 64 levels above, naming the argument, with the engine's
    // error as the cause; nothing reaches WebAssembly and the module keeps working.
    const deep = deepArrays(200000);
    const expectTooDeep = (what, fn) => {
      assert.throws(fn, (e) => {
        assert.ok(e instanceof SpringBonesError, `${e}`);
        assert.equal(e.code, 'invalid-argument');
        assert.ok(e.message.startsWith(`${what} nests too deeply to serialize as JSON`), e.message);
        assert.ok(e.cause instanceof Error);
        return true;
      });
    };
    expectTooDeep('setSpringBoneParams: params', () => tools.setSpringBoneParams(null, entity, 'BaseMale', 'SpringBone_hair', { custom: deep }));
    expectTooDeep('setSpringBoneParams: springBones', () =>
      tools.setSpringBoneParams({ version: 1, models: { [kHash]: { SpringBone_hair: { custom: deep } } } }, entity, 'BaseMale', 'SpringBone_hair', { stiffness: 1 }));
    expectTooDeep('setSpringBoneParams: entity', () => tools.setSpringBoneParams(null, { ...entity, deep }, 'BaseMale', 'SpringBone_hair', { stiffness: 1 }));
    assert.equal(tools.setSpringBoneParams(null, entity, 'BaseMale', 'SpringBone_hair', { stiffness: 3 }).models[kHash].SpringBone_hair.stiffness, 3);
  });

  test('objects nested too deeply for JSON.stringify are invalid-argument in every call that serializes them', () => {
    const deep = deepArrays(200000);
    const springBones = { version: 1, models: { [kHash]: { springbone_a: { stiffness: 1, custom: deep } } } };
    const entity = { content: [{ file: 'a.glb', hash: kHash }], deep };
    // loadRig serializes nothing: its typed input is written without recursion, at any depth.
    withRig(hairGlb, springBones, (rig) => assert.ok(rig.warnings.length > 0));
    assert.throws(() => sb.loadRig(hairGlb, null, { entity, bodyShape: 'BaseMale' }),
                  (e) => e instanceof SpringBonesError && e.code === 'invalid-argument' && /no data.representations/.test(e.message));
    const calls = [
      ['detectSpringBones: springBones', () => tools.detectSpringBones(hairGlb, springBones, { contentHash: kHash })],
      ['validateSpringBones: entity', () => tools.validateSpringBones(entity)],
    ];
    for (const [what, fn] of calls) {
      expectCode('invalid-argument', fn);
      assert.throws(fn, (e) => e.message.startsWith(`${what} nests too deeply to serialize as JSON`), what);
    }
    // What JSON.stringify throws for other reasons is unchanged: a cycle is its TypeError, and an
    // error thrown by a getter (here a RangeError) goes through as it is.
    const cyclic = { version: 1, models: {} };
    cyclic.models.self = cyclic;
    assert.throws(() => sb.loadRig(hairGlb, cyclic), TypeError);
    const own = new RangeError('from a getter');
    const getter = { version: 1, models: { get [kHash]() { throw own; } } };
    assert.throws(() => sb.loadRig(hairGlb, getter, { contentHash: kHash }), (e) => e === own);
    // A value 1,000 levels deep goes to the core as it is.
    withRig(hairGlb, { version: 1, models: { [kHash]: { SpringBone_hair: { ...entry(1, 1, [0, -1, 0], 0.5), custom: deepArrays(1000) } } } },
      (rig) => assert.equal(rig.joints.length, 2));
  });
});

describe('driver matrices and frame times', () => {
  test('NaN, infinite and singular driver matrices keep rotations finite unit quaternions', () => {
    withRig(hairGlb, hairMetadata(entry(1, 1, [0, -1, 0], 0.5)), (rig, inst) => {
      assert.equal(rig.drivers.length, 1);
      const rest = Float32Array.from(inst.driverMatrices);
      const variant = (f) => { const m = Float32Array.from(rest); f(m); return m; };
      const bad = [
        new Float32Array(16).fill(NaN), new Float32Array(16).fill(Infinity), new Float32Array(16),
        variant((m) => { m.fill(0); m[15] = 1; }), variant((m) => { m[5] = 0; }), variant((m) => { m[13] = NaN; }),
        variant((m) => { m[3] = 1; }), variant((m) => { for (let k = 0; k < 12; ++k) m[k] *= 3e38; }),
        variant((m) => { for (let k = 0; k < 12; ++k) m[k] *= 1e-40; }), variant((m) => { for (let k = 0; k < 4; ++k) m[k] = -m[k]; }),
        variant((m) => { m[12] = 3e38; }),
      ];
      stepAndCheck(inst, 5);
      for (const [b, matrix] of bad.entries()) {
        inst.driverMatrices.set(matrix);
        for (let i = 0; i < 5; ++i) {
          inst.step(1 / 60);
          assertFiniteUnit(inst.rotations, `bad matrix ${b}, frame ${i}`);
        }
        inst.driverMatrices.set(rest);
        stepAndCheck(inst, 5);
        inst.driverMatrices.set(matrix);
        inst.reset();
        inst.step(1 / 60);
        assertFiniteUnit(inst.rotations, `reset under bad matrix ${b}`);
        inst.driverMatrices.set(rest);
        stepAndCheck(inst, 3);
      }
    });
  });

  test('extended colliders of extreme finite sizes under bad driver matrices keep rotations finite unit quaternions', () => {
    // The largest sizes a rig takes (1e6, docs/semantics.md "Colliders"); beyond them a collider
    // is left out with collider-invalid, and hitRadius is clamped with hit-radius-out-of-range.
    const huge = 1e6, tiny = 1e-38, beyond = 3e38;
    const colliders = [
      { node: 'Avatar_Head', inside: true, offset: [huge, 0, 0], radius: huge },
      { node: 'Avatar_Head', inside: true, offset: [0, -0.1, 0], radius: 0 },
      { node: 'Avatar_Head', inside: true, offset: [0, 0, 0], tail: [0, -huge, tiny], radius: tiny },
      { node: 'Avatar_Head', shape: 'plane', offset: [0, -huge, 0], normal: [tiny, tiny, 0] },
      { node: 'Avatar_Head', shape: 'plane', offset: [0, huge, 0], normal: [beyond, beyond, beyond] },
      { node: 'Avatar_Hips', shape: 'plane', normal: [0, -1, tiny] },
    ];
    const leftOut = [
      { node: 'Avatar_Head', inside: true, offset: [beyond, 0, 0], radius: beyond },
      { node: 'Avatar_Head', inside: true, offset: [0, 0, 0], tail: [0, -beyond, tiny], radius: tiny },
      { node: 'Avatar_Head', shape: 'plane', offset: [0, beyond, 0] },
    ];
    const rig = sb.loadRig(hairGlb, hairMetadata(entry(1, 1, [0, -1, 0], 0.5)),
      { contentHash: kHash, colliders: [...colliders, ...leftOut], hitRadius: 1e30 });
    try {
      assert.equal(rig.colliders.length, colliders.length, JSON.stringify(rig.warnings));
      assert.deepEqual(rig.warnings.map((w) => w.code).sort(),
        ['collider-invalid', 'collider-invalid', 'collider-invalid', 'hit-radius-out-of-range']);
      for (const integrator of ['vrm', 'xpbd']) {
        const inst = rig.createInstance({ integrator });
        const rest = Float32Array.from(inst.driverMatrices);
        stepAndCheck(inst, 5);
        for (const fill of [NaN, Infinity, 0, 3e38, 1e-40]) {
          inst.driverMatrices.set(rest.map((v, k) => (k % 16 === 15 ? 1 : v * fill)));
          stepAndCheck(inst, 3);
          inst.driverMatrices.set(rest);
          stepAndCheck(inst, 3);
        }
        inst.dispose();
      }
    } finally {
      rig.dispose();
    }
  });

  test('dt of 1e9 runs at most maxSubsteps steps, dt of -1 does nothing, a non-finite dt is a RangeError', () => {
    withRig(hairGlb, hairMetadata(entry(1, 1, [0, -1, 0], 0.5)), (rig, inst) => {
      stepAndCheck(inst, 10);
      inst.step(1e9);
      assertFiniteUnit(inst.rotations);
      inst.step(Number.MAX_VALUE);
      assertFiniteUnit(inst.rotations);
      const before = Float32Array.from(inst.rotations);
      for (const dt of [-1, 0, -0, -1e9]) {
        inst.step(dt);
        assert.deepEqual(inst.rotations, before, `dt ${dt}`);
      }
      for (const dt of [NaN, Infinity, -Infinity]) assert.throws(() => inst.step(dt), RangeError);
      assert.deepEqual(inst.rotations, before);
      const fast = rig.createInstance({ stepHz: 1000, maxSubsteps: 64 });
      for (const dt of [1e9, 1e12, 1e300]) {
        fast.step(dt);
        assertFiniteUnit(fast.rotations, `dt ${dt} at 1000 Hz`);
      }
      fast.dispose();
    });
  });
});

describe('VRM avatars', () => {
  // A chain of `jointCount` VRMC_springBone joints, every one colliding with `colliderCount`
  // spheres, each listed `repeats` times (repeats count once).
  function vrmDoc(jointCount, colliderCount, repeats) {
    const nodes = [];
    for (let i = 0; i <= jointCount; ++i) {
      nodes.push({ name: `n${i}`, translation: [0, -0.01, 0], ...(i < jointCount ? { children: [i + 1] } : {}) });
    }
    const colliders = Array.from({ length: colliderCount }, () => ({ node: 0, shape: { sphere: { radius: 0.01 } } }));
    const ids = [];
    for (let r = 0; r < repeats; ++r) for (let c = 0; c < colliderCount; ++c) ids.push(c);
    const springs = [{ joints: Array.from({ length: jointCount }, (_, i) => ({ node: i + 1 })), colliderGroups: Array(repeats).fill(0) }];
    return gltfBytes({ asset: { version: '2.0' }, nodes,
      extensions: { VRMC_springBone: { specVersion: '1.0', springs, colliders, colliderGroups: [{ colliders: ids }] } } });
  }

  test('joints x colliders beyond 4,194,304 references is limit-exceeded; repeated references count once', () => {
    const side = Math.floor(Math.sqrt(4194304)) + 2;
    expectCode('limit-exceeded', () => sb.loadVrm(vrmDoc(side + 1, side, 1)));
    const rig = sb.loadVrm(vrmDoc(21, 50, 200));
    try {
      assert.equal(rig.joints.length, 20);
      const inst = rig.createInstance();
      stepAndCheck(inst, 10);
      inst.dispose();
    } finally {
      rig.dispose();
    }
  });
});

describe('size and leaks', () => {
  test('a rig of 100,000 joints loads and steps', () => {
    // 1,000 chains of 100 joints (+ a tip each) under Avatar_Hips, as in the native test.
    const chains = 1000, joints = 100;
    const nodes = [{ name: 'Avatar_Hips', children: [] }];
    const bones = {};
    for (let c = 0; c < chains; ++c) {
      nodes[0].children.push(nodes.length);
      for (let j = 0; j <= joints; ++j) {
        const name = `springbone_${c}_${j}`;
        const node = { name, translation: [j === 0 ? 0.001 : 0, -0.01, 0] };
        if (j < joints) node.children = [nodes.length + 1];
        nodes.push(node);
        if (j === 0) bones[name] = entry(1, 1, [0, -1, 0], 0.4);
      }
    }
    const glb = glbOfDoc({ asset: { version: '2.0' }, nodes });
    const rig = sb.loadRig(glb, { version: 1, models: { [kHash]: bones } }, { contentHash: kHash });
    const inst = rig.createInstance();
    for (let i = 0; i < 10; ++i) inst.step(1 / 60);
    assert.equal(rig.joints.length, chains * joints);
    assertFiniteUnit(inst.rotations);
    inst.dispose();
    rig.dispose();
  });

  test('10,000 load/dispose cycles leave the WASM heap where it started', () => {
    const springBones = JSON.stringify(hairMetadata(entry(1, 1, [0, -1, 0], 0.5)));
    const cycle = (i) => {
      const rig = sb.loadRig(hairGlb, springBones, { contentHash: kHash });
      assert.equal(rig.joints.length, 3);
      const inst = rig.createInstance();
      inst.step(1 / 60);
      // A failing load now and then: errors must free what they allocated too.
      if (i % 100 === 0) assert.throws(() => sb.loadRig(fixture('cycle.gltf'), null), SpringBonesError);
      inst.dispose();
      rig.dispose();
    };
    for (let i = 0; i < 100; ++i) cycle(i);  // warm up allocator pools
    const before = sb.stats();
    for (let i = 0; i < 10000; ++i) cycle(i);
    const after = sb.stats();
    assert.deepEqual(after, before);
  });
});
