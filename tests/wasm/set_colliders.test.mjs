// instance.setColliders: an instance's colliders changed at run time. The same checks as loadRig's
// colliders on both sides (web/rig_options.js, and the core's reader past every JavaScript check),
// the same warnings, a change that reaches the motion from the next step and only then, a collider
// following a frame the page writes, the 'dcl-body' preset resized and trimmed, and motion bit for
// bit unchanged when the rig's own colliders are given again.
import assert from 'node:assert/strict';
import { before, describe, test } from 'node:test';

import { createSpringBones, SpringBonesError } from '../../web/springbones.js';
import { takeError } from '../../web/errors.js';
import { instantiateModule } from '../../web/module_loader.js';
import { addRuntimeCalls } from '../../web/runtime_calls.js';
import { encodeGltf, encodeTyped } from '../../web/typed_value.js';
import { withBytes, withRoomForStrings } from '../../web/wasm_memory.js';
import { swayDrivers } from '../../bin/sway.mjs';
import { fixture, metadataKeyOf, springRig, swayFrames, tailPositions } from './helpers.mjs';

let sb;
let core;
before(async () => {
  sb = await createSpringBones();
  core = await instantiateModule('test', {}, {
    importGlue: () => import('../../web/dist/springbones_wasm.js'),
    glueFile: 'web/dist/springbones_wasm.js',
    defaultUrl: new URL('../../web/dist/springbones_wasm.wasm', import.meta.url),
  });
  addRuntimeCalls(core);
});

// One chain of three 5 cm bones hanging from Avatar_Head (at y 1.6) at z 0.05: the tails rest at
// y 1.55, 1.50 and 1.45.
const chain = springRig({ chains: 1, joints: 3 });
const head = 'Avatar_Head';
const kIdentity = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1];
// Centred 1 cm beside the middle tail: without a collider that tail sits inside it.
const kOffset = [0.01, -0.1, 0.05];
const kCenter = [0.01, 1.5, 0.05];

function load(options) {
  return sb.loadRig(chain.glb, chain.springBones, { contentHash: chain.hash, ...options });
}

const distance = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
const transform = (m, [x, y, z]) => [m[0] * x + m[4] * y + m[8] * z + m[12], m[1] * x + m[5] * y + m[9] * z + m[13],
  m[2] * x + m[6] * y + m[10] * z + m[14]];

// Sways every instance about `rest` from frame `from` to `to` (bin/sway.mjs), stepping each.
function swayOn(instances, rest, from, to, each = () => {}) {
  for (let k = from; k <= to; ++k) {
    for (const i of instances) {
      swayDrivers(rest, i.driverMatrices, k / 60);
      i.step(1 / 60);
    }
    each(k);
  }
}

// Each pair of (colliders, options) JavaScript refuses; the core must refuse what crosses for it,
// at the same path.
const kRefused = [
  [[{ node: head }], undefined],
  [[{ node: head, radius: -0.5 }], undefined],
  [[{ node: head, radius: NaN }], undefined],
  [[{ node: head, radius: 0.1 }, { node: head, radius: Infinity }], undefined],
  [[{ node: '', radius: 0.1 }], undefined],
  [[{ node: head, radius: 0.1, extra: 1 }], undefined],
  [[{ node: head, shape: 'plane', normal: [0, 0, 0] }], undefined],
  [[{ node: head, radius: 0.1, offset: [0, 0] }], undefined],
  [[{ node: head, shape: 'sphere', radius: 0.1, tail: [0, 1, 0] }], undefined],
  ['dcl-body', { scale: -1 }],
  ['dcl-body', { scale: NaN }],
  ['dcl-body', { scale: '2' }],
  ['dcl-body', { omit: ['hat'] }],
  ['dcl-body', { omit: [3] }],
  ['dcl-body', { avatarBones: { [head]: [1, 0, 0] } }],
  ['dcl-body', { avatarBones: { [head]: [...kIdentity.slice(0, 15), NaN] } }],
  [[{ node: head, radius: 0.1 }], { scale: 0.5 }],
  [[], { omit: ['head'] }],
];

// The typed input JavaScript would send for (colliders, options), sent straight to the core.
function typedOf(colliders, options = {}) {
  if (typeof colliders === 'string') return { preset: colliders, ...options };
  return colliders === null ? { ...options } : { colliders, ...options };
}

// The core's answer: null when it takes the colliders, else {code, path, message}.
function coreAnswer(typed) {
  const m = core;
  const gltf = encodeGltf('test', chain.doc, false);
  const metadata = encodeTyped('test', chain.springBones);
  const rig = withBytes(m, gltf, (gp, gs) => withBytes(m, metadata, (mp, ms) => withBytes(m, new Uint8Array(0),
    (op, os) => withRoomForStrings(m, [chain.hash], () => m.loadRig(gp, gs, mp, ms, chain.hash, op, os)))));
  assert.notEqual(rig, 0);
  const instance = m.createInstance(rig, 0, 0, 0, 4);
  try {
    const text = withBytes(m, encodeTyped('test', typed), (p, s) => m.setColliders(instance, p, s));
    if (text !== '') return null;
    const { code, path, message } = takeError(m);
    return { code, path, message };
  } finally {
    m.disposeInstance(instance);
    m.disposeRig(rig);
  }
}

// JavaScript's answer: null when it takes them, else {kind, path} of the option its message names
// ("setColliders: colliders[0].radius must be ...") as a JSON pointer.
function jsAnswer(colliders, options) {
  const instance = load().createInstance();
  try {
    instance.setColliders(colliders, options);
    return null;
  } catch (error) {
    const prefix = 'setColliders: ';
    assert.ok(error.message.startsWith(prefix), error.message);
    const steps = [];
    const step = /^(?:\.?([A-Za-z_$][\w$]*)|\[(\d+)\])/;
    let rest = error.message.slice(prefix.length);
    for (let m = step.exec(rest); m; rest = rest.slice(m[0].length), m = step.exec(rest)) steps.push(m[1] ?? m[2]);
    const unknown = /unknown option '([^']+)'/.exec(error.message);
    if (unknown) steps.push(unknown[1]);
    return { kind: error.constructor.name, path: steps.map((s) => `/${s}`).join(''), message: error.message };
  } finally {
    instance.dispose();
  }
}

describe('the checks', () => {
  test('what JavaScript refuses, the core refuses too, naming the same value', () => {
    for (const [colliders, options] of kRefused) {
      const shown = JSON.stringify([colliders, options], (_k, v) => (typeof v === 'number' && !Number.isFinite(v) ? String(v) : v));
      const js = jsAnswer(colliders, options);
      assert.ok(js !== null && ['TypeError', 'RangeError'].includes(js.kind), `JavaScript refuses ${shown}`);
      const native = coreAnswer(typedOf(colliders, options));
      assert.ok(native !== null, `the core refuses ${shown}`);
      assert.equal(native.code, 'invalid-argument', shown);
      assert.ok(native.message.startsWith('setColliders: '), native.message);
      assert.equal(native.path, js.path, `${shown}: the core names ${native.path} (${native.message}), JavaScript ${js.path} (${js.message})`);
    }
  });

  test('what JavaScript takes, the core takes', () => {
    const accepted = [[null], [[]], [[{ node: head, radius: 0.1 }]], [[{ node: 'hat', shape: 'plane', normal: [0, 1e39, 0] }]],
      ['dcl-body'], ['dcl-body', { scale: 0.5, omit: ['head', 'left-upper-arm'] }], ['dcl-body', { avatarBones: { [head]: kIdentity } }]];
    for (const [colliders, options] of accepted) {
      assert.equal(jsAnswer(colliders, options), null, JSON.stringify([colliders, options]));
      assert.equal(coreAnswer(typedOf(colliders, options)), null, JSON.stringify([colliders, options]));
    }
  });

  test('colliders must be given: an array, a preset or null', () => {
    const instance = load().createInstance();
    assert.throws(() => instance.setColliders(), TypeError);
    assert.throws(() => instance.setColliders({ node: head, radius: 0.1 }), TypeError);
    assert.throws(() => instance.setColliders('dcl-hat'), RangeError);
    assert.throws(() => instance.setColliders(null, { extra: 1 }), /unknown option 'extra'/);
    instance.dispose();
    assert.throws(() => instance.setColliders(null), (e) => e instanceof SpringBonesError && e.code === 'disposed');
  });

  test("shapes the core ignores come back as the rig's warnings, frozen", () => {
    const rig = load();
    const instance = rig.createInstance();
    // 1e39 is finite here and infinite in float: loadRig warns the same (colliders.test.mjs).
    const warnings = instance.setColliders([{ node: head, radius: 1e39 }, { node: 'SpringBone_0_1', radius: 0.1 },
      { node: head, radius: 0.01 }]);
    assert.deepEqual(warnings.map((w) => w.code), ['collider-invalid', 'collider-on-spring-bone']);
    assert.ok(Object.isFrozen(warnings) && Object.isFrozen(warnings[0]));
    const viaLoad = load({ colliders: [{ node: head, radius: 1e39 }, { node: 'SpringBone_0_1', radius: 0.1 }] });
    assert.deepEqual(viaLoad.warnings.map((w) => [w.code, w.message]), warnings.map((w) => [w.code, w.message]));
    // A huge scale makes every body radius infinite: each shape is left out the same way.
    const body = instance.setColliders('dcl-body', { scale: 1e39, avatarBones: { [head]: kIdentity } });
    assert.ok(body.every((w) => ['collider-invalid', 'body-collider-skipped'].includes(w.code)), JSON.stringify(body));
    swayFrames(instance, 60);
    assert.ok(instance.rotations.every(Number.isFinite));
  });
});

describe('the motion', () => {
  test("the rig's own colliders given again move the tails bit for bit, on the lanes and on XPBD", () => {
    const colliders = [{ node: head, offset: kOffset, radius: 0.03 }];
    const rig = load({ colliders, hitRadius: 0.01 });
    for (const integrator of ['vrm', 'xpbd']) {
      const a = rig.createInstance({ integrator });
      const b = rig.createInstance({ integrator });
      const rest = swayFrames(a, 30);
      swayFrames(b, 30);
      assert.deepEqual(b.setColliders(colliders), []);
      assert.deepEqual(b.frameNames, []);
      swayOn([a, b], rest, 31, 240, (k) => {
        assert.deepEqual(Array.from(b.rotations), Array.from(a.rotations), `${integrator} frame ${k}`);
      });
    }
  });

  test('a collider resized mid-motion changes the motion from the next step, and only then', () => {
    const rig = load({ colliders: [{ node: head, offset: kOffset, radius: 0.01 }] });
    const a = rig.createInstance();
    const b = rig.createInstance();
    swayFrames(a, 45);
    swayFrames(b, 45);
    b.setColliders([{ node: head, offset: kOffset, radius: 0.03 }]);
    assert.deepEqual(Array.from(b.rotations), Array.from(a.rotations), 'setColliders itself moves nothing');
    a.step(1 / 60);
    b.step(1 / 60);
    assert.notDeepEqual(Array.from(b.rotations), Array.from(a.rotations), 'the next step meets the bigger sphere');
    for (let k = 0; k < 120; ++k) b.step(1 / 60);
    const center = transform(b.driverMatrices.subarray(0, 16), kOffset);
    assert.ok(tailPositions(rig, b).every((t) => distance(t, center) > 0.03 - 0.003), 'every tail ends outside the bigger sphere');
  });

  test("a collider following a page's matrix pushes the tail out of where the page puts it", () => {
    const rig = load();
    const free = rig.createInstance();
    for (let k = 0; k < 120; ++k) free.step(1 / 60);
    assert.ok(distance(tailPositions(rig, free)[1], kCenter) < 0.011, 'without the collider the tail sits inside the sphere');

    const instance = rig.createInstance();
    assert.deepEqual(instance.setColliders([{ node: 'hat', radius: 0.03 }]), []);
    assert.deepEqual(instance.frameNames, ['hat']);
    assert.deepEqual(Array.from(instance.frameMatrices), kIdentity, 'a frame starts at the identity');
    const frame = instance.frameMatrices;
    for (let k = 0; k < 120; ++k) {
      frame.set(kIdentity);
      frame.set(kCenter, 12);  // the hat's world matrix, written each frame without allocating
      instance.step(1 / 60);
    }
    assert.ok(tailPositions(rig, instance).every((t) => distance(t, kCenter) > 0.03 - 0.003), JSON.stringify(tailPositions(rig, instance)));
    // The frame is gone with the next set; null leaves the tails free again.
    instance.setColliders(null);
    assert.deepEqual(instance.frameNames, []);
    assert.equal(instance.frameMatrices.length, 0);
    for (let k = 0; k < 240; ++k) instance.step(1 / 60);
    assert.ok(distance(tailPositions(rig, instance)[1], kCenter) < 0.011, 'without colliders the tail falls back inside');
  });

  test("'dcl-body' per instance: the same preset moves bit for bit, a scaled one differently", () => {
    const key = metadataKeyOf('avatar_hair.glb');
    const metadata = fixture('avatar_hair.metadata.json').toString('utf8');
    const rig = sb.loadRig(fixture('avatar_hair.glb'), metadata, { contentHash: key, colliders: 'dcl-body', hitRadius: 0.01 });
    assert.equal(rig.colliders.length, 8);
    const [a, b, c] = [rig.createInstance(), rig.createInstance(), rig.createInstance()];
    assert.deepEqual(b.setColliders('dcl-body'), []);
    assert.deepEqual(c.setColliders('dcl-body', { scale: 1.5, omit: ['left-upper-arm'] }), []);
    swayFrames(a, 120);
    swayFrames(b, 120);
    swayFrames(c, 120);
    assert.deepEqual(Array.from(b.rotations), Array.from(a.rotations));
    assert.notDeepEqual(Array.from(c.rotations), Array.from(a.rotations));
    assert.ok(c.rotations.every(Number.isFinite));
  });
});
