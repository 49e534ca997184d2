// The demo's sample avatar and hair wearable for the three.js adapter tests: the module, both
// GLBs parsed by GLTFLoader (in Node, without a renderer), the wearable's bytes and metadata, and
// its rig.
import { readFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';
import { createSpringBones } from '../../web/springbones.js';

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
  return { sb, avatarGltf, wearableGltf, wearableBytes, metadata, rig };
}
