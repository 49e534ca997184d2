// loadRig with a springBones object: the usual objects go to the core already decoded
// (springBonesEntries in web/springbones.js, readSpringBonesEntries in src/json_scan.h) instead of
// as JSON.stringify's text. That is only a shortcut: for every input, the object must give what its
// JSON text gives (the same rig description, warnings in the same order, or the same error).
// Each variant below is loaded both ways and compared; a few check which way was taken, by
// counting the JSON.stringify calls loadRig makes on the springBones object (the shortcut makes
// none; the text path, also after the core declined the shortcut, makes one).
import assert from 'node:assert/strict';
import { after, before, describe, test } from 'node:test';

import { createSpringBones } from '../../web/springbones.js';
import { glbBytes } from './helpers.mjs';

let sb;
before(async () => {
  sb = await createSpringBones();
});

// Chains whose names need escaping in JSON pointers, UTF-8 of 2, 3 and 4 bytes, and a center node.
const kChainNames = ['springbone_a', 'springbone_b', 'springbone_é', 'springbone_日本', 'springbone_😀', 'springbone/x~y'];
function skeleton() {
  const nodes = [{ name: 'Avatar_Head', children: [], translation: [0, 1.6, 0] }, { name: 'center_node' }];
  nodes[0].children.push(1);
  for (const [c, name] of kChainNames.entries()) {
    const first = nodes.length;
    nodes[0].children.push(first);
    nodes.push({ name, translation: [0.01 * c, 0, 0.05], children: [first + 1] });
    nodes.push({ name: `${name}_1`, translation: [0, -0.05, 0], children: [first + 2] });
    nodes.push({ name: `${name}_tip`, translation: [0, -0.05, 0] });
  }
  return glbBytes({ asset: { version: '2.0' }, scene: 0, scenes: [{ nodes: [0] }], nodes });
}
const glb = skeleton();

const kParams = { stiffness: 1, gravityPower: 0.5, gravityDir: [0, -1, 0], drag: 0.4 };
function entries(overrides = {}) {
  const out = {};
  for (const name of kChainNames) {
    out[name] = { ...kParams, isRoot: true };
    out[`${name}_1`] = { ...kParams };
  }
  return Object.assign(out, overrides);
}
function springBones(overrides = {}, hash = 'h') {
  return { version: 1, models: { [hash]: entries(overrides) } };
}

// Everything a rig tells about itself, or the error: what both paths must agree on.
function outcome(load) {
  try {
    const rig = load();
    const seen = {
      contentHash: rig.contentHash, format: rig.format, nodeCount: rig.nodeCount, joints: rig.joints,
      chains: rig.chains, drivers: rig.drivers, colliders: rig.colliders, warnings: rig.warnings,
    };
    // And how it moves, bit for bit (the description's numbers are rounded, and would hide a -0).
    const instance = rig.createInstance();
    for (let i = 0; i < 4; ++i) instance.step(1 / 30);
    seen.motion = Array.from(new Uint32Array(Float32Array.from(instance.rotations).buffer));
    instance.dispose();
    rig.dispose();
    return { rig: seen };
  } catch (error) {
    return { error: { type: error.constructor.name, code: error.code, message: error.message, path: error.path } };
  }
}

// JSON.stringify(value) calls made while fn runs (any other value is not counted).
function stringifyCallsOn(value, fn) {
  const original = JSON.stringify;
  let calls = 0;
  JSON.stringify = function stringify(v, ...rest) {
    if (v === value) ++calls;
    return original.call(this, v, ...rest);
  };
  try {
    fn();
  } finally {
    JSON.stringify = original;
  }
  return calls;
}

// The object and its JSON text load alike. The text is taken first, so a value that changes on
// every read is compared with what the first read gave. When JSON.stringify throws, the object
// must throw the same.
function assertSameAsText(value, options = { contentHash: 'h' }, what = '') {
  let text;
  try {
    text = JSON.stringify(value);
  } catch (error) {
    assert.deepEqual(outcome(() => sb.loadRig(glb, value, options)),
      { error: { type: error.constructor.name, code: undefined, message: error.message, path: undefined } }, what);
    return;
  }
  const fromText = outcome(() => sb.loadRig(glb, text ?? null, options));
  const fromObject = outcome(() => sb.loadRig(glb, value, options));
  assert.deepEqual(fromObject, fromText, what);
  return fromObject;
}

function withGetter(object, key, get) {
  Object.defineProperty(object, key, { get, enumerable: true, configurable: true });
  return object;
}

describe('loadRig: a springBones object loads as its JSON text does', () => {
  after(() => assert.equal(sb.stats().rigs, 0));

  test('the usual object, and several shapes of it', () => {
    const plain = assertSameAsText(springBones());
    assert.equal(plain.rig.joints.length, 2 * kChainNames.length);
    assert.deepEqual(plain.rig.warnings, []);
    assertSameAsText(springBones({ springbone_a: {} }), undefined, 'every param missing');
    assertSameAsText(springBones({ springbone_a: { isRoot: true } }), undefined, 'only isRoot');
    assertSameAsText({ models: springBones().models, version: 1 }, undefined, 'models first');
    assertSameAsText({ version: 1, models: { h: {} } }, undefined, 'an empty model');
    const parsed = JSON.parse(JSON.stringify(springBones()));
    assertSameAsText(parsed, undefined, 'from JSON.parse');
  });

  test('numbers: zeros, bounds, out of range, not finite, huge, tiny', () => {
    const variants = [];
    for (const key of ['stiffness', 'gravityPower', 'drag']) {
      for (const v of [-0, 0, 1, 2, 4, 0.1 + 0.2, 1 / 3, 4.000000000000001, 2.0000001, 1.0000001, -1e-300, 5e-324,
                       1e300, -1e300, 1e21, 2 ** 60, NaN, Infinity, -Infinity, Number.MAX_VALUE]) {
        variants.push([`${key} ${v}`, { springbone_a: { ...kParams, [key]: v } }]);
      }
    }
    for (const dir of [[-0, -1, -0], [1, -0, 0], [0, 0, 0], [1e-10, 0, 0], [1e-9, 0, 0], [2e-9, 0, 0], [10, 0, 0],
                       [-10, 0, 0], [10.000000000000002, 0, 0], [1e300, 0, 0], [3, 4, 12], [0.1, 0.2, 0.3],
                       [NaN, -1, 0], [0, Infinity, 0], [5e-324, 5e-324, 0], [1e-300, -1e-300, 1e-300]]) {
      variants.push([`gravityDir ${dir}`, { springbone_a: { ...kParams, gravityDir: dir } }]);
    }
    for (const [what, overrides] of variants) assertSameAsText(springBones(overrides), undefined, what);
  });

  test('values JSON.stringify writes otherwise: wrappers, undefined, functions, symbols, BigInt', () => {
    const odd = [
      ['Number object', new Number(1)], ['String number', '1'], ['Boolean', true], ['null', null],
      ['undefined', undefined], ['function', () => 1], ['symbol', Symbol('s')], ['array', [1]], ['object', {}],
      ['BigInt', 1n], ['Date', new Date(0)],
    ];
    for (const [what, v] of odd) {
      for (const key of ['stiffness', 'gravityPower', 'drag', 'gravityDir', 'center', 'isRoot']) {
        assertSameAsText(springBones({ springbone_a: { ...kParams, [key]: v } }), undefined, `${key}: ${what}`);
      }
    }
    const sparse = [0, , 0];  // eslint-disable-line no-sparse-arrays
    const extra = Object.assign([0, -1, 0], { extra: 1 });
    for (const [what, dir] of [['2 numbers', [0, -1]], ['4 numbers', [0, -1, 0, 0]], ['sparse', sparse],
                               ['extra property', extra], ['Float64Array', new Float64Array([0, -1, 0])],
                               ['strings', ['0', '-1', '0']], ['Number objects', [new Number(0), -1, 0]],
                               ['object', { 0: 0, 1: -1, 2: 0, length: 3 }]]) {
      assertSameAsText(springBones({ springbone_a: { ...kParams, gravityDir: dir } }), undefined, `gravityDir ${what}`);
    }
  });

  test('center and isRoot', () => {
    for (const center of [null, 'center_node', '', 'no_such_node', 'springbone_é', 'Avatar_Head', 5, false, '\ud800',
                          'center_node\u0000']) {
      assertSameAsText(springBones({ springbone_a: { ...kParams, center } }), undefined, `center ${String(center)}`);
      assertSameAsText(springBones({ springbone_b: { ...kParams, isRoot: true, center } }), undefined, 'center on a root');
    }
    for (const isRoot of [null, false, true, 1, 0, 'true']) {
      assertSameAsText(springBones({ springbone_a: { ...kParams, isRoot }, springbone_a_1: { ...kParams, isRoot } }),
        undefined, `isRoot ${isRoot}`);
    }
  });

  test('names: unknown, escaped, integer-like, __proto__, lone surrogates, repeated', () => {
    const unknown = { ...kParams, stiffnes: 1 };
    assertSameAsText(springBones({ springbone_a: unknown }), undefined, 'an unknown key');
    assertSameAsText(springBones({ '0': { ...kParams }, '10': {}, '2': { drag: 0.1 }, '': {} }), undefined, 'integer-like and empty names');
    assertSameAsText(springBones({ 'a"b\\c\n': { ...kParams }, 'tab\there': {} }), undefined, 'names JSON escapes');
    assertSameAsText(JSON.parse('{"version":1,"models":{"h":{"__proto__":{"stiffness":1},"springbone_a":{}}}}'),
      undefined, 'an own __proto__ entry');
    assertSameAsText(springBones({ 'bad\udc00': { ...kParams } }), undefined, 'a lone low surrogate in a name');
    assertSameAsText(springBones({ '\ud83d': {}, '\ude00': {} }), undefined, 'a pair split over two names');
    assertSameAsText(springBones({ 'springbone_\u00e9': {}, 'springbone_e\u0301': {} }), undefined, 'NFC and NFD apart');
    assertSameAsText({ version: 1, models: { h: entries(), 'h\ud800': {} } }, undefined, 'a lone surrogate in another key');
    assertSameAsText({ version: 1, models: { '\ud800': entries() } }, { contentHash: '\ud800' }, 'lone surrogate hash');
    assertSameAsText({ version: 1, models: { h: { springbone_a: { [Symbol('x')]: 1, ...kParams } } } }, undefined,
      'a symbol key');
  });

  test('top level: version, models, other models, hashes', () => {
    const model = entries();
    const tops = [
      ['version 2', { version: 2, models: { h: model } }], ['version "1"', { version: '1', models: { h: model } }],
      ['version 1.0', { version: 1.0, models: { h: model } }], ['no version', { models: { h: model } }],
      ['no models', { version: 1 }], ['models null', { version: 1, models: null }], ['models array', { version: 1, models: [model] }],
      ['models string', { version: 1, models: 'h' }], ['extra key', { version: 1, models: { h: model }, extra: {} }],
      ['model a number', { version: 1, models: { h: 5 } }], ['model an array', { version: 1, models: { h: [] } }],
      ['model null', { version: 1, models: { h: null } }], ['entry a number', { version: 1, models: { h: { springbone_a: 5 } } }],
      ['entry an array', { version: 1, models: { h: { springbone_a: [1] } } }],
      ['entry null', { version: 1, models: { h: { springbone_a: null } } }],
      ['another model malformed', { version: 1, models: { other: 5, h: model } }],
      ['another model with odd entries', { version: 1, models: { other: { x: { stiffness: NaN, y: 1 } }, h: model } }],
      ['the same model twice', { version: 1, models: { other: model, h: model } }],
      ['hash not in models', { version: 1, models: { other: model } }],
      ['empty models', { version: 1, models: {} }],
      ['an array', [1, 2]],
    ];
    for (const [what, value] of tops) assertSameAsText(value, undefined, what);
    // Without a contentHash the core hashes the GLB; with an entity it picks the hash from it.
    assertSameAsText(springBones(), {}, 'no contentHash');
    assertSameAsText(springBones({}, sb.contentHash(glb)), {}, 'no contentHash, the GLB\'s hash in models');
    assertSameAsText(springBones({}, 'hash-of-nothing'), undefined, 'another hash');
    for (const value of [null, undefined]) {
      assert.deepEqual(outcome(() => sb.loadRig(glb, value, { contentHash: 'h' })),
        outcome(() => sb.loadRig(glb, 'null', { contentHash: 'h' })), String(value));
    }
  });

  test('objects that are not plain: toJSON, prototypes, getters, proxies, cycles', () => {
    const throwing = () => { throw new RangeError('no reading this'); };
    const variants = [
      ['toJSON at the top', Object.assign(springBones(), { toJSON: () => ({ version: 1, models: { h: {} } }) })],
      ['toJSON on models', { version: 1, models: Object.assign(entries(), { toJSON: () => 'x' }) }],
      ['toJSON on the model', { version: 1, models: { h: Object.assign(entries(), { toJSON: () => ({}) }) } }],
      ['toJSON on an entry', springBones({ springbone_a: { ...kParams, toJSON: () => ({ drag: 0.9 }) } })],
      ['toJSON on a gravityDir', springBones({ springbone_a: { ...kParams, gravityDir: Object.assign([0, -1, 0], { toJSON: () => [1, 0, 0] }) } })],
      ['non-enumerable toJSON', springBones({
        springbone_a: Object.defineProperty({ ...kParams }, 'toJSON', { value: () => ({ drag: 0.9 }), enumerable: false }),
      })],
      ['null prototype entry', springBones({ springbone_a: Object.assign(Object.create(null), kParams) })],
      ['class instance entry', springBones({ springbone_a: Object.assign(new (class Entry {})(), kParams) })],
      ['Map entry', springBones({ springbone_a: new Map(Object.entries(kParams)) })],
      ['array subclass gravityDir', springBones({ springbone_a: { ...kParams, gravityDir: Object.setPrototypeOf([0, -1, 0], Object.create(Array.prototype)) } })],
      ['getter', springBones({ springbone_a: withGetter({ ...kParams }, 'drag', () => 0.25) })],
      ['throwing getter', springBones({ springbone_a: withGetter({ ...kParams }, 'drag', throwing) })],
      ['throwing getter elsewhere', { version: 1, models: withGetter({ h: entries() }, 'other', throwing) }],
      ['non-enumerable stiffness', springBones({ springbone_a: Object.defineProperty({ drag: 0.2 }, 'stiffness', { value: 3, enumerable: false }) })],
      ['non-enumerable stiffness and an unknown key', springBones({
        springbone_a: Object.defineProperty({ drag: 0.2, extra: 1 }, 'stiffness', { value: 3, enumerable: false }),
      })],
      ['proxy entry', springBones({ springbone_a: new Proxy({ ...kParams }, {}) })],
      ['proxy that throws', springBones({ springbone_a: new Proxy({ ...kParams }, { ownKeys: throwing }) })],
      ['frozen entry', springBones({ springbone_a: Object.freeze({ ...kParams }) })],
    ];
    const cyclic = springBones();
    cyclic.models.h.springbone_a.self = cyclic;
    variants.push(['a cycle', cyclic]);
    const cyclicOther = springBones();
    cyclicOther.models.other = cyclicOther.models;
    variants.push(['a cycle in another model', cyclicOther]);
    variants.push(['BigInt in another model', { version: 1, models: { h: entries(), other: { x: { stiffness: 1n } } } }]);
    for (const [what, value] of variants) assertSameAsText(value, undefined, what);
  });

  test('changes to the prototypes JSON.stringify sees', () => {
    const cases = [
      [Object.prototype, 'inherited', { value: 1, enumerable: true }],
      [Object.prototype, 'stiffness', { value: 3, enumerable: false }],
      [Object.prototype, 'gravityPower', { value: 1, enumerable: true }],
      [Object.prototype, 'toJSON', { value() { return this; }, enumerable: false }],
      [Array.prototype, 'toJSON', { value() { return [1, 0, 0]; }, enumerable: false }],
    ];
    for (const [proto, key, descriptor] of cases) {
      Object.defineProperty(proto, key, { ...descriptor, configurable: true, writable: true });
      try {
        assertSameAsText(springBones({ springbone_a: { drag: 0.2 } }), undefined, key);
      } finally {
        delete proto[key];
      }
    }
  });

  test('large models: 5,000 entries, and texts near and over the 16 MiB limit', () => {
    const many = {};
    for (let c = 0; c < 1000; ++c) {
      for (let j = 0; j < 5; ++j) many[`springbone_${c}_${j}`] = j === 0 ? { ...kParams, isRoot: true } : { ...kParams };
    }
    assertSameAsText({ version: 1, models: { h: { ...entries(), ...many } } }, undefined, '5,000 entries');
    const mib = 1024 * 1024;
    for (const [what, length] of [['2 MiB center', 2 * mib], ['3 MiB center (JS bound over, text under)', 3 * mib],
                                  ['17 MiB center', 17 * mib]]) {
      assertSameAsText(springBones({ springbone_a: { ...kParams, center: 'c'.repeat(length) } }), undefined, what);
    }
    assertSameAsText({ version: 1, models: { h: entries(), other: { x: { center: 'é'.repeat(9 * mib) } } } },
      undefined, '18 MiB of UTF-8 in another model');
  });

  test('with colliders and hitRadius', () => {
    const options = {
      contentHash: 'h', hitRadius: 0.02,
      colliders: [{ node: 'Avatar_Head', offset: [0, 0.1, 0], radius: 0.1, tail: [0, 0.2, 0] }],
    };
    assertSameAsText(springBones(), options, 'colliders');
    assertSameAsText(springBones({ springbone_a: { drag: 7 } }), options, 'colliders and a warning');
  });

  test('a GLB that does not load gives its error either way', () => {
    const bad = new Uint8Array([1, 2, 3]);
    const value = springBones();
    assert.deepEqual(outcome(() => sb.loadRig(bad, value, { contentHash: 'h' })),
      outcome(() => sb.loadRig(bad, JSON.stringify(value), { contentHash: 'h' })));
    assert.equal(outcome(() => sb.loadRig(bad, value, { contentHash: 'h' })).error.type, 'SpringBonesError');
  });
});

describe('loadRig: which path a springBones object takes', () => {
  const load = (value, options = { contentHash: 'h' }) => stringifyCallsOn(value, () => {
    const result = outcome(() => sb.loadRig(glb, value, options));
    assert.ok(result.rig, JSON.stringify(result.error));
  });

  test('the usual object goes in decoded, without JSON.stringify', () => {
    assert.equal(load(springBones()), 0);
    assert.equal(load(springBones({ springbone_a: { center: 'center_node', isRoot: null } })), 0);
    assert.equal(load(springBones({ 'springbone_é': { ...kParams, center: '日本' } })), 0);
    assert.equal(load(springBones({}, sb.contentHash(glb)), {}), 0, 'no contentHash: the GLB\'s own');
  });

  test('anything unusual goes as text: declined in JS or by the core', () => {
    assert.equal(load(springBones({ springbone_a: { ...kParams, note: 'hi' } })), 1, 'unknown key (JS)');
    assert.equal(load(springBones({ springbone_a: { ...kParams, drag: NaN } })), 1, 'NaN (JS)');
    assert.equal(load(springBones({ springbone_a: { ...kParams, drag: 2 } })), 1, 'out of range (core)');
    assert.equal(load(springBones({ springbone_a: { ...kParams, gravityDir: [0, 0, 0] } })), 1, 'no direction (core)');
    assert.equal(load(springBones(), {}), 1, 'no contentHash');
    assert.equal(load(springBones({}, 'other')), 1, 'hash not in models');
  });
});
