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
import { glbOfJson } from '../../scripts/lib/fixtures/glb.mjs';
import { decodeTyped } from './typed_decode.mjs';
import { babylonKit } from '../adapters/babylon_kit.mjs';
import { registerSpringBonesLoaderExtension, springBonesOf } from '../../web/babylon/index.js';
import { loadReaders } from '../../web/readers.js';
import { createSpringBones } from '../../web/springbones.js';
import { encodeGltf } from '../../web/typed_value.js';

const realDir = realFixturesDir();

/** parser.json of three.js's GLTFLoader for these bytes (the rest of its parse is not waited for). */
function threeJson(bytes) {
  const { json, error } = threeParse(bytes);
  assert.ok(json, `GLTFLoader gave its plugins no parser.json: ${error}`);
  return json;
}

/** What GLTFLoader makes of these bytes: its parser.json, or the error it reported. */
function threeParse(bytes) {
  let json;
  let error;
  const loader = new GLTFLoader();
  loader.register((parser) => {
    json = parser.json;
    return { name: 'capture' };
  });
  try {
    loader.parse(bytes.slice().buffer, '', () => {}, (e) => {
      error = e;
    });
  } catch (e) {  // JSON.parse's SyntaxError comes out of parse() itself
    error = e;
  }
  return { json, error };
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

// Issue 39, classes 4 and 5: bytes that JSON.parse and a byte-level JSON library read differently.
// Each case is a small wearable in a GLB whose JSON chunk is written byte for byte; three.js's
// GLTFLoader (TextDecoder, then JSON.parse) is the page's side, the readers module the other.
describe('bytes read as the page reads them', () => {
  const kHash = 'bafkreifrontends';
  const metadata = {
    version: 1,
    models: { [kHash]: { SpringBone_hair: { stiffness: 1, gravityPower: 0.5, gravityDir: [0, -1, 0], drag: 0.4, isRoot: true } } },
  };
  const utf8 = (text) => new TextEncoder().encode(text);
  const concat = (...parts) => {
    const out = new Uint8Array(parts.reduce((n, p) => n + p.length, 0));
    let at = 0;
    for (const p of parts) {
      out.set(p, at);
      at += p.length;
    }
    return out;
  };
  // The JSON of the wearable, with `rotation` as written and `extra` members after `nodes`; the
  // node name `name` is spliced in as bytes.
  const wearable = ({ rotation = '[0,0,0,1]', name = utf8('SpringBone_hair_1'), extra = '' } = {}) => concat(
    utf8('{"asset":{"version":"2.0"},"nodes":[{"name":"Avatar_Head","children":[1]},' +
         `{"name":"SpringBone_hair","children":[2],"translation":[0.1,0,0],"rotation":${rotation}},{"name":"`),
    name, utf8(`","translation":[0,-0.1,0]}]${extra}}`));
  // A GLB around these JSON bytes, padded with `pad` (glbOfJson pads with spaces, as glTF asks).
  const glbWith = (json, pad) => {
    const glb = glbOfJson(json);
    if (pad === undefined) return glb;
    const padded = concat(glb.subarray(0, 20), json, pad);
    const view = new DataView(padded.buffer);
    view.setUint32(8, padded.length, true);
    view.setUint32(12, json.length + pad.length, true);
    return padded;
  };

  const same = (name, bytes) => {
    test(`${name}: the same typed input, rig, warnings and rotation bits`, () => {
      const json = threeJson(bytes);
      assert.deepStrictEqual(decodeTyped(encodeGltf('test', json, true)), decodeTyped(readers.readGltf(bytes, true)));
      const a = sb.loadRig(bytes, metadata, { contentHash: kHash });
      const b = sb.loadRig(json, metadata, { contentHash: kHash });
      for (const key of ['nodeCount', 'joints', 'chains', 'drivers', 'colliders', 'warnings']) assert.deepStrictEqual(b[key], a[key], key);
      assert.equal(a.joints.length, 1);
      assert.deepEqual(motionBits(b), motionBits(a));
      a.dispose();
      b.dispose();
    });
  };
  const bothRefuse = (name, bytes, code) => {
    test(`${name}: refused by the page's parse and by the readers`, () => {
      const page = threeParse(bytes);
      let pageRefused = page.json === undefined;
      if (!pageRefused) assert.throws(() => sb.loadRig(page.json, metadata, { contentHash: kHash }), (e) => (pageRefused = e instanceof Error));
      assert.ok(pageRefused, 'the page refuses it');
      assert.throws(() => sb.loadRig(bytes, metadata, { contentHash: kHash }), (e) => e.code === code, 'the readers refuse it');
    });
  };

  same('1e400 in accessors[0].max (a member never read)',
       glbWith(wearable({ extra: ',"accessors":[{"componentType":5126,"count":1,"type":"SCALAR","max":[1e400],"min":[-1e400]}]' })));
  same('an escaped lone surrogate in a mesh name (a member never read)',
       glbWith(wearable({ extra: ',"meshes":[{"name":"\\ud800 and \\udfff","primitives":[]}]' })));
  same('ill-formed UTF-8 in a mesh name (a member never read)',
       glbWith(concat(wearable().subarray(0, -1), utf8(',"meshes":[{"name":"'), new Uint8Array([0xff, 0xc3, 0xe2, 0x82]), utf8('"}]}'))));
  same('ill-formed UTF-8 in a node name that is read: U+FFFD, as TextDecoder gives it',
       glbWith(wearable({ name: concat(utf8('SpringBone_'), new Uint8Array([0xff, 0xe2, 0x82, 0x41, 0xed, 0xa0, 0x80, 0xf0, 0x9f, 0x98, 0x80])) })));
  same('a byte order mark before the JSON of a GLB chunk', glbWith(concat(new Uint8Array([0xef, 0xbb, 0xbf]), wearable())));
  same('-0 in a rotation keeps its sign (class 5)', glbWith(wearable({ rotation: '[-0,-0.0,-0e0,1]' })));
  same('-0 in a rotation that turns the bone', glbWith(wearable({ rotation: '[-0,0.6,-0,0.8]' })));
  same('a repeated key: the last one is read', glbWith(wearable({ rotation: '[0,0,0,1],"rotation":[-0,0.6,0,0.8]' })));
  same('a number of 800 digits and one of 1e-400 where they are read',
       glbWith(wearable({ rotation: `[0.${'3'.repeat(800)},1e-400,0,1]` })));
  same('an unread root extension with a lone surrogate, and a VRM extension\'s unread members',
       glbWith(wearable({ extra: ',"extensions":{"KHR_x":{"t":"\\udc00"},"VRM":{"meta":{"title":"\\ud800"},"secondaryAnimation":null}}' })));

  bothRefuse('a JSON chunk padded with NUL bytes', glbWith(wearable(), new Uint8Array(3)), 'gltf-bad-json');
  bothRefuse('{...}\\0garbage', glbWith(wearable(), concat(new Uint8Array(1), utf8('garbage'))), 'gltf-bad-json');
  bothRefuse('garbage after the document', glbWith(wearable(), utf8(' x')), 'gltf-bad-json');
  bothRefuse('an escaped lone surrogate in a node name that is read',
             glbWith(wearable({ name: utf8('SpringBone_\\ud800') })), 'gltf-invalid');
  bothRefuse('1e400 in a node transform that is read', glbWith(wearable({ rotation: '[1e400,0,0,1]' })), 'gltf-invalid');
});
