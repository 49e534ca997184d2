// The first loadRig of a preview, after the page sat idle for a second: the module started, the
// sample wearable (web/demo/assets) parsed by GLTFLoader, one idle second (where the API's idle
// warm-up runs, web/warm_up.js), then loadRig of the parsed glTF, createInstance and a first
// step, each timed. With ?warmup=off the page takes requestIdleCallback away before the API is
// imported, so the same page runs without the warm-up. The result goes to window.firstLoad (or the
// error to window.benchError).
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';

const ASSETS = new URL('../../../web/demo/assets/', import.meta.url);
const WEARABLE = 'hair_wearable.glb';
const IDLE_MS = 1000;

async function fetchBytes(name) {
  const response = await fetch(new URL(name, ASSETS));
  if (!response.ok) throw new Error(`${name}: HTTP ${response.status}`);
  return response.arrayBuffer();
}

async function run() {
  const warmUp = new URLSearchParams(location.search).get('warmup') !== 'off';
  if (!warmUp) window.requestIdleCallback = undefined;
  const [{ createSpringBones }, wearableBuffer, entityBuffer] = await Promise.all([
    import('/web/springbones.js'), fetchBytes(WEARABLE), fetchBytes('hair_wearable.entity.json'),
  ]);
  const sb = await createSpringBones();
  const entity = JSON.parse(new TextDecoder().decode(entityBuffer));
  const contentHash = entity.content.find((c) => c.file === WEARABLE).hash;
  const springBones = entity.metadata.data.springBones;
  const wearable = await new GLTFLoader().parseAsync(wearableBuffer, ASSETS.href);
  await new Promise((resolve) => setTimeout(resolve, IDLE_MS));
  let t = performance.now();
  const rig = sb.loadRig(wearable.parser.json, springBones, { contentHash });
  const loadRigMs = performance.now() - t;
  t = performance.now();
  const instance = rig.createInstance();
  const createInstanceMs = performance.now() - t;
  instance.driverMatrices[12] += 0.01;
  t = performance.now();
  instance.step(1 / 60);
  const firstStepMs = performance.now() - t;
  return { warmUp, joints: rig.joints.length, loadRigMs, createInstanceMs, firstStepMs };
}

run().then((result) => { window.firstLoad = result; }, (error) => { window.benchError = String(error?.stack ?? error); });
