// The demo's Babylon.js page: the sample avatar walking with its hair, simulated by
// springbones/babylon's SpringBoneSimulation as Decentraland's preview would use it (one
// AssetContainer per GLB, the wearable registered before its animation starts, one before-render
// step for every wearable), on Babylon 4.2's UMD build (the global BABYLON, loaded by the page).
//
// As the preview assembles an avatar, the wearable keeps its own copy of the armature bones it
// carries; the avatar's animation groups drive those too, by bone name (the hair follows the
// wearable's own Avatar_Head).
import { createSpringBones } from '../../../springbones.js';
import { SpringBoneSimulation } from '../../../babylon/index.js';
import { ChainPanel } from './chainPanel.js';
import { HairDrag } from './drag.js';

const BABYLON = globalThis.BABYLON;
const ASSETS = new URL('../../assets/', import.meta.url);
// The module's download starts at once; the simulation takes the module as a promise, so the
// wearables are registered (and drawn at rest) while it compiles.
const sbPromise = createSpringBones({ wasm: fetch(new URL('../../../dist/springbones_wasm.wasm', import.meta.url)) });

const boot = document.getElementById('boot');
const canvas = document.getElementById('view');
const engine = new BABYLON.Engine(canvas, true, { preserveDrawingBuffer: true, stencil: true });
const scene = new BABYLON.Scene(engine);
scene.clearColor = new BABYLON.Color4(0.086, 0.094, 0.114, 1);
// A three-quarter view from the avatar's front left: it faces the file's +Z, Babylon's +Z too.
// Far enough for the whole avatar, and for the teleport (1 m away from the camera) to stay in frame.
const camera = new BABYLON.ArcRotateCamera('camera', Math.PI / 2 - 0.8, Math.PI / 2.3, 4.2, new BABYLON.Vector3(0, 0.95, 0), scene);
camera.minZ = 0.05;
camera.attachControl(canvas, true);
new BABYLON.HemisphericLight('sky', new BABYLON.Vector3(0.2, 1, -0.4), scene).intensity = 1.1;
new BABYLON.DirectionalLight('sun', new BABYLON.Vector3(-0.4, -1, 0.6), scene).intensity = 1.6;

// Ground under the avatar, as on the three.js page: a disc of 4 m with a 0.5 m grid.
const ground = BABYLON.MeshBuilder.CreateDisc('ground', { radius: 4, tessellation: 64 }, scene);
ground.rotation.x = Math.PI / 2;  // the disc is made in the XY plane, facing -Z
const groundMaterial = new BABYLON.StandardMaterial('ground', scene);
groundMaterial.diffuseColor = new BABYLON.Color3(0.18, 0.196, 0.235);
groundMaterial.specularColor = BABYLON.Color3.Black();
ground.material = groundMaterial;
const gridLines = [];
for (let k = -8; k <= 8; k++) {
  const u = k * 0.5;
  const v = Math.sqrt(16 - u * u);  // the lines end at the disc's rim
  gridLines.push([new BABYLON.Vector3(u, 0.001, -v), new BABYLON.Vector3(u, 0.001, v)]);
  gridLines.push([new BABYLON.Vector3(-v, 0.001, u), new BABYLON.Vector3(v, 0.001, u)]);
}
BABYLON.MeshBuilder.CreateLineSystem('grid', { lines: gridLines }, scene).color = new BABYLON.Color3(0.29, 0.31, 0.376);

async function loadContainer(name) {
  const container = await BABYLON.SceneLoader.LoadAssetContainerAsync(ASSETS.href, name, scene);
  for (const group of container.animationGroups) group.stop();  // the loader starts the first one
  return container;
}

const [avatar, wearable, springBones] = await Promise.all([
  loadContainer('avatar.glb'),
  loadContainer('hair_wearable.glb'),
  fetch(new URL('hair_wearable.metadata.json', ASSETS)).then((r) => r.json()),
]);
const [itemHash] = Object.keys(springBones.models);
// Both files under one node that the page moves (the teleport).
const avatarRoot = new BABYLON.TransformNode('avatar', scene);
for (const container of [avatar, wearable]) {
  container.addAllToScene();
  container.meshes.find((m) => m.name === '__root__').parent = avatarRoot;
}

// Registered before any animation moves it: its current pose is the rest pose. With loadRig's
// 'dcl-body' colliders (head, neck, chest, belly, shoulders, upper arms), which the drop-in
// measures on the avatar in the scene (the skeleton with the whole armature: the hair's GLB
// carries Hips to Head only) and drives from the avatar's bones; the hit radius is the three.js
// page's. Decentraland's preview passes the models entry alone, without colliders.
const simulation = new SpringBoneSimulation(sbPromise);
simulation.registerWearable(scene, wearable, itemHash, { springBones, contentHash: itemHash, colliders: 'dcl-body', hitRadius: 0.01 });
simulation.start(scene);

// The avatar's clips drive the wearable's bones of the same names too.
const wearableNodes = new Map(wearable.transformNodes.map((n) => [n.name, n]));
for (const group of avatar.animationGroups) {
  for (const { animation, target } of [...group.targetedAnimations]) {
    const twin = wearableNodes.get(target.name);
    if (twin) group.addTargetedAnimation(animation, twin);
  }
}
let playing = null;
function play(name) {
  playing?.stop();
  playing = avatar.animationGroups.find((g) => g.name === name) ?? null;
  playing?.play(true);
}
document.getElementById('animation').addEventListener('change', (event) => play(event.target.value));
// The teleport moves the avatar 1 m away from the camera, and back: it stays in frame however the
// camera was orbited (moving sideways or towards the camera could leave the picture).
function teleport() {
  if (avatarRoot.position.lengthSquared() > 0.25) {
    avatarRoot.position.setAll(0);
  } else {
    const away = avatarRoot.position.subtract(camera.position);
    away.y = 0;
    avatarRoot.position.addInPlace(away.normalize());
  }
  simulation.jump();  // carried across the move: no whip
}
document.getElementById('teleport').addEventListener('click', teleport);
// Reset: the hair at rest in the pose the avatar has now (settle), not falling from its rest pose.
document.getElementById('reset').addEventListener('click', () => {
  drag?.letGo({ pointerId: -1 });
  simulation.settle();
});
let drag = null;  // the mouse drag of the hair, once the rig is there
document.getElementById('inertia').addEventListener('input', (event) => {
  const inertia = Number(event.target.value);
  document.getElementById('inertia-value').textContent = inertia.toFixed(2);
  simulation.setInertia(inertia);
});
// The body's shapes resized for this wearable without a rebuild (applied when the module comes,
// if it has not yet).
document.getElementById('body-scale').addEventListener('input', (event) => {
  const scale = Number(event.target.value);
  document.getElementById('body-scale-value').textContent = scale.toFixed(2);
  simulation.setColliders(itemHash, 'dcl-body', { scale });
});
document.getElementById('wind').addEventListener('input', (event) => {
  const strength = Number(event.target.value);
  document.getElementById('wind-value').textContent = strength.toFixed(1);
  // From the avatar's front (+Z in the glTF's space, where the direction is given), gusting.
  simulation.setWind(strength > 0 ? { direction: [-0.3, 0, -1], strength, gustFrequency: 0.5, seed: 1 } : null);
});

await simulation.ready;
const sb = await sbPromise;
play('walk');

const showRig = () => {
  const rig = simulation.rigOf(itemHash);
  document.getElementById('readout-joints').textContent = rig.joints.length;
  document.getElementById('readout-chains').textContent = rig.chains.length;
  document.getElementById('warnings').textContent = rig.warnings.map((w) => `${w.code}: ${w.message}`).join('\n');
};
// A press on a chain's tail drags the hair; elsewhere it turns the camera.
drag = new HairDrag(BABYLON, scene, camera, simulation, itemHash,
  () => simulation.rigOf(itemHash)?.joints.map((j) => (j.tail ? wearableNodes.get(j.tail) ?? null : null)) ?? []);
const panel = new ChainPanel(springBones.models[itemHash], (entry) => {
  simulation.updateParams(itemHash, entry);
  showRig();
});
showRig();
document.getElementById('readout-babylon').textContent = BABYLON.Engine.Version;

const fps = document.getElementById('readout-fps');
let frames = 0;
engine.runRenderLoop(() => {
  scene.render();
  if (++frames % 30 === 0) fps.textContent = engine.getFps().toFixed(0);
});
window.addEventListener('resize', () => engine.resize());
boot.hidden = true;

/** For the browser tests (tests/browser/babylon.test.mjs). */
window.springbonesBabylonDemo = {
  ready: true,
  babylonVersion: BABYLON.Engine.Version,
  springbonesVersion: sb.version,
  /** The bones that carry the rig's colliders, and the rig's warnings' codes. */
  colliders: () => simulation.rigOf(itemHash).colliders.map((c) => c.node),
  warnings: () => simulation.rigOf(itemHash).warnings.map((w) => w.code),
  /** The rig's joints: name, chain root, parameters. */
  joints: () => simulation.rigOf(itemHash).joints.map((j, i, all) => ({ name: j.name, chain: all[j.chain].name, params: j.params })),
  /** Every simulated node's rotationQuaternion, in the rig's joint order, flat. */
  rotations: (names = simulation.rigOf(itemHash).joints.map((j) => j.name)) => names.flatMap((name) => {
    const q = wearableNodes.get(name).rotationQuaternion;
    return [q.x, q.y, q.z, q.w];
  }),
  entry: () => structuredClone(panel.entry),
  /**
   * Where the avatar is drawn: the screen rectangle (page CSS pixels) of its meshes' bounds in
   * the current pose, the canvas's, and the ground's top and the avatar's lowest point (metres).
   */
  onScreen: () => {
    scene.render();  // world matrices and bounds of this frame
    const meshes = [...avatar.meshes, ...wearable.meshes].filter((m) => m.getTotalVertices() > 0);
    const rect = canvas.getBoundingClientRect();
    const viewport = camera.viewport.toGlobal(engine.getRenderWidth(), engine.getRenderHeight());
    const transform = scene.getTransformMatrix();
    const xs = [];
    const ys = [];
    let lowest = Infinity;
    for (const mesh of meshes) {
      mesh.refreshBoundingInfo(true);  // with the skeleton's current pose
      for (const v of mesh.getBoundingInfo().boundingBox.vectorsWorld) {
        const p = BABYLON.Vector3.Project(v, BABYLON.Matrix.IdentityReadOnly, transform, viewport);
        xs.push(rect.left + p.x / engine.getRenderWidth() * rect.width);
        ys.push(rect.top + p.y / engine.getRenderHeight() * rect.height);
        lowest = Math.min(lowest, v.y);
      }
    }
    return {
      avatar: { left: Math.min(...xs), right: Math.max(...xs), top: Math.min(...ys), bottom: Math.max(...ys) },
      canvas: { left: rect.left, right: rect.right, top: rect.top, bottom: rect.bottom },
      ground: { y: ground.getBoundingInfo().boundingBox.maximumWorld.y, radius: 4, visible: ground.isEnabled() && ground.isVisible },
      lowest,
      position: avatarRoot.position.asArray(),
    };
  },
  teleport,
  /** Where a node (a chain's tail) is drawn, in the page's CSS pixels (null: no such node). */
  tailOnScreen: (name) => {
    const node = wearableNodes.get(name);
    if (!node) return null;
    const p = BABYLON.Vector3.Project(node.getAbsolutePosition(), BABYLON.Matrix.Identity(), scene.getTransformMatrix(),
      camera.viewport.toGlobal(canvas.clientWidth, canvas.clientHeight));
    const rect = canvas.getBoundingClientRect();
    return { x: rect.left + p.x, y: rect.top + p.y };
  },
  /** Whether the mouse holds a joint of the hair. */
  dragging: () => drag.dragging,
};
