// The Babylon adapter's per-frame work, measured for babylon_simulation.test.mjs: two wearables
// registered with one SpringBoneSimulation, a head that moves every frame, and the simulation's
// before-render callback run by notifyObservers (Babylon's render itself allocates, and is not
// ours). Each measurement runs in a child process of its own, so that one Babylon version's
// classes never meet the other's at the same call sites (a page has one Babylon):
// `node --expose-gc babylon_frame_heap.mjs <version> growth` prints the heap growth of 4,000-frame
// windows, each after a full GC; `node --allow-natives-syntax [V8 flags] babylon_frame_heap.mjs
// <version>` samples every allocation of the measured frames (V8's sampling heap profiler, objects
// collected since included) and prints, as JSON, the bytes allocated by each function whose source
// is in web/babylon/: the test runs it with escape analysis off, so that an object a compiler
// would have optimized away is allocated and shows.
import { Session } from 'node:inspector/promises';
import { createSpringBones } from '../../web/springbones.js';
import { SpringBoneSimulation } from '../../web/babylon/index.js';
import { babylonKit, readAsset } from './babylon_kit.mjs';

/** The sample wearable twice in one scene, started; returns the frame function. */
export async function twoWearables(which) {
  const sb = await createSpringBones();
  const kit = await babylonKit(which);
  const scene = kit.scene();
  const metadata = JSON.parse(new TextDecoder().decode(readAsset('hair_wearable.metadata.json')));
  const [hash] = Object.keys(metadata.models);
  const simulation = new SpringBoneSimulation(sb);
  const heads = [];
  for (const itemId of [hash, 'second']) {
    const container = await kit.load(scene, readAsset('hair_wearable.glb'));
    container.addAllToScene();
    simulation.registerWearable(scene, container, itemId, metadata.models[hash]);
    heads.push(container.transformNodes.find((n) => n.name === 'Avatar_Head'));
  }
  simulation.start(scene);
  const angles = [0, 0.3, -0.2, 0.1];  // fixed poses taken in turn: no number computed per frame
  let f = 0;
  const frame = () => {
    f = (f + 1) & 3;
    for (const head of heads) head.position.x = angles[f];
    scene.onBeforeRenderObservable.notifyObservers(scene);
  };
  return { frame, simulation, scene };
}

export async function measureFrameHeap(which, gc, { warmup = 20000, frames = 4000, windows = 5 } = {}) {
  const { frame, simulation, scene } = await twoWearables(which);
  for (let i = 0; i < warmup; i++) frame();
  const growths = [];
  for (let w = 0; w < windows; w++) {
    gc();
    const before = process.memoryUsage().heapUsed;
    for (let i = 0; i < frames; i++) frame();
    growths.push(process.memoryUsage().heapUsed - before);
  }
  simulation.dispose(scene);
  return growths;
}

async function sampleOwnAllocations(which, { warmup = 20000, frames = 4000 } = {}) {
  const { frame, simulation, scene } = await twoWearables(which);
  // springbones' own scene.step is kept from being inlined into the adapter (with escape analysis
  // off, its WebAssembly call allocates by itself, and inlined it would count as the adapter's):
  // a wrapper V8 never optimizes stands between them (needs --allow-natives-syntax).
  const sbScene = simulation._sbScene;
  const step = sbScene.step.bind(sbScene);
  const wrapper = { step: (dt) => step(dt) };
  new Function('f', '%NeverOptimizeFunction(f)')(wrapper.step);
  simulation._sbScene = wrapper;
  for (let i = 0; i < warmup; i++) frame();
  const session = new Session();
  session.connect();
  await session.post('HeapProfiler.enable');
  await session.post('HeapProfiler.startSampling', {
    samplingInterval: 64, includeObjectsCollectedByMajorGC: true, includeObjectsCollectedByMinorGC: true,
  });
  for (let i = 0; i < frames; i++) frame();
  const { profile } = await session.post('HeapProfiler.stopSampling');
  session.disconnect();
  simulation._sbScene = sbScene;
  simulation.dispose(scene);
  const own = {};
  let total = 0;
  const walk = (node) => {
    total += node.selfSize;
    const { url, functionName, lineNumber } = node.callFrame;
    if (node.selfSize > 0 && url.includes('/web/babylon/')) {
      const key = `${functionName} (${url.split('/').pop()}:${lineNumber + 1})`;
      own[key] = (own[key] ?? 0) + node.selfSize;
    }
    node.children.forEach(walk);
  };
  walk(profile.head);
  return { own, total, frames };
}

if (process.argv[1]?.endsWith('babylon_frame_heap.mjs')) {
  const [which, what] = process.argv.slice(2);
  const result = what === 'growth' ? { growths: await measureFrameHeap(which, globalThis.gc) } : await sampleOwnAllocations(which);
  console.log(JSON.stringify(result));
}
