// loadRig's options (colliders, hitRadius, avatarBones) have one home per side: web/rig_options.js checks the caller's object, and the
// core's reader of what crosses (readRigOptions, src/boundary/api_json.cpp) checks it by the same
// rules. The same bad options go to both: through loadRig in JavaScript, and as typed input
// straight into the core's loadRig binding, past every JavaScript check. Each side must refuse
// them, JavaScript with a TypeError or RangeError naming the option, the core with
// invalid-argument and a JSON pointer to the same option; what one accepts the other accepts.
// Colliders, hitRadius and limits: the keys that say which models entry applies are resolved
// before anything crosses (models_entry.js), and jumpDistance / jumpAngle stay in JavaScript.
import assert from 'node:assert/strict';
import { before, test } from 'node:test';

import { createSpringBones } from '../../web/springbones.js';
import { takeError } from '../../web/errors.js';
import { instantiateModule } from '../../web/module_loader.js';
import { addRuntimeCalls } from '../../web/runtime_calls.js';
import { encodeGltf, encodeTyped } from '../../web/typed_value.js';
import { withBytes, withRoomForStrings } from '../../web/wasm_memory.js';
import { springRig } from './helpers.mjs';

const rig = springRig();
const head = 'Avatar_Head';  // a node of the rig, not a spring bone
const joint = 'SpringBone_0_0';  // a simulated joint of the rig
const kIdentity = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1];

// Options that are the same object in the caller's form and in the form that crosses (no preset
// name, every collider spelled out), so both sides read exactly the same value.
const kRefused = [
  { hitRadius: -1 },
  { hitRadius: '0.1' },
  { hitRadius: Infinity },
  { colliders: {} },
  { colliders: [null] },
  { colliders: [[head, 0.1]] },
  { colliders: [{ radius: 0.1 }] },
  { colliders: [{ node: '', radius: 0.1 }] },
  { colliders: [{ node: 7, radius: 0.1 }] },
  { colliders: [{ node: head, radius: 0.1, extra: 1 }] },
  { colliders: [{ node: head, shape: 'cube', radius: 0.1 }] },
  { colliders: [{ node: head, shape: 1, radius: 0.1 }] },
  { colliders: [{ node: head, shape: 'sphere', radius: 0.1, tail: [0, 1, 0] }] },
  { colliders: [{ node: head, radius: 0.1, normal: [0, 1, 0] }] },
  { colliders: [{ node: head, shape: 'plane', radius: 0.1 }] },
  { colliders: [{ node: head, shape: 'plane', inside: true }] },
  { colliders: [{ node: head, shape: 'plane', normal: [0, 0, 0] }] },
  { colliders: [{ node: head, shape: 'plane', normal: [0, 1] }] },
  { colliders: [{ node: head }] },
  { colliders: [{ node: head, radius: -0.5 }] },
  { colliders: [{ node: head, radius: NaN }] },
  { colliders: [{ node: head, radius: null }] },
  { colliders: [{ node: head, radius: 0.1, offset: [0, 0] }] },
  { colliders: [{ node: head, radius: 0.1, offset: [0, -Infinity, 0] }] },
  { colliders: [{ node: head, radius: 0.1, offset: 'up' }] },
  { colliders: [{ node: head, radius: 0.1, tail: [1, 2] }] },
  { colliders: [{ node: head, radius: 0.1, tail: null }] },
  { colliders: [{ node: head, radius: 0.1, inside: 'yes' }] },
  { colliders: [{ node: head, radius: 0.1 }, { node: head, radius: 0.1, tail: [0, 1, 0], inside: 1 }] },
  { limits: [] },
  { limits: 5 },
  { limits: { [joint]: 5 } },
  { limits: { [joint]: [] } },
  { limits: { [joint]: {} } },
  { limits: { [joint]: { cone: { angle: 1 }, hinge: { angle: 1 } } } },
  { limits: { [joint]: { box: {} } } },
  { limits: { [joint]: { cone: 5 } } },
  { limits: { [joint]: { cone: {} } } },
  { limits: { [joint]: { cone: { angle: '1' } } } },
  { limits: { [joint]: { cone: { angle: NaN } } } },
  { limits: { [joint]: { cone: { angle: 1, extra: 2 } } } },
  { limits: { [joint]: { hinge: { angle: 1, pitch: 1 } } } },
  { limits: { [joint]: { spherical: { pitch: 1 } } } },
  { limits: { [joint]: { spherical: { pitch: 1, yaw: 1, angle: 1 } } } },
  { limits: { [joint]: { cone: { angle: 1, rotation: [0, 0, 1] } } } },
  { limits: { [joint]: { cone: { angle: 1, rotation: [0, 0, 0, 0] } } } },
  { limits: { [joint]: { cone: { angle: 1, rotation: [0, 0, 0, 'a'] } } } },
  { limits: { [joint]: { cone: { angle: 1, rotation: [0, 0, 0, Infinity] } } } },
  { limits: { 'a "quoted" joint': { cone: { angle: -Infinity } } } },
  { avatarBones: [] },
  { avatarBones: { [head]: [1, 0, 0] } },
  { avatarBones: { [head]: 'identity' } },
  { avatarBones: { [head]: [...kIdentity.slice(0, 15), '1'] } },
  { avatarBones: { [head]: [...kIdentity.slice(0, 15), NaN] } },
  { avatarBones: { [head]: [...kIdentity.slice(0, 12), 1e13, 0, 0, 1] } },
];

const kAccepted = [
  {},
  { hitRadius: 0.02 },
  { hitRadius: 0 },
  { colliders: [] },
  { colliders: [{ node: head, radius: 0.1 }] },
  { colliders: [{ node: head, radius: 0, offset: [0, 0.1, 0], inside: true }] },
  { colliders: [{ node: head, radius: 0.1, tail: [0, 0.2, 0] }] },
  { colliders: [{ node: head, shape: 'capsule', radius: 0.1 }] },
  { colliders: [{ node: head, shape: 'plane' }] },
  { colliders: [{ node: head, shape: 'plane', normal: [0, 1e39, 0], offset: [0, 1, 0] }] },
  { colliders: [{ node: 'Avatar_Hips', radius: 0.2 }], hitRadius: 0.01 },  // a bone the caller supplies
  { limits: {} },
  { limits: { [joint]: { cone: { angle: 0.5 } } } },
  { limits: { [joint]: { hinge: { angle: 7, rotation: [0, 0, 1e20, 1e20] } } } },  // clamped, warned
  { limits: { [joint]: { spherical: { pitch: 0.2, yaw: 0.3, rotation: [0, 0, 0, 1] } } } },
  { limits: { 'no such joint': { cone: { angle: 0.5 } } } },  // warned: limit-joint-not-found
  { avatarBones: {} },
  { avatarBones: { [head]: kIdentity, Avatar_Neck: [...kIdentity.slice(0, 12), 0, 1.5, 0, 1] } },
];

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

// The core's answer to `options` as they cross: null when it loads, else {code, path}.
function coreAnswer(options) {
  const gltf = encodeGltf('test', rig.doc, false);
  const metadata = encodeTyped('test', rig.springBones);
  const typed = encodeTyped('test', options);
  const m = core;
  const handle = withBytes(m, gltf, (gp, gs) => withBytes(m, metadata, (mp, ms) => withBytes(m, typed,
    (op, os) => withRoomForStrings(m, [rig.hash], () => m.loadRig(gp, gs, mp, ms, rig.hash, op, os)))));
  if (handle !== 0) {
    m.disposeRig(handle);
    return null;
  }
  const { code, path, message } = takeError(m);
  return { code, path, message };
}

// JavaScript's answer: null when it loads, else {kind, path} with the option its message names
// ("loadRig: colliders[0].radius must be ...", "loadRig: colliders[0]: unknown option 'extra'")
// as a JSON pointer.
function jsAnswer(options) {
  try {
    sb.loadRig(rig.doc, rig.springBones, { contentHash: rig.hash, ...options }).dispose();
    return null;
  } catch (error) {
    const steps = optionNamed(error.message);
    const unknown = /unknown option '([^']+)'/.exec(error.message);
    if (unknown) steps.push(unknown[1]);
    return { kind: error.constructor.name, path: steps.map((s) => `/${s}`).join(''), message: error.message };
  }
}

// The steps of the option a message begins with, as JavaScript writes a path: `loadRig:
// colliders[0].radius` or `loadRig: limits["a \"quoted\" joint"].cone.angle`.
function optionNamed(message) {
  assert.ok(message.startsWith('loadRig: '), message);
  const steps = [];
  const step = /^(?:\.?([A-Za-z_$][\w$]*)|\[(\d+)\]|\[("(?:[^"\\]|\\.)*")\])/;
  let rest = message.slice('loadRig: '.length);
  for (let m = step.exec(rest); m; rest = rest.slice(m[0].length), m = step.exec(rest)) {
    steps.push(m[1] ?? m[2] ?? JSON.parse(m[3]));
  }
  assert.ok(steps.length > 0, `the message names the option: ${message}`);
  return steps;
}

test('options JavaScript refuses, the core refuses too, naming the same option', () => {
  for (const options of kRefused) {
    const js = jsAnswer(options);
    const native = coreAnswer(options);
    const shown = JSON.stringify(options, (_k, v) => (typeof v === 'number' && !Number.isFinite(v) ? String(v) : v));
    assert.ok(js !== null && ['TypeError', 'RangeError'].includes(js.kind), `JavaScript refuses ${shown}`);
    assert.ok(native !== null, `the core refuses ${shown}`);
    assert.equal(native.code, 'invalid-argument', shown);
    assert.equal(native.path, js.path, `${shown}: the core names ${native.path} (${native.message}), ` +
                 `JavaScript ${js.path} (${js.message})`);
  }
});

test('options JavaScript accepts, the core accepts, with the same colliders', () => {
  for (const options of kAccepted) {
    assert.equal(jsAnswer(options), null, JSON.stringify(options));
    assert.equal(coreAnswer(options), null, JSON.stringify(options));
  }
  // What JavaScript sends for the caller's form is what the core reads from the same form.
  const options = { colliders: [{ node: head, shape: 'plane', normal: [0, 1e39, 0] }, { node: head, radius: 0.1, tail: [0, 0.2, 0] }] };
  const viaJs = sb.loadRig(rig.doc, rig.springBones, { contentHash: rig.hash, ...options });
  assert.deepEqual(viaJs.colliders.map((c) => c.shape), ['plane', 'capsule']);
  assert.deepEqual(Array.from(viaJs.colliders[0].normal), [0, 1, 0]);
});
