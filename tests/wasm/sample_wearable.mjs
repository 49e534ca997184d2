// The demo's sample avatar and hair wearable for the three.js adapter tests: the module, both
// GLBs parsed by GLTFLoader (in Node, without a renderer), the wearable's bytes and metadata, its
// rig, and wear() to put it on a clone of the avatar.
import { readFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { AnimationMixer, Group, Scene } from 'three';
import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';
import * as SkeletonUtils from 'three/examples/jsm/utils/SkeletonUtils.js';
import { createSpringBones } from '../../web/springbones.js';
import { attachWearable, wearableNodes } from '../../web/three/springBonesThree.js';

const assets = join(dirname(fileURLToPath(import.meta.url)), '..', '..', 'web', 'demo', 'assets');
const read = (name) => new Uint8Array(readFileSync(join(assets, name)));

export async function loadSampleWearable() {
  const loader = new GLTFLoader();
  const parse = (bytes) => loader.parseAsync(bytes.slice().buffer, '');
  const sb = await createSpringBones();
  const avatarGltf = await parse(read('avatar.glb'));
  const wearableBytes = read('hair_wearable.glb');
  const wearableGltf = await parse(wearableBytes);
  const metadata = JSON.parse(readFileSync(join(assets, 'hair_wearable.metadata.json'), 'utf8'));
  const rig = sb.loadRig(wearableBytes, metadata);
  const wear = (wornRig, options) => wearOnAvatar(avatarGltf, wearableGltf, wornRig, options);
  return { sb, avatarGltf, wearableGltf, wearableBytes, metadata, rig, wear };
}

/**
 * A clone of the wearable on a clone of the avatar, in scene > world > holder, as the demo holds
 * it: the world group carries teleports and turns, the holder walks, shakes and spins. `instance`
 * is attachWearable's option; with watchMixer the adapter watches the avatar's mixer for actions
 * starting. The clips' actions are made, not played.
 */
function wearOnAvatar(avatarGltf, wearableGltf, rig, { instance = {}, watchMixer = false, holderScale = [1, 1, 1] } = {}) {
  const scene = new Scene();
  const world = new Group();
  const holder = new Group();
  holder.scale.fromArray(holderScale);
  world.add(holder);
  scene.add(world);
  const avatarRoot = SkeletonUtils.clone(avatarGltf.scene);
  holder.add(avatarRoot);
  const mixer = new AnimationMixer(avatarRoot);
  const wearable = SkeletonUtils.clone(wearableGltf.scene);
  const attachment = attachWearable(avatarRoot, wearable, rig, {
    nodes: wearableNodes(wearableGltf, wearable), instance, mixer: watchMixer ? mixer : undefined,
  });
  const actions = Object.fromEntries(avatarGltf.animations.map((clip) => [clip.name, mixer.clipAction(clip)]));
  return { scene, world, holder, avatarRoot, mixer, actions, attachment };
}
