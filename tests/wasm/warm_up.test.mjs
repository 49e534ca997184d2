// The idle warm-up (web/warm_up.js) runs the load path a preview takes: a parsed glTF, a rig, an
// instance, one step that moves a joint. It must not throw (it once handed loadRig GLB bytes,
// which need the readers module a preview never loads, and an empty catch hid it), and whatever
// stops it is kept where a test or a page can see it. tests/browser/warm_up.test.mjs runs it in
// Chromium without the readers module.
import assert from 'node:assert/strict';
import { afterEach, test } from 'node:test';

import { createSpringBones } from '../../web/springbones.js';
import { warmUp, warmUpOutcome, warmUpWhenIdle } from '../../web/warm_up.js';

const sb = await createSpringBones();

// Node has no requestIdleCallback: a test installs one that queues the callback, and runs it.
let idleCallbacks = [];
const runIdleCallbacks = () => {
  const callbacks = idleCallbacks;
  idleCallbacks = [];
  for (const callback of callbacks) callback({ didTimeout: false, timeRemaining: () => 50 });
};
afterEach(() => {
  delete globalThis.requestIdleCallback;
  idleCallbacks = [];
});
const installIdleCallback = () => {
  globalThis.requestIdleCallback = (callback) => idleCallbacks.push(callback);
};

// The API with its loadRig watched: what the warm-up hands it.
function watched(api) {
  const calls = [];
  const proxy = new Proxy(api, {
    get(target, key) {
      const value = Reflect.get(target, key, target);
      if (key !== 'loadRig') return typeof value === 'function' ? value.bind(target) : value;
      return (...args) => {
        calls.push(args);
        return value.apply(target, args);
      };
    },
  });
  return { proxy, calls };
}

test('warmUp loads a parsed glTF (no bytes, so no readers), and its step turns a joint', () => {
  const { proxy, calls } = watched(sb);
  const report = warmUp(proxy);
  assert.equal(calls.length, 1);
  const [gltf] = calls[0];
  assert.ok(!ArrayBuffer.isView(gltf) && !(gltf instanceof ArrayBuffer), 'the glTF crosses as a parsed object');
  assert.equal(typeof gltf, 'object');
  assert.ok(report.joints >= 1, `the rig has joints (${report.joints})`);
  assert.ok(report.turned > 0, `the step turned the first joint (by ${report.turned})`);
});

test('warmUp frees what it made: the heap in use returns to where it was', () => {
  warmUp(sb);  // anything allocated once, on a first use, is allocated now
  const before = sb.stats().heapInUse;
  warmUp(sb);
  assert.equal(sb.stats().heapInUse, before);
});

test('the idle warm-up keeps its report once the page is idle, and nothing before', () => {
  installIdleCallback();
  warmUpWhenIdle(sb);
  assert.equal(warmUpOutcome(sb), undefined, 'nothing runs before the idle period');
  assert.equal(idleCallbacks.length, 1);
  runIdleCallbacks();
  const outcome = warmUpOutcome(sb);
  assert.equal(outcome.error, undefined, `the warm-up failed: ${outcome.error?.stack}`);
  assert.ok(outcome.report.joints >= 1 && outcome.report.turned > 0);
});

test('createSpringBones schedules the warm-up where there is idle time, and it succeeds', async () => {
  installIdleCallback();
  const fresh = await createSpringBones();
  assert.equal(idleCallbacks.length, 1, 'one idle callback requested');
  runIdleCallbacks();
  assert.equal(warmUpOutcome(fresh).error, undefined, `the warm-up failed: ${warmUpOutcome(fresh).error?.stack}`);
  assert.ok(warmUpOutcome(fresh).report.turned > 0);
});

test('a warm-up that throws leaves the error in its outcome, and the page goes on', () => {
  installIdleCallback();
  const failure = new Error('no module');
  const broken = { loadRig: () => { throw failure; } };
  warmUpWhenIdle(broken);
  assert.doesNotThrow(runIdleCallbacks);
  assert.deepEqual(warmUpOutcome(broken), { error: failure });
});

test('without requestIdleCallback (Node) nothing is scheduled', () => {
  const api = { loadRig: () => assert.fail('the warm-up ran') };
  warmUpWhenIdle(api);
  assert.equal(warmUpOutcome(api), undefined);
});
