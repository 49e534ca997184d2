// A preview opened cold, the way the demo opens: the sample avatar and the sample wearable
// (web/demo/assets: avatar.glb, hair_wearable.glb and its entity), the wearable's spring bones
// simulated by one library. The page around the library is the same for both libraries (this
// module); each library's page passes what is its own:
//   importLibrary()           its JavaScript (timed: "import")
//   start(lib, {priority})    its start-up, e.g. downloading and compiling WebAssembly: a
//                             promise, or null when there is none; called when the page's
//                             fetch order says (below; timed: "start", from the call to its
//                             resolution); priority: the fetch priority to ask for, or undefined
//   wear(lib, item, started)  puts the wearable on the avatar, at once (the avatar wearing it can
//                             be drawn: it must not wait for `started`); returns a promise of
//                             { joints, step(dt), loadMs, details } once the library can simulate
//                             (loadMs: its own loading of the joints, timed by the library)
// As a preview should, the page draws before the library is ready: the first animation frame after
// wear() sets the performance mark 'first-drawable-frame'; the first frame after the simulation is
// ready steps it once and sets 'first-simulated-frame' (startTime: milliseconds since navigation).
// When the library starts is the page's fetch order, the query's `fetch` (scripts/benchmarks/bench_fetch_order.mjs
// compares them; the preload orders also need the link cold_springbones.html adds):
//   after-draw       once the first drawable frame is set (the default): its bytes never share the
//                    link with the GLBs'
//   after-downloads  once the GLBs' bytes are in, before they are parsed
//   at-wear          once they are parsed and the item worn, before the drawing (the adapters' own
//                    order when they start the module themselves)
//   with-glbs        at once, while the GLBs download; with-glbs-low: asking for low priority
//   preload, preload-low  a <link rel=preload> (fetchpriority=low) in the HTML, used after-draw Nothing is rendered: WebGL would cost both pages alike. The result goes to
// window.coldResult (or the error to window.benchError). The pages are not cross-origin isolated
// (as a marketplace's preview iframe is not); the timer's 0.1 ms step is far below what is timed.
import { Group } from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';

const ASSETS = new URL('../../../web/demo/assets/', import.meta.url);
const WEARABLE = 'hair_wearable.glb';

async function fetchBytes(name) {
  const response = await fetch(new URL(name, ASSETS));
  if (!response.ok) throw new Error(`${name}: HTTP ${response.status}`);
  return response.arrayBuffer();
}

const nextFrame = () => new Promise((resolve) => requestAnimationFrame(resolve));

/** Runs the cold start with one library's parts (see the top of this file). */
export async function coldStart(library) {
  try {
    // The page's own downloads start first and run while the library loads, as a page would.
    const downloads = Promise.all([fetchBytes('avatar.glb'), fetchBytes(WEARABLE), fetchBytes('hair_wearable.entity.json')]);
    const order = fetchOrder();
    const times = {};
    let t = performance.now();
    const lib = await library.importLibrary();
    times.importMs = performance.now() - t;
    let startCalledAt = 0;
    let callStart;
    const started = new Promise((resolve) => { callStart = resolve; });
    started.catch(() => {});  // reported where it is awaited
    const startNow = () => {
      startCalledAt = performance.now();
      callStart(library.start(lib, { priority: order.priority }));
    };
    if (order.when === 'with-glbs') startNow();

    const [avatarBuffer, wearableBuffer, entityBuffer] = await downloads;
    if (order.when === 'after-downloads') startNow();
    const entity = JSON.parse(new TextDecoder().decode(entityBuffer));
    const contentHash = entity.content.find((c) => c.file === WEARABLE).hash;
    const springBones = entity.metadata.data.springBones;
    const wearableBytes = new Uint8Array(wearableBuffer.slice(0));  // GLTFLoader may keep views on its copy
    const loader = new GLTFLoader();
    const [avatar, wearable] = await Promise.all([
      loader.parseAsync(avatarBuffer, ASSETS.href), loader.parseAsync(wearableBuffer, ASSETS.href),
    ]);
    const world = new Group();
    world.add(avatar.scene);
    world.updateMatrixWorld(true);

    t = performance.now();
    const simulating = library.wear(lib, { avatar, wearable, wearableBytes, springBones, contentHash }, started);
    times.wearMs = performance.now() - t;
    if (order.when === 'at-wear') startNow();
    await nextFrame();
    world.updateMatrixWorld();
    times.navigationToDrawableMs = performance.mark('first-drawable-frame').startTime;

    if (order.when === 'after-draw') startNow();
    await started;
    times.startMs = performance.now() - startCalledAt;
    const simulation = await simulating;
    times.loadMs = simulation.loadMs;

    await new Promise((resolve, reject) => requestAnimationFrame(() => {
      try {
        world.updateMatrixWorld();
        t = performance.now();
        simulation.step(1 / 60);
        times.stepMs = performance.now() - t;
        times.navigationToFirstFrameMs = performance.mark('first-simulated-frame').startTime;
        resolve();
      } catch (error) {
        reject(error);
      }
    }));
    times.libraryMs = times.importMs + times.startMs + times.wearMs + times.loadMs + times.stepMs;
    times.longestTaskMs = longestTaskBefore(times.navigationToFirstFrameMs);
    window.coldResult = {
      library: library.name, fetchOrder: order.name, joints: simulation.joints, crossOriginIsolated: globalThis.crossOriginIsolated === true,
      ...times, ...(simulation.details ?? {}),
    };
  } catch (error) {
    window.benchError = `${error.message}\n${error.stack ?? ''}`;
  }
}

const kFetchOrders = {
  'after-draw': { when: 'after-draw' },
  'after-downloads': { when: 'after-downloads' },
  'at-wear': { when: 'at-wear' },
  'with-glbs': { when: 'with-glbs' },
  'with-glbs-low': { when: 'with-glbs', priority: 'low' },
  preload: { when: 'after-draw' },
  'preload-low': { when: 'after-draw' },
};

/** The page's fetch order (the query's `fetch`): { name, when, priority }. */
function fetchOrder() {
  const name = new URLSearchParams(location.search).get('fetch') ?? 'after-draw';
  const order = kFetchOrders[name];
  if (!order) throw new Error(`unknown fetch order ${name} (expected ${Object.keys(kFetchOrders).join(', ')})`);
  return { name, ...order };
}

/**
 * The longest main-thread task (PerformanceObserver 'longtask': 50 ms or more, collected from the
 * page's first script by the inline observer in cold_*.html) that started before `until`; 0 when
 * there was none of 50 ms or more.
 */
function longestTaskBefore(until) {
  const tasks = (window.coldLongTasks ?? []).filter((task) => task.startTime < until);
  return tasks.reduce((longest, task) => Math.max(longest, task.duration), 0);
}
