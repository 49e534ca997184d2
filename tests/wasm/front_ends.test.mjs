// One rig builder behind every front end: a file read by the readers module from its bytes, parsed
// by three.js's GLTFLoader (what a three.js page hands over: parser.json) or by Babylon's glTF
// loader (what springbones/babylon's loader extension hands over) gives the runtime the same typed
// input and the same rig, and the rig moves bit for bit the same. Every fixture of tests/fixtures
// and every file of ../shared/fixtures/real (VRM avatars made by others, read in place). Babylon's
// document has the nodes only (no root extensions): for a VRM it is compared by its node table.
import assert from 'node:assert/strict';
import { readFileSync, readdirSync } from 'node:fs';
import { join } from 'node:path';
import { before, describe, test } from 'node:test';
import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';
import { fixture, fixturesDir, metadataKeyOf, realFixturesDir } from './helpers.mjs';
import { decodeTyped } from './typed_decode.mjs';
import { babylonKit } from '../adapters/babylon_kit.mjs';
import { registerSpringBonesLoaderExtension, springBonesOf } from '../../web/babylon/index.js';
import { loadReaders } from '../../web/readers.js';
import { createSpringBones } from '../../web/springbones.js';
import { encodeGltf } from '../../web/typed_value.js';

const realDir = realFixturesDir();

/** parser.json of three.js's GLTFLoader for these bytes (the rest of its parse is not waited for). */
function threeJson(bytes) {
  let json;
  const loader = new GLTFLoader();
  loader.register((parser) => {
    json = parser.json;
    return { name: 'capture' };
  });
  loader.parse(bytes.slice().buffer, '', () => {}, () => {});
  assert.ok(json, 'GLTFLoader gave its plugins no parser.json');
  return json;
}

/** The files, each with how to load it: loadRig with its metadata, or loadVrm. */
function inputs() {
  const manifest = JSON.parse(fixture('manifest.json').toString('utf8')).files;
  const list = [];
  for (const [name, entry] of Object.entries(manifest)) {
    if (!/\.(glb|gltf)$/.test(name) || !entry.metadata) continue;
    list.push({ name, bytes: new Uint8Array(fixture(name)), metadata: JSON.parse(fixture(entry.metadata).toString('utf8')),
                key: metadataKeyOf(name) });
  }
  for (const name of readdirSync(fixturesDir).filter((f) => f.endsWith('.vrm'))) {
    list.push({ name, bytes: new Uint8Array(fixture(name)), vrm: true });
  }
  const real = readdirSync(realDir).filter((f) => /\.(gltf|vrm)$/.test(f)).map((f) => join(realDir, f));
  real.push(...readdirSync(join(realDir, 'originals')).map((f) => join(realDir, 'originals', f)));
  for (const path of real) list.push({ name: path.slice(realDir.length + 1), bytes: new Uint8Array(readFileSync(path)), vrm: true });
  return list;
}

/** Rotations of every joint over 90 frames of a swaying root driver, as raw bits. */
function motionBits(rig) {
  const instance = rig.createInstance();
  const bits = [];
  for (let frame = 0; frame < 90; ++frame) {
    const drivers = instance.driverMatrices;
    for (let d = 0; d < rig.drivers.length; ++d) {
      drivers.fill(0, 16 * d, 16 * d + 16);
      drivers[16 * d] = drivers[16 * d + 5] = drivers[16 * d + 10] = drivers[16 * d + 15] = 1;
      drivers[16 * d + 12] = 0.3 * Math.sin(frame / 6);
      drivers[16 * d + 14] = 0.2 * Math.cos(frame / 9);
    }
    instance.step(1 / 60);
    bits.push(...new Uint32Array(instance.rotations.slice().buffer));
  }
  instance.dispose();
  return bits;
}

let sb;
let readers;
let babylon;
before(async () => {
  sb = await createSpringBones();
  readers = await loadReaders({});
  babylon = await babylonKit('current');
  registerSpringBonesLoaderExtension(babylon.GLTFLoader, {});
});

/** The glTF document springbones/babylon's loader extension hands over for these bytes. */
async function babylonDocument(name, bytes) {
  const scene = babylon.scene();
  // glTF text goes in as a data URL: Babylon reads only binary glTF from an ArrayBufferView.
  const text = name.endsWith('.gltf');
  const source = text ? `data:model/gltf+json;base64,${Buffer.from(bytes).toString('base64')}` : bytes.slice();
  const container = await babylon.BABYLON.LoadAssetContainerAsync(source, scene, { pluginExtension: text ? '.gltf' : '.glb' });
  const loaded = springBonesOf(container);
  assert.ok(loaded, 'the loader extension put nothing on the container');
  const { gltf } = loaded;
  container.dispose();
  scene.getEngine().dispose();
  return gltf;
}

/** The node table the runtime reads: each node's name, children and transform fields. */
const nodeTable = (typed) => decodeTyped(typed).nodes;

describe('the front ends', () => {
  for (const input of inputs()) {
    test(`${input.name}: the readers and three.js's parse give the same input, rig and motion`, () => {
      const json = threeJson(input.bytes);
      const fromBytes = readers.readGltf(input.bytes, Boolean(input.vrm));
      assert.deepEqual(decodeTyped(encodeGltf('test', json, Boolean(input.vrm))), decodeTyped(fromBytes));
      const load = (gltf) => (input.vrm ? sb.loadVrm(gltf) : sb.loadRig(gltf, input.metadata, { contentHash: input.key }));
      const a = load(input.bytes);
      const b = load(json);
      for (const key of ['format', 'nodeCount', 'joints', 'chains', 'drivers', 'colliders', 'warnings']) {
        assert.deepEqual(b[key], a[key], key);
      }
      assert.ok(a.nodeCount > 0);
      assert.deepEqual(motionBits(b), motionBits(a));
      a.dispose();
      b.dispose();
    });

    test(`${input.name}: Babylon's parse gives the same node table${input.vrm ? '' : ', rig and motion'}`, async () => {
      const gltf = await babylonDocument(input.name, input.bytes);
      assert.deepEqual(nodeTable(encodeGltf('test', gltf, false)), nodeTable(readers.readGltf(input.bytes, false)));
      if (input.vrm) return;
      const a = sb.loadRig(input.bytes, input.metadata, { contentHash: input.key });
      const b = sb.loadRig(gltf, input.metadata, { contentHash: input.key });
      for (const key of ['nodeCount', 'joints', 'chains', 'drivers', 'colliders', 'warnings']) {
        assert.deepEqual(b[key], a[key], key);
      }
      assert.deepEqual(motionBits(b), motionBits(a));
      a.dispose();
      b.dispose();
    });
  }
});
