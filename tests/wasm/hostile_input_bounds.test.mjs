// Bounded by its input (issue 39, classes 1-3): every dimension of an object argument has a bound,
// checked before the work it bounds, in JavaScript before encoding (web/typed_value.js) as in the
// core before allocating (tests/native/hostile_input_test.cpp holds the core's side). Work is
// counted, never timed: a Proxy counts the reads the encoder makes, and the module's memory is
// compared before and after each refused input.
import assert from 'node:assert/strict';
import { describe, test } from 'node:test';

import { createSpringBones, SpringBonesError } from '../../web/springbones.js';
import { kTypedLimits } from '../../web/typed_encoding.js';
import { encodeGltf, encodeTyped } from '../../web/typed_value.js';
import { fixture } from './helpers.mjs';

const sb = await createSpringBones();
const kHash = 'bafkreibounds';

const hairDoc = () => ({
  asset: { version: '2.0' },
  nodes: [
    { name: 'Avatar_Head', children: [1] },
    { name: 'SpringBone_hair', children: [2], translation: [0.1, 0, 0] },
    { name: 'SpringBone_hair_1', translation: [0, -0.1, 0] },
  ],
});
const hairEntry = () => ({ stiffness: 1, gravityPower: 0.5, gravityDir: [0, -1, 0], drag: 0.4, isRoot: true });
const metadataWith = (bones) => ({ version: 1, models: { [kHash]: bones } });

// A Proxy over `target` that counts every trap it sees; `onGet` may change the target.
function counted(target, onGet = () => {}) {
  const counts = { traps: 0 };
  const proxy = new Proxy(target, {
    get(t, key, receiver) {
      ++counts.traps;
      onGet(t, key);
      return Reflect.get(t, key, receiver);
    },
    has(t, key) {
      ++counts.traps;
      return Reflect.has(t, key);
    },
    ownKeys(t) {
      ++counts.traps;
      return Reflect.ownKeys(t);
    },
    getOwnPropertyDescriptor(t, key) {
      ++counts.traps;
      return Reflect.getOwnPropertyDescriptor(t, key);
    },
  });
  return { proxy, counts };
}

// `fn` throws limit-exceeded (with the limit in its message and, when given, its path), leaves the
// module's memory and its heap in use where they were, and frees every handle.
function refusedWithin(fn, { limit, path } = {}) {
  const before = sb.stats();
  assert.throws(fn, (e) => {
    assert.ok(e instanceof SpringBonesError, `${e}`);
    assert.equal(e.code, 'limit-exceeded', e.message);
    if (limit !== undefined) assert.ok(e.message.includes(String(limit)), e.message);
    if (path !== undefined) assert.equal(e.path, path);
    assert.ok(e.message.length < 400, `the message quotes a bounded prefix: ${e.message.length} characters`);
    return true;
  });
  const after = sb.stats();
  assert.equal(after.heapBytes, before.heapBytes, 'the module\'s memory did not grow');
  assert.equal(after.heapInUse, before.heapInUse);
  assert.equal(after.rigs, before.rigs);
}

describe('class 1: the node count is checked before any node is encoded', () => {
  test('a sparse nodes array of length 2**32 - 1 is limit-exceeded after reading its length alone', () => {
    const nodes = [];
    nodes.length = 2 ** 32 - 1;
    const { proxy, counts } = counted(nodes);
    refusedWithin(() => sb.loadRig({ asset: { version: '2.0' }, nodes: proxy }, null), { limit: kTypedLimits.maxNodes, path: '/nodes' });
    refusedWithin(() => sb.loadVrm({ asset: { version: '2.0' }, nodes: proxy }), { limit: kTypedLimits.maxNodes });
    assert.ok(counts.traps <= 8, `${counts.traps} reads of the nodes array`);
  });

  test('1,000,000 nodes are refused without growing the module; the limit itself loads', () => {
    const doc = { asset: { version: '2.0' }, nodes: Array.from({ length: 1_000_000 }, () => ({})) };
    refusedWithin(() => sb.loadRig(doc, null), { limit: kTypedLimits.maxNodes, path: '/nodes' });
    doc.nodes.length = kTypedLimits.maxNodes + 1;
    refusedWithin(() => sb.loadRig(doc, null), { limit: kTypedLimits.maxNodes });
    doc.nodes.length = kTypedLimits.maxNodes;
    const rig = sb.loadRig(doc, null);
    assert.equal(rig.nodeCount, kTypedLimits.maxNodes);
    rig.dispose();
  });
});

describe('class 2: a length is read once, so a growing array is written as long as it was', () => {
  // An array whose every element read pushes another element.
  const growing = (values) => counted(values.slice(), (t, key) => {
    if (/^\d+$/.test(String(key))) t.push(t[t.length - 1]);
  });

  test('children, gravityDir, VRM joints: each read is bounded by the length first read', () => {
    const doc = hairDoc();
    const children = growing([1]);
    doc.nodes[0].children = children.proxy;
    const gravityDir = growing([0, -1, 0]);
    const rig = sb.loadRig(doc, metadataWith({ SpringBone_hair: { ...hairEntry(), gravityDir: gravityDir.proxy } }),
                           { contentHash: kHash });
    assert.equal(rig.joints.length, 1);
    assert.deepEqual(rig.joints[0].params.gravityDir, [0, -1, 0]);
    rig.dispose();
    // One read of the length, then for each element a has and a get (and its toJSON lookup on the value).
    assert.ok(children.counts.traps <= 8, `children: ${children.counts.traps} traps`);
    assert.ok(gravityDir.counts.traps <= 16, `gravityDir: ${gravityDir.counts.traps} traps`);

    const file = fixture('vrm10_springs.vrm');
    const vrm = JSON.parse(file.subarray(20, 20 + file.readUInt32LE(12)).toString('utf8'));
    const spring = vrm.extensions.VRMC_springBone.springs[0];
    const joints = growing(spring.joints);
    const first = spring.joints.length;
    spring.joints = joints.proxy;
    const fromVrm = sb.loadVrm(vrm);
    assert.ok(fromVrm.joints.length > 0);
    fromVrm.dispose();
    assert.ok(joints.counts.traps <= 4 * first + 8, `joints: ${joints.counts.traps} traps for ${first} joints`);
  });

  test('colliders: the options\' array is checked and read to the length it had', () => {
    const colliders = growing([{ node: 'Avatar_Head', offset: [0, 0, 0], radius: 0.1 }]);
    const rig = sb.loadRig(hairDoc(), metadataWith({ SpringBone_hair: hairEntry() }),
                           { contentHash: kHash, colliders: colliders.proxy });
    assert.ok(rig.colliders.length >= 1 && rig.colliders.length <= 3, `${rig.colliders.length} colliders`);
    rig.dispose();
    assert.ok(colliders.counts.traps <= 64, `colliders: ${colliders.counts.traps} traps`);
  });

  test('an array whose length grows each time it is read is written at the length first read', () => {
    const { proxy, counts } = counted([0.5], (t, key) => {
      if (key === 'length') t.push(0.5);
    });
    const bytes = encodeTyped('test', { a: proxy });
    // tag, count, key "a", then the array: its count is the length of the one read.
    assert.equal(new DataView(bytes.buffer, bytes.byteOffset).getUint32(1 + 4 + 4 + 1 + 1, true), 2);
    assert.ok(counts.traps <= 8, `${counts.traps} traps`);
  });

  test('an array longer than the container bound is refused by its length, before its elements', () => {
    const long = [];
    long.length = kTypedLimits.maxContainerSize + 1;
    const { proxy, counts } = counted(long);
    refusedWithin(() => encodeTyped('test', { a: proxy }), { limit: kTypedLimits.maxContainerSize, path: '/a' });
    assert.ok(counts.traps <= 4, `${counts.traps} traps`);
  });
});

describe('class 3: strings, keys and whole objects have bounds, and messages quote names by a prefix', () => {
  test('a 50 MB bone key is refused at once: limit-exceeded, and the module does not grow', () => {
    const key = `SpringBone_${'x'.repeat(50_000_000)}`;
    refusedWithin(() => sb.loadRig(hairDoc(), metadataWith({ [key]: hairEntry() }), { contentHash: kHash }),
                  { limit: kTypedLimits.maxStringBytes });
  });

  test('a 50 MB contentHash or bodyShape is refused before it is copied', () => {
    const long = 'Q'.repeat(50_000_000);
    refusedWithin(() => sb.loadRig(hairDoc(), null, { contentHash: long }), { limit: kTypedLimits.maxStringBytes });
    refusedWithin(() => sb.loadRig(hairDoc(), null, { entity: {}, bodyShape: long }), { limit: kTypedLimits.maxStringBytes });
  });

  test('a string one byte past the bound is refused with its path; the bound itself is accepted', () => {
    // 'é' is two UTF-8 bytes: the bound is on bytes, not on UTF-16 units.
    const atBound = 'é'.repeat(kTypedLimits.maxStringBytes / 2);
    assert.ok(encodeTyped('test', { s: atBound }).length > kTypedLimits.maxStringBytes);
    refusedWithin(() => encodeTyped('test', { s: `${atBound}a` }), { limit: kTypedLimits.maxStringBytes, path: '/s' });
    refusedWithin(() => encodeTyped('test', { [`${atBound}a`]: 1 }), { limit: kTypedLimits.maxStringBytes });
  });

  test('a springBones object past 16 MiB as typed input is limit-exceeded, as its text is', () => {
    const bones = {};
    const name = 'n'.repeat(60_000);
    for (let i = 0; i < 300; ++i) bones[`${name}${i}`] = i;
    refusedWithin(() => sb.loadRig(hairDoc(), metadataWith(bones), { contentHash: kHash }),
                  { limit: kTypedLimits.maxMetadataTypedBytes });
  });

  test('a warning quotes a long node name by its first bytes', () => {
    const long = `SpringBone_${'y'.repeat(60_000)}`;
    const doc = hairDoc();
    doc.nodes[2].name = long;
    doc.nodes[1].children = [2];
    const rig = sb.loadRig(doc, metadataWith({ [long]: hairEntry(), SpringBone_hair: hairEntry() }),
                           { contentHash: kHash });
    assert.ok(rig.warnings.length > 0, 'the tip entry is warned about');
    for (const w of rig.warnings) {
      assert.ok(w.message.length < 400, `${w.code}: ${w.message.length} characters`);
    }
    rig.dispose();
  });

  test('the glTF document keeps its own bound: encodeGltf writes nodes a metadata bound would refuse', () => {
    const nodes = Array.from({ length: 300 }, (_, i) => ({ name: `${'m'.repeat(60_000)}${i}` }));
    assert.ok(encodeGltf('test', { asset: { version: '2.0' }, nodes }, false).length > kTypedLimits.maxMetadataTypedBytes);
  });
});
