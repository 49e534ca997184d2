// The Babylon adapter's per-frame work, measured for babylon_simulation.test.mjs in a child
// process (`node --allow-natives-syntax [V8 flags] babylon_frame_heap.mjs <4.2|current>`; one
// Babylon per process, as on a page): two wearables registered with one SpringBoneSimulation, a
// head that moves every frame, and the simulation's before-render callback run by
// notifyObservers. After a warm-up, V8's sampling heap profiler records every allocation of
// 4,000 frames (objects collected since included) and the script prints, as JSON, the bytes
// allocated by each function whose source is in web/babylon/, and the total.
//
// Why by function and not by heap growth (as three_adapter_frame.test.mjs does): Babylon's own
// computeWorldMatrix, which the frame calls to bring the drivers' world matrices up to date,
// allocates by itself in Babylon 4.2, and in the current major in some runs and not others,
// depending on how V8 happened to optimize it; the growth of the heap then says nothing about
// the adapter's code.
import { Session } from 'node:inspector/promises';
import { createSpringBones } from '../../web/springbones.js';
import { SpringBoneSimulation } from '../../web/babylon/index.js';
import { babylonKit, readAsset, readJsonAsset } from './babylon_kit.mjs';

/** The sample wearable twice in one scene, started; returns the frame function. */
export async function twoWearables(which) {
  const sb = await createSpringBones();
  const kit = await babylonKit(which);
  const scene = kit.scene();
  const metadata = readJsonAsset('hair_wearable.metadata.json');
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

async function sampleOwnAllocations(which, { warmup = 20000, frames = 4000 } = {}) {
  const { frame, simulation, scene } = await twoWearables(which);
  // springbones' own scene.step is kept from being inlined into the adapter (with escape analysis
  // off, its WebAssembly call allocates by itself, and inlined it would count as the adapter's):
  // a wrapper V8 never optimizes stands between them (needs --allow-natives-syntax).
  const internals = simulation.internalsForTests;
  const sbScene = internals.sbScene;
  const step = sbScene.step.bind(sbScene);
  const wrapper = { step: (dt) => step(dt) };
  new Function('f', '%NeverOptimizeFunction(f)')(wrapper.step);
  internals.sbScene = wrapper;
  // Warm up, give V8's background compiler time to install the optimized code (a loaded machine
  // delays it), then warm up again.
  for (let i = 0; i < warmup; i++) frame();
  await new Promise((resolve) => setTimeout(resolve, 300));
  for (let i = 0; i < warmup / 4; i++) frame();
  const session = new Session();
  session.connect();
  await session.post('HeapProfiler.enable');
  await session.post('HeapProfiler.startSampling', {
    samplingInterval: 64, includeObjectsCollectedByMajorGC: true, includeObjectsCollectedByMinorGC: true,
  });
  for (let i = 0; i < frames; i++) frame();
  const { profile } = await session.post('HeapProfiler.stopSampling');
  session.disconnect();
  internals.sbScene = sbScene;
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
  const [which] = process.argv.slice(2);
  console.log(JSON.stringify(await sampleOwnAllocations(which)));
}
