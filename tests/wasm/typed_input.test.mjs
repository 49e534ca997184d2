// Typed input (web/typed_value.js): a parsed value crosses into the runtime with its JSON types,
// as JSON.stringify would see it but for non-finite numbers (kept) and lone surrogates (refused),
// without recursion; and loadRig on a page's parse behaves as loadRig on the bytes.
import assert from 'node:assert/strict';
import { before, describe, test } from 'node:test';
import { fixture, metadataKeyOf } from './helpers.mjs';
import { decodeTyped } from './typed_decode.mjs';
import { createSpringBones } from '../../web/springbones.js';
import { encodeTyped } from '../../web/typed_value.js';

const roundTrip = (value) => decodeTyped(encodeTyped('test', value));

describe('encodeTyped', () => {
  test('keeps each JSON type, and reads back what JSON.parse(JSON.stringify()) gives for JSON values', () => {
    const value = { s: 'héllo \u{1F600}', n: -1.5e-300, i: 42, t: true, f: false, z: null, a: [1, 'x', [], {}], o: { b: 2, a: 1 } };
    assert.deepEqual(roundTrip(value), JSON.parse(JSON.stringify(value)));
  });

  test('calls toJSON, leaves out undefined, functions and symbols of objects, unwraps boxed values', () => {
    const value = { d: { toJSON: () => 'D' }, u: undefined, fn() {}, sym: Symbol('s'), arr: [3], boxed: new Number(7) };
    assert.deepEqual(roundTrip(value), JSON.parse(JSON.stringify(value)));
  });

  test('a hole or an undefined element of an array is a TypeError that names its index', () => {
    // eslint-disable-next-line no-sparse-arrays
    assert.throws(() => encodeTyped('arg', { dir: [0, , 1] }), (e) => e instanceof TypeError && /arg\.dir\[1\] is a hole/.test(e.message));
    assert.throws(() => encodeTyped('arg', [1, undefined]), (e) => e instanceof TypeError && /arg\[1\] is undefined/.test(e.message));
    assert.throws(() => encodeTyped('arg', { v: new Float32Array(3) }), (e) => e instanceof TypeError && /arg\.v is a Float32Array/.test(e.message));
  });

  test('keeps NaN and the infinities as numbers', () => {
    const back = roundTrip({ a: NaN, b: Infinity, c: -Infinity });
    assert.ok(Number.isNaN(back.a));
    assert.equal(back.b, Infinity);
    assert.equal(back.c, -Infinity);
  });

  test('refuses a cycle and a BigInt with a TypeError, a lone surrogate with a RangeError, saying where', () => {
    const cyclic = { a: { b: {} } };
    cyclic.a.b.c = cyclic;
    assert.throws(() => encodeTyped('arg', cyclic), (e) => e instanceof TypeError && /circular/.test(e.message));
    assert.throws(() => encodeTyped('arg', { n: 1n }), (e) => e instanceof TypeError && /arg\.n is a BigInt/.test(e.message));
    assert.throws(() => encodeTyped('arg', { models: { 'Hair_springbone\uD800': {} } }),
                  (e) => e instanceof RangeError && /lone surrogate/.test(e.message));
    assert.throws(() => encodeTyped('arg', ['ok', 'bad\uDC00']), (e) => e instanceof RangeError && /arg\[1\] contains a lone surrogate/.test(e.message));
  });

  test('writes a value nested 100,000 deep without running out of stack', () => {
    let deep = [];
    for (let i = 0; i < 100000; ++i) deep = [deep];
    assert.ok(encodeTyped('deep', deep).length > 500000);
  });

  test('a repeated (not circular) object is written twice', () => {
    const shared = { x: 1 };
    assert.deepEqual(roundTrip({ a: shared, b: shared }), { a: { x: 1 }, b: { x: 1 } });
  });
});

describe('loadRig on what the page parsed', () => {
  let sb;
  before(async () => {
    sb = await createSpringBones();
  });
  const glb = () => new Uint8Array(fixture('avatar_hair.glb'));
  const metadata = () => JSON.parse(fixture('avatar_hair.metadata.json').toString('utf8'));
  const key = metadataKeyOf('avatar_hair.glb');
  const gltfJson = (bytes) => {
    const view = new DataView(bytes.buffer, bytes.byteOffset);
    return JSON.parse(new TextDecoder().decode(bytes.subarray(20, 20 + view.getUint32(12, true))));
  };

  test('gives the rig the bytes give', () => {
    const a = sb.loadRig(glb(), metadata(), { contentHash: key });
    const b = sb.loadRig(gltfJson(glb()), metadata(), { contentHash: key });
    assert.ok(a.joints.length > 0);
    assert.deepEqual(b.joints, a.joints);
    assert.deepEqual(b.warnings, a.warnings);
    a.dispose();
    b.dispose();
  });

  test('a non-finite parameter in the springBones object earns param-not-finite and the default', () => {
    const m = metadata();
    const [name] = Object.keys(m.models[key]);
    m.models[key][name].stiffness = NaN;
    const rig = sb.loadRig(glb(), m, { contentHash: key });
    const warning = rig.warnings.find((w) => w.code === 'param-not-finite' && w.path.endsWith('/stiffness'));
    assert.ok(warning, JSON.stringify(rig.warnings));
    assert.equal(rig.joints.find((j) => j.name === name).params.stiffness, 2);
    rig.dispose();
  });

  test('without bytes to hash, springBones needs contentHash or an entity', () => {
    assert.throws(() => sb.loadRig(gltfJson(glb()), metadata()), (e) => e instanceof TypeError && /contentHash/.test(e.message));
    const rig = sb.loadRig(gltfJson(glb()), null);
    assert.equal(rig.joints.length, 0);
    rig.dispose();
  });

  test('a glTF that is neither bytes nor an object is a TypeError; bad node fields the same error as in a file', () => {
    assert.throws(() => sb.loadRig('{"asset":{}}', null), TypeError);
    const json = gltfJson(glb());
    json.nodes[1].translation = [0, 'up', 0];
    const bytes = new TextEncoder().encode(JSON.stringify(json));
    const codeOf = (fn) => { try { fn(); } catch (e) { return `${e.code}: ${e.message}`; } return 'no error'; };
    assert.equal(codeOf(() => sb.loadRig(json, null)), codeOf(() => sb.loadRig(bytes, null)));
    assert.match(codeOf(() => sb.loadRig(json, null)), /^gltf-invalid: node 1: translation/);
  });

  test('springBones JSON text still works, and text that does not parse is metadata-bad-json', () => {
    const rig = sb.loadRig(glb(), JSON.stringify(metadata()), { contentHash: key });
    assert.ok(rig.joints.length > 0);
    rig.dispose();
    assert.throws(() => sb.loadRig(glb(), '{"version":', { contentHash: key }), (e) => e.code === 'metadata-bad-json');
  });
});
