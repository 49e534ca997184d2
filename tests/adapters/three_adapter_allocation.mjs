// Child process of three_adapter_frame.test.mjs: measures the heap bytes that the three.js
// adapter's frame (one attachment.update and one group.update of three attachments, the demo's
// sample avatar and wearable) allocates per frame, in the V8 tier its flags select, and prints one
// JSON line. Run as
//   node --expose-gc --min-semi-space-size=64 --max-semi-space-size=64 [tier flags] this-file [--inject]
// The large new space keeps every window free of scavenges, so heapUsed only grows and the growth
// is exactly what the window allocated (plus the few bytes the measurement itself costs).
//
// Two frames are measured, in the same process and tier:
//   adapter    attachment.update(dt) and group.update(dt), what a page calls;
//   reference  the same instance.step / scene.step calls, plus one read of every float the
//              adapter copies (each driver matrixWorld element, each instance rotation).
// With the optimizing compiler off (Ignition and Sparkplug: no escape analysis, no unboxing), a
// float read from an array costs a 16-byte heap number, and Emscripten's embind invoker behind
// step() makes its `arguments` object: both frames allocate those alike, and nothing else may
// differ. Any temporary of the adapter's own (an object, array, closure, iterator, rest or
// destructured arguments) shows as adapter > reference, on every frame, whatever the machine's
// speed or load. `--inject` adds one small object per adapter frame, to show that it is seen.
import { getHeapSpaceStatistics } from 'node:v8';
import { AnimationMixer, Scene } from 'three';
import * as SkeletonUtils from 'three/examples/jsm/utils/SkeletonUtils.js';
import { loadSampleWearable } from '../wasm/sample_wearable.mjs';
import { SpringBonesGroup, attachWearable, wearableNodes } from '../../web/three/springBonesThree.js';

const DT = 1 / 60;
const WARMUP = Number(process.env.WARMUP_FRAMES ?? 20000);
const FRAMES = 4000;
const WINDOWS = 5;
const inject = process.argv.includes('--inject');

if (typeof globalThis.gc !== 'function') throw new Error('run with --expose-gc');
const { sb, avatarGltf, wearableGltf, rig } = await loadSampleWearable();

const scene = new Scene();
const walkers = [0, 1, 2, 3].map((x) => {
  const avatarRoot = SkeletonUtils.clone(avatarGltf.scene);
  avatarRoot.position.x = x;
  scene.add(avatarRoot);
  const wearable = SkeletonUtils.clone(wearableGltf.scene);
  const attachment = attachWearable(avatarRoot, wearable, rig, { nodes: wearableNodes(wearableGltf, wearable), instance: { stepHz: 60 } });
  const mixer = new AnimationMixer(avatarRoot);
  mixer.clipAction(avatarGltf.animations.find((c) => c.name === 'walk')).play();
  return { avatarRoot, attachment, mixer };
});
// A walked pose: the matrices and rotations hold ordinary non-integer values.
for (let f = 0; f < 30; f++) {
  for (const w of walkers) w.mixer.update(DT);
  scene.updateMatrixWorld();
  for (const w of walkers) w.attachment.update(DT);
}
scene.updateMatrixWorld();

const single = walkers[0].attachment;
const group = new SpringBonesGroup(sb);
for (const w of walkers.slice(1)) group.add(w.attachment);
const attachments = walkers.map((w) => w.attachment);
const driverArrays = attachments.map((a) => a.driverObjects.filter((o) => o !== null).map((o) => o.matrixWorld.elements));
const rootArrays = walkers.slice(1).map((w) => w.avatarRoot.matrixWorld.elements);

let sink = null;
function adapterFrame() {
  single.update(DT);
  group.update(DT);
  if (inject) sink = { frame: 1 };
}

let floatSink = 0;
function referenceFrame() {
  single.instance.step(DT);
  group.scene.step(DT);
  for (let i = 0; i < attachments.length; i++) {
    const arrays = driverArrays[i];
    for (let d = 0; d < arrays.length; d++) {
      const e = arrays[d];
      for (let k = 0; k < 16; k++) floatSink = e[k];
    }
    const r = attachments[i].instance.rotations;
    for (let k = 0; k < r.length; k++) floatSink = r[k];
  }
  for (let i = 0; i < rootArrays.length; i++) {
    const e = rootArrays[i];
    floatSink = e[12]; floatSink = e[13]; floatSink = e[14];
  }
}

const newSpace = getHeapSpaceStatistics().findIndex((s) => s.space_name === 'new_space');
const newSpaceUsed = () => getHeapSpaceStatistics()[newSpace].space_used_size;

function run(frame, frames) {
  for (let f = 0; f < frames; f++) frame();
}

/** Heap growth per frame over each of WINDOWS windows of FRAMES frames, each after a full GC. */
function windows(frame) {
  const perFrame = [];
  for (let w = 0; w < WINDOWS; w++) {
    globalThis.gc();  // --expose-gc
    const before = newSpaceUsed();
    run(frame, FRAMES);
    perFrame.push((newSpaceUsed() - before) / FRAMES);
  }
  return perFrame;
}

run(adapterFrame, WARMUP);
run(referenceFrame, WARMUP);
const result = { adapter: windows(adapterFrame), reference: windows(referenceFrame), frames: FRAMES };
group.dispose();
for (const a of attachments) a.dispose();
console.log(JSON.stringify({ ...result, sink: sink !== null, floatSink: Number.isFinite(floatSink) }));
