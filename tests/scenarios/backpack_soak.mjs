// A backpack that never leaks, the page's side: cycles of load a wearable -> wear it on the avatar
// -> 30 frames -> take it off and dispose, through the three.js adapter, as a backpack or login
// screen swaps wearables for as long as it is open. Runs in a page with three in its import map
// (tests/browser/pages/blank.html); tests/browser/backpack_soak.test.mjs drives it and measures
// between batches (600 cycles in CI, 2,000 in `scripts/bench --soak`).
//
// The cycle alternates three wearables: the sample hair through GLTFLoader with the
// SpringBonesLoaderPlugin (entity + body shape, wear(), dispose()), and the two VRM fixtures
// through GLTFLoader, sb.loadVrm and attachWearable on a SkeletonUtils clone (the adapter
// underneath the plugin; a VRM's springs are not Decentraland metadata, so the plugin does not
// read them).

import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import * as SkeletonUtils from 'three/addons/utils/SkeletonUtils.js';
import { Scene } from 'three';
import { createSpringBones } from '/web/springbones.js';
import { SpringBonesLoaderPlugin } from '/web/three/springBonesLoaderPlugin.js';
import { attachWearable, wearableNodes } from '/web/three/springBonesThree.js';

const kFrames = 30;
const kDt = 1 / 60;

const bytesOf = async (url) => (await fetch(url)).arrayBuffer();

/** Opens the soak: the module, the avatar in a scene, the wearables' bytes. */
export async function openSoak() {
  const sb = await createSpringBones();
  await sb.readers();  // the wearables arrive as bytes
  const [avatarBytes, hairBytes, entity, vrm0, vrm10] = await Promise.all([
    bytesOf('/web/demo/assets/avatar.glb'), bytesOf('/web/demo/assets/hair_wearable.glb'),
    (await fetch('/web/demo/assets/hair_wearable.entity.json')).json(),
    bytesOf('/tests/fixtures/vrm0_springs.vrm'), bytesOf('/tests/fixtures/vrm10_springs.vrm'),
  ]);
  const avatar = await new GLTFLoader().parseAsync(avatarBytes.slice(0), '');
  const scene = new Scene();
  scene.add(avatar.scene);
  const springBones = entity.metadata.data.springBones;

  // One cycle of the sample hair: the loader plugin end to end.
  async function hairCycle() {
    const loader = new GLTFLoader();
    loader.register((parser) => new SpringBonesLoaderPlugin(parser, { sb, springBones, entity, bodyShape: 'BaseMale' }));
    const wearable = (await loader.parseAsync(hairBytes.slice(0), '')).userData.springBones;
    const worn = wearable.wear(avatar.scene);
    run(worn);
    wearable.dispose();
  }

  // One cycle of a VRM: its springs through sb.loadVrm, worn with the adapter on a clone.
  async function vrmCycle(bytes) {
    const gltf = await new GLTFLoader().parseAsync(bytes.slice(0), '');
    const rig = sb.loadVrm(new Uint8Array(bytes));
    const clone = SkeletonUtils.clone(gltf.scene);
    const worn = attachWearable(avatar.scene, clone, rig, { nodes: wearableNodes(gltf, clone) });
    run(worn);
    worn.dispose();
    rig.dispose();
  }

  // 30 frames of a walk-like sway of the avatar root, as the page's loop would run them.
  let time = 0;
  function run(worn) {
    for (let i = 0; i < kFrames; i++) {
      time += kDt;
      avatar.scene.rotation.y = 0.3 * Math.sin(2 * Math.PI * 0.7 * time);
      avatar.scene.position.x = 0.05 * Math.sin(2 * Math.PI * 0.9 * time);
      scene.updateMatrixWorld();
      worn.update(kDt);
    }
    for (const v of worn.instance.rotations) if (!Number.isFinite(v)) throw new Error('a non-finite rotation');
  }

  let cycles = 0;
  /** Runs `count` more cycles; returns the module's numbers after the last one. */
  async function runCycles(count) {
    for (let i = 0; i < count; i++, cycles++) {
      switch (cycles % 3) {
        case 0: await hairCycle(); break;
        case 1: await vrmCycle(vrm0); break;
        default: await vrmCycle(vrm10); break;
      }
    }
    // What stays on the avatar: the wearables' objects must all have been taken off.
    let objects = 0;
    avatar.scene.traverse(() => { objects++; });
    return { cycles, ...sb.stats(), avatarObjects: objects };
  }
  return { runCycles };
}
