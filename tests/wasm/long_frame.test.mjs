// step(16) where step(0.016) was meant: a frame of more than a second is clamped by the substep
// cap, so the hair moves in slow motion and nothing said why. The API warns once per module, on
// the console, and says what the clamp does and what the frame would be in seconds.
import assert from 'node:assert/strict';
import { test } from 'node:test';

import { createSpringBones } from '../../web/springbones.js';
import { springRig } from './helpers.mjs';

// Runs `fn` with console.warn collected instead of printed.
function warnings(fn) {
  const printed = [];
  const saved = console.warn;
  console.warn = (...args) => printed.push(args.join(' '));
  try {
    fn();
  } finally {
    console.warn = saved;
  }
  return printed;
}

async function instanceOfNewModule(options) {
  const sb = await createSpringBones();
  const { doc, springBones, hash } = springRig();
  return { sb, instance: sb.loadRig(doc, springBones, { contentHash: hash }).createInstance(options) };
}

test('step(16) warns once that a frame over 1 s is clamped by the substep cap, and the clamp is real', async () => {
  const { instance } = await instanceOfNewModule({ maxSubsteps: 3 });
  const said = warnings(() => {
    instance.step(1 / 60);
    instance.step(1);  // a second exactly: no warning
    instance.step(16);
  });
  assert.equal(said.length, 1, said.join('\n'));
  assert.match(said[0], /step\(16\)/);
  assert.match(said[0], /more than 1 s/);
  assert.match(said[0], /clamped by that substep cap/);
  assert.match(said[0], /milliseconds, pass 0\.016/);
  // What the warning says: the frame ran the cap's steps, not 16 s of them (960 at 60 Hz).
  assert.equal(instance.lastSteps, 3);
  assert.deepEqual(warnings(() => instance.step(16)), [], 'said once per module');
});

test('scene.step says it too, once for its module; another module says it again', async () => {
  const first = await instanceOfNewModule();
  const scene = first.sb.createScene();
  scene.add(first.instance);
  const fromScene = warnings(() => {
    scene.step(0.5);
    scene.step(33);
    scene.step(33);
    first.instance.step(20);  // the same module: already said
  });
  assert.equal(fromScene.length, 1, fromScene.join('\n'));
  assert.match(fromScene[0], /scene\.step\(33\).*pass 0\.033/);
  const second = await instanceOfNewModule();
  assert.equal(warnings(() => second.instance.step(2)).length, 1);
});

test('frames of 1 s or less, zero and negative frames say nothing', async () => {
  const { instance } = await instanceOfNewModule();
  assert.deepEqual(warnings(() => {
    for (const dt of [0, -5, 1e-9, 0.25, 1]) instance.step(dt);
  }), []);
});
