// One vocabulary for "why is my hair static" (issue 37): the three.js adapter and the Babylon
// drop-in, given the same wearable and the same springBones and hash options, say the same code,
// message, fix and path for every case; docs/diagnostics.md lists exactly the codes the code has;
// and a case the adapters cannot see (a module that never loads) is told apart from one loadRig
// refuses.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { before, describe, test } from 'node:test';
import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';
import * as SkeletonUtils from 'three/examples/jsm/utils/SkeletonUtils.js';
import { babylonKit, readAsset, readJsonAsset } from './babylon_kit.mjs';
import { createSpringBones } from '../../web/springbones.js';
import { SpringBonesLoaderPlugin } from '../../web/three/index.js';
import { SpringBoneSimulation } from '../../web/babylon/index.js';
import { kDiagnostics } from '../../web/wearable/diagnostics.js';

const metadata = readJsonAsset('hair_wearable.metadata.json');
const hash = Object.keys(metadata.models)[0];
const wearableBytes = readAsset('hair_wearable.glb');

let sb;
let avatarGltf;
let kit;
before(async () => {
  sb = await createSpringBones();
  avatarGltf = await new GLTFLoader().parseAsync(readAsset('avatar.glb').slice().buffer, '');
  kit = await babylonKit('current');
});

const edited = (edit) => {
  const copy = structuredClone(metadata);
  edit(copy.models[hash]);
  return copy;
};
const project = (warnings) => warnings.map(({ code, message, fix, path }) => ({ code, message, fix, path }));

/** What wear() says about the wearable loaded with these plugin options (no console). */
async function threeSays(options) {
  const received = [];
  const loader = new GLTFLoader();
  loader.register((parser) => new SpringBonesLoaderPlugin(parser, { ...options, onWarning: (w) => received.push(w) }));
  const wearable = (await loader.parseAsync(wearableBytes.slice().buffer, '')).userData.springBones;
  const worn = wearable.wear(SkeletonUtils.clone(avatarGltf.scene));
  await worn.ready.catch(() => {});
  const said = project(worn.warnings);
  wearable.dispose();
  return { said, received: project(received) };
}

/** What the Babylon drop-in says about the same wearable registered with `params` (no console). */
async function babylonSays(module, params) {
  const scene = kit.scene();
  const container = await kit.load(scene, wearableBytes);
  container.addAllToScene();
  const original = console.warn;
  const lines = [];
  console.warn = (...args) => lines.push(args.join(' '));
  try {
    const simulation = new SpringBoneSimulation(module);
    simulation.registerWearable(scene, container, 'urn:item', params);
    await simulation.ready.catch(() => {});
    const said = project(simulation.warnings);
    simulation.dispose();
    return { said, lines };
  } finally {
    console.warn = original;
    scene.getEngine().dispose();
  }
}

describe('both adapters say the same for the same wearable and metadata', () => {
  const cases = [
    ['springbones-missing', {}],
    ['models-missing', { springBones: { version: 1 }, contentHash: hash }],
    ['model-not-found', { springBones: metadata, contentHash: 'bafkreianothermodel' }],
    ['entry-not-matched', { springBones: { version: 1, models: { [hash]: { Other_springbone: { isRoot: true } } } }, contentHash: hash }],
    ['no-chain-root', { springBones: edited((entry) => Object.values(entry).forEach((e) => delete e.isRoot)), contentHash: hash }],
    ['unrooted-bones', { springBones: edited((entry) => delete entry.hair_springbone_l.isRoot), contentHash: hash }],
    ['rig-failed', { springBones: '{ not json', contentHash: hash }],
  ];
  for (const [code, options] of cases) {
    test(code, async () => {
      const three = await threeSays({ sb: Promise.resolve(sb), ...options });
      const babylon = await babylonSays(sb, options.springBones === undefined ? undefined : options);
      assert.deepEqual(three.said.map((w) => w.code), [code], JSON.stringify(three.said));
      assert.deepEqual(babylon.said, three.said);
      // onWarning hears the wearable and each attachment (the application says each once).
      assert.deepEqual([...new Set(three.received.map((w) => JSON.stringify(w)))], three.said.map((w) => JSON.stringify(w)),
        'onWarning received what the attachment lists');
      assert.equal(babylon.lines.length, 1, babylon.lines.join('\n'));
      assert.equal(babylon.lines[0], `springbones [${code}] wearable urn:item: ${three.said[0].message}. Fix: ${three.said[0].fix}.`);
    });
  }

  test('the advice fits the case: unrooted-bones names the bone without isRoot, and only it', async () => {
    const { said } = await threeSays({ sb, springBones: edited((entry) => delete entry.hair_springbone_l.isRoot), contentHash: hash });
    assert.match(said[0].message, /"hair_springbone_l"/);
    assert.match(said[0].fix, /"isRoot": true to "hair_springbone_l"/);
    assert.doesNotMatch(said[0].message + said[0].fix, /ponytail|hair_springbone_r/);
  });

  test('no-chain-root names the chains\' top bones, not a member below them', async () => {
    const { said } = await threeSays({ sb, springBones: edited((entry) => Object.values(entry).forEach((e) => delete e.isRoot)), contentHash: hash });
    assert.match(said[0].fix, /"SpringBone_ponytail"/);
    assert.doesNotMatch(said[0].fix, /SpringBone_ponytail_3/);
  });

  test('a module that never loads: module-failed in both, with the same message', async () => {
    const failing = createSpringBones({ wasmUrl: new URL('file:///nonexistent/springbones_wasm.wasm') });
    failing.catch(() => {});
    const three = await threeSays({ sb: failing, springBones: metadata, contentHash: hash });
    const babylon = await babylonSays(failing, { springBones: metadata, contentHash: hash });
    assert.deepEqual(three.said.map((w) => w.code), ['module-failed']);
    assert.deepEqual(babylon.said, three.said);
  });

  test('the sample as it should be worn says nothing in either', async () => {
    const three = await threeSays({ sb, springBones: metadata, contentHash: hash });
    const babylon = await babylonSays(sb, { springBones: metadata, contentHash: hash });
    assert.deepEqual(three.said, []);
    assert.deepEqual(babylon.said, []);
    assert.deepEqual(babylon.lines, []);
  });
});

test('docs/diagnostics.md lists every code of web/wearable/diagnostics.js, in its order, and no other', () => {
  const doc = readFileSync(new URL('../../docs/diagnostics.md', import.meta.url), 'utf8');
  const documented = [...doc.matchAll(/^\| `([a-z-]+)` \|/gm)].map((m) => m[1]);
  assert.deepEqual(documented, Object.keys(kDiagnostics));
});
