// A preview opened cold, the way the demo opens: the sample avatar and the sample wearable
// (web/demo/assets: avatar.glb, hair_wearable.glb and its entity), the wearable's spring bones
// simulated by one library, one frame. The page around the library is the same for both
// libraries (this module); each library's page passes what is its own:
//   importLibrary()  its JavaScript (timed: "import")
//   start(lib)       its start-up, e.g. compiling WebAssembly (timed: "start")
//   load(lib, item)  its joints on the loaded scene (timed: "load"); returns { joints, step(dt) }
// and its first step(dt) is timed inside the first animation frame, which then sets the
// performance mark 'first-simulated-frame' (its startTime: milliseconds since navigation).
// Nothing is rendered: WebGL would cost both pages alike. The result goes to window.coldResult
// (or the error to window.benchError).
import { Group } from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { requireIsolation } from './conditions.mjs';

const ASSETS = new URL('../../web/demo/assets/', import.meta.url);
const WEARABLE = 'hair_wearable.glb';

async function fetchBytes(name) {
  const response = await fetch(new URL(name, ASSETS));
  if (!response.ok) throw new Error(`${name}: HTTP ${response.status}`);
  return response.arrayBuffer();
}

/** Runs the cold start with one library's parts (see the top of this file). */
export async function coldStart(library) {
  try {
    requireIsolation();
    // The page's own downloads start first and run while the library loads, as a page would.
    const downloads = Promise.all([fetchBytes('avatar.glb'), fetchBytes(WEARABLE), fetchBytes('hair_wearable.entity.json')]);
    const times = {};
    let t = performance.now();
    const lib = await library.importLibrary();
    times.importMs = performance.now() - t;
    t = performance.now();
    await library.start(lib);
    times.startMs = performance.now() - t;

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
    const simulation = await library.load(lib, { avatar, wearable, wearableBytes, springBones, contentHash });
    times.loadMs = performance.now() - t;

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
    times.libraryMs = times.importMs + times.startMs + times.loadMs + times.stepMs;
    window.coldResult = { library: library.name, joints: simulation.joints, ...times, ...(simulation.details ?? {}) };
  } catch (error) {
    window.benchError = `${error.message}\n${error.stack ?? ''}`;
  }
}
