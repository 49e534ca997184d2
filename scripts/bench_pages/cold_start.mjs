// A preview opened cold, the way the demo opens: the sample avatar and the sample wearable
// (web/demo/assets: avatar.glb, hair_wearable.glb and its entity), the wearable's spring bones
// simulated by one library. The page around the library is the same for both libraries (this
// module); each library's page passes what is its own:
//   importLibrary()           its JavaScript (timed: "import")
//   start(lib)                its start-up, e.g. downloading and compiling WebAssembly: a
//                             promise, or null when there is none; called once the first
//                             drawable frame is set (timed: "start", from the call to its
//                             resolution)
//   wear(lib, item, started)  puts the wearable on the avatar, at once (the avatar wearing it can
//                             be drawn: it must not wait for `started`); returns a promise of
//                             { joints, step(dt), loadMs, details } once the library can simulate
//                             (loadMs: its own loading of the joints, timed by the library)
// As a preview should, the page draws before the library is ready, and the library's start
// (its download and compilation) comes after the drawing, so that on a slow link its bytes do not
// share the bandwidth with the GLBs' and on a fast one its compilation does not hold the main
// thread while they are parsed: the first animation frame after wear() sets the performance mark
// 'first-drawable-frame', then start(lib) is called; the first frame after the
// simulation is ready steps it once and sets 'first-simulated-frame' (startTime: milliseconds
// since navigation). Nothing is rendered: WebGL would cost both pages alike. The result goes to
// window.coldResult (or the error to window.benchError). The pages are not cross-origin isolated
// (as a marketplace's preview iframe is not); the timer's 0.1 ms step is far below what is timed.
import { Group } from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';

const ASSETS = new URL('../../web/demo/assets/', import.meta.url);
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
    const times = {};
    let t = performance.now();
    const lib = await library.importLibrary();
    times.importMs = performance.now() - t;
    let callStart;
    const started = new Promise((resolve) => { callStart = resolve; });
    started.catch(() => {});  // reported where it is awaited

    const [avatarBuffer, wearableBuffer, entityBuffer] = await downloads;
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
    await nextFrame();
    world.updateMatrixWorld();
    times.navigationToDrawableMs = performance.mark('first-drawable-frame').startTime;

    t = performance.now();
    callStart(library.start(lib));
    await started;
    times.startMs = performance.now() - t;
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
      library: library.name, joints: simulation.joints, crossOriginIsolated: globalThis.crossOriginIsolated === true,
      ...times, ...(simulation.details ?? {}),
    };
  } catch (error) {
    window.benchError = `${error.message}\n${error.stack ?? ''}`;
  }
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
