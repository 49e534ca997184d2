// Jumps in the demo (Chromium): its walk, idle, spin and shake are motion, never a jump (the
// instances' count stays 0); a change of clip, an AnimationMixer action starting, is one per
// avatar, announced by the three.js adapter, and the hair does not whip across it.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { turnAt } from '../../scripts/lib/fixtures/vec.mjs';
import { skip, useDemoPage } from './demo_page.mjs';

let page;
let consoleErrors;
useDemoPage((demo) => ({ page, consoleErrors } = demo));

const demo = (fn, arg) => page.evaluate(fn, arg);

test("the demo's motions are no jumps; a change of clip is one", { skip }, async () => {
  await demo(() => {
    const d = window.springbonesDemo;
    d.setPaused(true);
    d.setAvatarCount(1);
    d.reset();
  });
  for (const clip of ['walk', 'idle']) {
    await demo((name) => {
      const d = window.springbonesDemo;
      d.setAnimation(name);
      d.advance(1);
    }, clip);
    const before = (await demo(() => window.springbonesDemo.state())).jumps;
    await demo(() => {
      const d = window.springbonesDemo;
      d.advance(3);           // the clip alone
      d.setSpin(true);
      d.advance(3);           // spinning at 120 degrees per second
      d.setSpin(false);
      d.shake();
      d.advance(2);           // the whole shake
      d.shake();
      d.setSpin(true);
      d.advance(2);           // shaken while spinning
      d.setSpin(false);
    });
    const state = await demo(() => window.springbonesDemo.state());
    assert.equal(state.jumps, before, `${clip}: no jump from the clip, the spin or the shake`);
  }
  // The change of clip above was one jump (the idle action starting); one more now.
  const before = (await demo(() => window.springbonesDemo.state())).jumps;
  const rotations = await demo(() => {
    const d = window.springbonesDemo;
    d.setAnimation('walk');
    const out = [];
    for (let f = 0; f < 30; f++) {
      d.advance(1 / 60);
      out.push(d.rotations());
    }
    return out;
  });
  assert.equal((await demo(() => window.springbonesDemo.state())).jumps, before + 1);
  // Carried, not whipped: no joint turns by more than 0.1 rad in a frame (a whip is 1-3 rad).
  for (let f = 1; f < rotations.length; f++) {
    for (let i = 0; i < rotations[f].length; i += 4) {
      assert.ok(turnAt(rotations[f - 1], rotations[f], i) < 0.1, `frame ${f}, joint ${i / 4}`);
    }
  }
  assert.deepEqual(consoleErrors, []);
});
