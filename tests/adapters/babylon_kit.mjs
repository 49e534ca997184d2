// Babylon.js in Node for the adapter's tests: the same small kit over Babylon 4.2 (the UMD
// package `babylonjs` with `babylonjs-loaders`, what Decentraland's preview pins; its ES modules
// do not load in Node) and the current major (@babylonjs/core + @babylonjs/loaders): a
// NullEngine scene and the demo's sample loaded into AssetContainers by Babylon's own glTF loader.
import { readFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const require = createRequire(import.meta.url);
const assets = join(dirname(fileURLToPath(import.meta.url)), '..', '..', 'web', 'demo', 'assets');
export const readAsset = (name) => new Uint8Array(readFileSync(join(assets, name)));
/** A JSON file of the demo's assets, parsed. */
export const readJsonAsset = (name) => JSON.parse(readFileSync(join(assets, name), 'utf8'));

/** Babylon 4.2 from its UMD build: the global BABYLON namespace, loaders included. */
async function babylon4() {
  const BABYLON = require('babylonjs');
  globalThis.BABYLON = BABYLON;  // babylonjs-loaders registers itself on the global
  require('babylonjs-loaders');
  const load = (scene, bytes) => BABYLON.SceneLoader.LoadAssetContainerAsync(
    '', `data:base64,${Buffer.from(bytes).toString('base64')}`, scene, undefined, '.glb');
  return { BABYLON, GLTFLoader: BABYLON.GLTF2.GLTFLoader, load };
}

/** The current major from its ES modules. */
async function babylonCurrent() {
  const BABYLON = await import('@babylonjs/core');
  const loaders = await import('@babylonjs/loaders/glTF/2.0/index.js');
  const load = (scene, bytes) => BABYLON.LoadAssetContainerAsync(bytes.slice(), scene, { pluginExtension: '.glb' });
  return { BABYLON, GLTFLoader: loaders.GLTFLoader, load };
}

export const kBabylonVersions = ['4.2', 'current'];

/**
 * { BABYLON, GLTFLoader, version, load(scene, bytes) -> AssetContainer, scene(options) } for
 * '4.2' or 'current'. The engine's frame time is fixed at 1/60 s (a NullEngine measures the wall
 * clock, and a test must not depend on the machine's speed).
 */
export async function babylonKit(which) {
  const kit = which === '4.2' ? await babylon4() : await babylonCurrent();
  const { BABYLON } = kit;
  BABYLON.Logger?.ClearLogCache?.();
  if (BABYLON.Logger) BABYLON.Logger.LogLevels = BABYLON.Logger.ErrorLogLevel;
  kit.version = BABYLON.Engine.Version;
  kit.scene = ({ rightHanded = false, deltaMs = 1000 / 60 } = {}) => {
    const engine = new BABYLON.NullEngine();
    engine.getDeltaTime = () => deltaMs;
    const scene = new BABYLON.Scene(engine);
    scene.useRightHandedSystem = rightHanded;
    new BABYLON.FreeCamera('camera', new BABYLON.Vector3(0, 1, -3), scene);
    return scene;
  };
  return kit;
}
