// WebAssembly memory: views survive memory growth, stepping allocates nothing, loading,
// instancing and disposing leak neither memory nor handles, and the heap in use is the bytes asked
// for.
import assert from 'node:assert/strict';
import { before, test } from 'node:test';

import { instantiateModule } from '../../web/module_loader.js';
import { takeTyped } from '../../web/typed_output.js';
import { addRuntimeCalls } from '../../web/runtime_calls.js';
import { createSpringBones } from '../../web/springbones.js';
import { swayDrivers } from '../../bin/sway.mjs';
import { loadFixtureRig, springRig, swayFrames } from './helpers.mjs';

let sb;
before(async () => {
  sb = await createSpringBones();
});

test('views taken before memory growth are rebuilt by the getters, with the same contents', () => {
  const rig = loadFixtureRig(sb, 'avatar_hair.glb');
  const inst = rig.createInstance();
  const rest = swayFrames(inst, 20);
  const oldRotations = inst.rotations;
  const oldDrivers = inst.driverMatrices;
  const rotations = Float32Array.from(oldRotations);
  const drivers = Float32Array.from(oldDrivers);
  const heapBefore = sb.stats().heapBytes;

  const { doc, springBones, hash } = springRig({ chains: 3 });
  // A parsed glTF document crosses into this module's memory as typed input (a GLB's bytes go to
  // the readers' memory): a large one makes it grow. Its size is in node names, each within the
  // bound of a typed string (docs/input.md).
  const name = 'x'.repeat(60000);
  const padding = Array.from({ length: Math.ceil((heapBefore + (8 << 20)) / name.length) }, (_, i) => ({ name: `${name}${i}` }));
  const big = sb.loadRig({ ...doc, nodes: [...doc.nodes, ...padding] }, springBones, { contentHash: hash });
  assert.equal(big.joints.length, 9);
  assert.ok(sb.stats().heapBytes > heapBefore, 'the memory grew');
  assert.equal(oldRotations.byteLength, 0, 'the old view is detached, as any view held across growth');

  assert.notEqual(inst.rotations, oldRotations);
  assert.equal(inst.rotations.length, rotations.length);
  assert.deepEqual(inst.rotations, rotations);
  assert.deepEqual(inst.driverMatrices, drivers);
  // The new views are the live buffers: writes reach the core, steps show up.
  swayDrivers(rest, inst.driverMatrices, 21 / 60);
  inst.step(1 / 60);
  assert.notDeepEqual(inst.rotations, rotations);
  // An instance of the new rig works alongside.
  const other = big.createInstance();
  other.driverMatrices[12] += 0.05;
  other.step(1 / 60);
  assert.ok(other.rotations.every(Number.isFinite));
  for (const x of [inst, other, rig, big]) x.dispose();
});

test('10,000 frames of stepping grow neither the heap nor the handle count', () => {
  const rig = loadFixtureRig(sb, 'avatar_hair.glb');
  const inst = rig.createInstance();
  const rest = Float32Array.from(inst.driverMatrices);
  const scratch = new Float64Array(16);
  const drive = (k) => {
    swayDrivers(rest, inst.driverMatrices, k / 60, scratch);
    inst.step(k % 97 === 0 ? 0.5 : 1 / 60);  // a hitch now and then takes the substep cap
    if (k % 1000 === 0) inst.reset();
  };
  for (let k = 1; k <= 100; ++k) drive(k);
  const before = sb.stats();
  for (let k = 101; k <= 10100; ++k) drive(k);
  const after = sb.stats();
  console.log(`heap ${before.heapBytes} -> ${after.heapBytes} bytes, in use ${before.heapInUse} -> ${after.heapInUse}, ` +
              `handles ${before.rigs + before.instances} -> ${after.rigs + after.instances}`);
  assert.deepEqual(after, before);
  assert.ok(inst.rotations.every(Number.isFinite));
  inst.dispose();
  rig.dispose();
});

test('loading, instancing and disposing 200 times returns every byte and every handle', () => {
  const cycle = () => {
    const rig = loadFixtureRig(sb, 'avatar_hair.glb');
    const a = rig.createInstance();
    const b = rig.createInstance({ stepHz: 90 });
    a.step(1 / 60);
    b.step(1 / 60);
    rig.dispose();  // instances outlive the rig handle
    a.dispose();
    b.dispose();
  };
  cycle();
  const before = sb.stats();
  for (let i = 0; i < 200; ++i) cycle();
  assert.deepEqual(sb.stats(), before);
});

// heapInUse counts what malloc was asked for (wasm/heap_in_use.cpp), not the allocator's blocks:
// an allocator rounds 13 bytes up to a block of 16 or 24, and how much of a split free region a
// block takes depends on the layout before it, so a count of blocks moves without a leak.
test('each module with a stats() counts the bytes asked for, exactly', async () => {
  const modules = [  // the runtime's entry points are plain exports (web/runtime_calls.js), the tools' embind
    ['springbones_wasm.wasm', 'springbones_wasm.js', addRuntimeCalls],
    ['springbones_crowd.wasm', 'springbones_wasm.js', addRuntimeCalls],  // on the runtime's glue
    ['springbones_creator_tools.wasm', 'springbones_creator_tools.js', () => {}],
  ];
  for (const [wasm, glue, addCalls] of modules) {
    const m = await instantiateModule('test', {}, {
      importGlue: () => import(`../../web/dist/${glue}`),
      glueFile: `web/dist/${glue}`,
      defaultUrl: new URL(`../../web/dist/${wasm}`, import.meta.url),
    });
    addCalls(m);
    const inUse = () => takeTyped(m, m.stats()).heapInUse;
    const start = inUse();
    const small = m._malloc(13);
    assert.equal(inUse() - start, 13, `${wasm}: 13 bytes`);
    const large = m._malloc(100001);
    assert.equal(inUse() - start, 100014, `${wasm}: 13 + 100,001 bytes`);
    m._free(small);
    assert.equal(inUse() - start, 100001, `${wasm}: 100,001 bytes after freeing the 13`);
    const again = m._malloc(13);  // into what the 13 left, or not: the same count either way
    m._free(large);
    m._free(again);
    assert.equal(inUse(), start, `${wasm}: back where it started`);
  }
});
