// Dragging the hair with the mouse (Chromium), on the three.js page and the Babylon.js page: a
// press on a chain's tail and a move pull the tail toward the pointer (instance.grab); letting go
// releases it and the hair swings back toward where it hung. On the three.js page Reset settles
// the hair (instance.settle): the next frame of the paused page hardly moves it.
import assert from 'node:assert/strict';
import { after, before, describe, test } from 'node:test';
import { openDemo, skip } from './demo_page.mjs';

const distance = (a, b) => Math.hypot(a.x - b.x, a.y - b.y);

describe('three.js page', { skip }, () => {
  let demo;
  before(async () => {
    demo = await openDemo();
  });
  after(async () => {
    await demo?.close();
  });
  const run = (fn, arg) => demo.page.evaluate(fn, arg);

  test('a press on the ponytail tip drags it toward the pointer; letting go swings it back', async () => {
    await run(() => {
      const d = window.springbonesDemo;
      d.setPaused(true);
      d.setAvatarCount(1);
      d.setView('head');
      d.setAnimation('idle');
      d.reset();
      d.advance(1);
    });
    const names = await run(() => window.springbonesDemo.jointNames());
    // The ponytail's last joint: its tail is the chain's tip, the farthest from the head.
    const joint = names.filter((n) => n.startsWith('SpringBone_ponytail')).at(-1);
    assert.ok(joint, `a ponytail joint among ${names.join(', ')}`);
    const start = await run((name) => window.springbonesDemo.tailOnScreen(name), joint);
    assert.ok(start, 'the tail is drawn');
    const target = { x: start.x + 70, y: start.y - 40 };
    await demo.page.mouse.move(start.x, start.y);
    await demo.page.mouse.down();
    await demo.page.mouse.move(target.x, target.y, { steps: 8 });
    await run(() => window.springbonesDemo.advance(1));
    assert.equal(await run(() => window.springbonesDemo.grabbedJoint()), names.indexOf(joint));
    const held = await run((name) => window.springbonesDemo.tailOnScreen(name), joint);
    assert.ok(distance(held, target) < 0.3 * distance(start, target),
      `the tail followed the pointer: ${distance(held, target).toFixed(1)} px from it, ${distance(start, target).toFixed(1)} at the press`);
    await demo.page.mouse.up();
    assert.equal(await run(() => window.springbonesDemo.grabbedJoint()), -1);
    await run(() => window.springbonesDemo.advance(4));
    const back = await run((name) => window.springbonesDemo.tailOnScreen(name), joint);
    assert.ok(distance(back, start) < 0.3 * distance(start, target),
      `released, it swung back: ${distance(back, start).toFixed(1)} px from where it hung`);
    assert.deepEqual(demo.consoleErrors, []);
  });

  test('Reset settles the hair: the next frame hardly turns it', async () => {
    const turn = await run(() => {
      const d = window.springbonesDemo;
      d.setPaused(true);
      d.setAnimation('idle');
      d.shake();
      d.advance(0.5);
      d.reset();
      const settled = d.rotations();
      d.advance(1 / 60);
      const next = d.rotations();
      let most = 0;
      for (let i = 0; i < settled.length; i += 4) {
        const dot = Math.abs(settled[i] * next[i] + settled[i + 1] * next[i + 1] + settled[i + 2] * next[i + 2] + settled[i + 3] * next[i + 3]);
        most = Math.max(most, 2 * Math.acos(Math.min(1, dot)));
      }
      return most;
    });
    // The idle clip itself moves the head a little in a frame; a fall from rest would be 0.1 rad.
    assert.ok(turn < 0.02, `the frame after Reset turns a joint by ${turn} rad`);
  });
});

describe('Babylon.js page', { skip }, () => {
  let demo;
  before(async () => {
    demo = await openDemo({ page: 'babylon.html', readyHook: 'springbonesBabylonDemo' });
  });
  after(async () => {
    await demo?.close();
  });
  const run = (fn, arg) => demo.page.evaluate(fn, arg);

  test('a press on a tail drags it toward the pointer; letting go releases it', async () => {
    // The ponytail's tip: the tail of its last joint, the farthest from the head.
    const tip = 'SpringBone_ponytail_tip';
    const start = await run((name) => window.springbonesBabylonDemo.tailOnScreen(name), tip);
    assert.ok(start, `${tip} is drawn`);
    const target = { x: start.x - 60, y: start.y - 40 };
    await demo.page.mouse.move(start.x, start.y);
    await demo.page.mouse.down();
    assert.equal(await run(() => window.springbonesBabylonDemo.dragging()), true, 'the press took the tail');
    await demo.page.mouse.move(target.x, target.y, { steps: 8 });
    await demo.page.waitForTimeout(1500);  // the page renders (and steps) on its own
    const held = await run((name) => window.springbonesBabylonDemo.tailOnScreen(name), tip);
    assert.ok(distance(held, target) < 0.5 * distance(start, target),
      `the tail followed the pointer: ${distance(held, target).toFixed(1)} px from it, ${distance(start, target).toFixed(1)} at the press`);
    await demo.page.mouse.up();
    assert.equal(await run(() => window.springbonesBabylonDemo.dragging()), false);
    assert.deepEqual(demo.consoleErrors, []);
  });
});
