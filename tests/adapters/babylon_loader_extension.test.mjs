// The Babylon glTF loader extension (web/babylon/springBonesLoaderExtension.js), registered on
// Babylon's own GLTFLoader class in 4.2 (UMD) and the current major: the loaded container carries
// the file's nodes by glTF index and the rig, and the drop-in class uses them.
import assert from 'node:assert/strict';
import { after, before, describe, test } from 'node:test';
import { createSpringBones } from '../../web/springbones.js';
import {
  SpringBoneSimulation, registerSpringBonesLoaderExtension, springBonesOf, unregisterSpringBonesLoaderExtension,
} from '../../web/babylon/index.js';
import { babylonKit, kBabylonVersions, readAsset, readJsonAsset } from './babylon_kit.mjs';

const metadata = readJsonAsset('hair_wearable.metadata.json');
const entity = readJsonAsset('hair_wearable.entity.json');
const [hash] = Object.keys(metadata.models);
const glb = readAsset('hair_wearable.glb');

/** The glTF JSON chunk of a GLB. */
function gltfJson(bytes) {
  const view = new DataView(bytes.buffer, bytes.byteOffset);
  return JSON.parse(new TextDecoder().decode(bytes.subarray(20, 20 + view.getUint32(12, true))));
}

let sb;
before(async () => {
  sb = await createSpringBones();
});

for (const which of kBabylonVersions) {
  describe(`Babylon ${which}`, () => {
    let kit;
    before(async () => {
      kit = await babylonKit(which);
    });
    after(() => unregisterSpringBonesLoaderExtension(kit.GLTFLoader));

    test('without the extension a container carries nothing', async () => {
      unregisterSpringBonesLoaderExtension(kit.GLTFLoader);
      const container = await kit.load(kit.scene(), glb);
      assert.equal(springBonesOf(container), null);
    });

    test('registered on GLTFLoader: the file\'s nodes by glTF index and the rig, on the loaded container', async () => {
      registerSpringBonesLoaderExtension(kit.GLTFLoader, { sb, springBones: metadata, entity, bodyShape: 'BaseMale' });
      const container = await kit.load(kit.scene(), glb);
      const loaded = springBonesOf(container);
      const json = gltfJson(glb);
      assert.equal(loaded.nodes.length, json.nodes.length);
      json.nodes.forEach((node, i) => assert.equal(loaded.nodes[i]?.name, node.name ?? loaded.nodes[i]?.name, `node ${i}`));
      assert.equal(loaded.error, null);
      const reference = sb.loadRig(glb, metadata);
      assert.deepEqual(loaded.rig.joints.map((j) => [j.name, j.node, j.tailNode]), reference.joints.map((j) => [j.name, j.node, j.tailNode]));
      assert.equal(loaded.rig.contentHash, hash);
      assert.deepEqual(loaded.warnings, []);
      // The drop-in class takes the container as it is, springBones and all.
      const scene = container.scene ?? kit.scene();
      container.addAllToScene();
      const simulation = new SpringBoneSimulation(sb);
      simulation.registerWearable(scene, container, 'item');
      assert.deepEqual(simulation.rigOf('item').joints.map((j) => j.node), reference.joints.map((j) => j.node));
      simulation.dispose(scene);
      reference.dispose();
      loaded.rig.dispose();
    });

    test('metadata the core rejects: the file loads, the error is on the wearable', async () => {
      registerSpringBonesLoaderExtension(kit.GLTFLoader, { sb, springBones: { version: 1, models: 7 }, contentHash: hash });
      const container = await kit.load(kit.scene(), glb);
      const loaded = springBonesOf(container);
      assert.equal(loaded.rig, null);
      assert.equal(loaded.error.code, 'metadata-invalid');
      assert.ok(container.meshes.length > 1, 'the meshes loaded');
    });

    test('registering needs Babylon\'s GLTFLoader class', () => {
      assert.throws(() => registerSpringBonesLoaderExtension({}, { sb }), TypeError);
    });

    if (which === 'current') {
      test('per load, the loader\'s extensionOptions override the registered options', async () => {
        registerSpringBonesLoaderExtension(kit.GLTFLoader, { sb });
        const scene = kit.scene();
        const container = await kit.BABYLON.LoadAssetContainerAsync(glb.slice(), scene, {
          pluginExtension: '.glb',
          pluginOptions: { gltf: { extensionOptions: { springbones: { springBones: metadata, contentHash: hash } } } },
        });
        assert.equal(springBonesOf(container).rig.joints.length, 15);
        springBonesOf(container).rig.dispose();
      });
    }
  });
}
