// Never silent (issue 31): every way a worn wearable's spring bones stay at rest on the three.js
// side says so once per wearable on the console, with a code and the fix, and lists it in the
// attachment's (and the loaded wearable's) `warnings`: a module that fails to load, a models entry
// without isRoot, a hash that matches no entry, and avatar bones wear() cannot match. A failure
// reaches `ready` and never ends a Node process as an unhandled rejection.
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import { readFileSync } from 'node:fs';
import { after, before, describe, test } from 'node:test';
import { fileURLToPath } from 'node:url';
import { Scene } from 'three';
import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';
import * as SkeletonUtils from 'three/examples/jsm/utils/SkeletonUtils.js';
import { loadSampleWearable } from '../wasm/sample_wearable.mjs';
import { createSpringBones } from '../../web/springbones.js';
import { SpringBonesLoaderPlugin, attachWearable, wearableNodes } from '../../web/three/index.js';

const assets = new URL('../../web/demo/assets/', import.meta.url);
const entity = JSON.parse(readFileSync(new URL('hair_wearable.entity.json', assets), 'utf8'));
const bodyShape = 'urn:decentraland:off-chain:base-avatars:BaseMale';

let sb;
let avatarGltf;
let wearableGltf;
let wearableBytes;
let metadata;

// Any unhandled rejection while these tests run is a failure of the test that caused it.
const unhandled = [];
const onUnhandled = (reason) => unhandled.push(reason);
before(async () => {
  ({ sb, avatarGltf, wearableGltf, wearableBytes, metadata } = await loadSampleWearable());
  process.on('unhandledRejection', onUnhandled);
});
after(() => process.off('unhandledRejection', onUnhandled));

/** Runs fn with console.warn recorded; returns what fn returned and the lines warned. */
async function recordingWarnings(fn) {
  const lines = [];
  const original = console.warn;
  console.warn = (...args) => lines.push(args.join(' '));
  try {
    const result = await fn();
    // Let every rejection handler and unhandled-rejection check of this turn run.
    await new Promise((resolve) => setTimeout(resolve, 20));
    return { result, lines };
  } finally {
    console.warn = original;
  }
}

async function loadWithPlugin(options) {
  const loader = new GLTFLoader();
  loader.register((parser) => new SpringBonesLoaderPlugin(parser, options));
  return (await loader.parseAsync(wearableBytes.slice().buffer, '')).userData.springBones;
}

/** Two avatars in a scene, each a clone of the sample avatar; `rename` renames bones first. */
function twoAvatars(rename = {}) {
  const scene = new Scene();
  const avatars = [0, 1].map(() => SkeletonUtils.clone(avatarGltf.scene));
  for (const avatar of avatars) {
    avatar.traverse((o) => {
      const to = rename[o.userData.name ?? o.name];
      if (to) {
        o.name = to;
        o.userData.name = to;
      }
    });
  }
  scene.add(...avatars);
  return { scene, avatars };
}

/** The one console line of `code`, checked for its shape: code, what, and a fix. */
function assertOneLine(lines, code) {
  const ours = lines.filter((l) => l.startsWith('springbones ['));
  assert.equal(ours.length, 1, `one console warning, not ${ours.length}: ${ours.join('\n')}`);
  assert.match(ours[0], new RegExp(`^springbones \\[${code}\\] wearable \\S+: .+\\. Fix: \\S.+\\.$`));
  return ours[0];
}

const codes = (warnings) => warnings.map((w) => w.code);

/** Every warning of these codes has a message and a fix. */
function assertExplained(warnings, code) {
  const found = warnings.filter((w) => w.code === code);
  assert.ok(found.length >= 1, `a ${code} warning in ${JSON.stringify(codes(warnings))}`);
  for (const w of found) {
    assert.ok(typeof w.message === 'string' && w.message.length > 10, w.message);
    assert.ok(typeof w.fix === 'string' && w.fix.length > 10, w.fix);
  }
}

describe('the static-hair cases say why, once per wearable', () => {
  test('a module that fails to load: module-failed, ready rejects, no unhandled rejection', async () => {
    const { result, lines } = await recordingWarnings(async () => {
      const failing = createSpringBones({ wasmUrl: new URL('file:///nonexistent/springbones_wasm.wasm') });
      const wearable = await loadWithPlugin({ sb: failing, springBones: metadata, glb: wearableBytes });
      const { avatars } = twoAvatars();
      const worn = avatars.map((a) => wearable.wear(a));
      const reasons = await Promise.all(worn.map((w) => w.ready.then(() => null, (e) => e)));
      return { wearable, worn, reasons };
    });
    const line = assertOneLine(lines, 'module-failed');
    assert.match(line, /nonexistent/, 'the line names what failed');
    const { wearable, worn, reasons } = result;
    for (const reason of reasons) assert.equal(reason?.code, 'module-load-failed');
    assert.deepEqual(codes(wearable.warnings), ['module-failed']);
    assertExplained(wearable.warnings, 'module-failed');
    for (const w of worn) {
      assert.equal(w.simulating, false);
      assertExplained(w.warnings, 'module-failed');
    }
    assert.deepEqual(unhandled, []);
    wearable.dispose();
  });

  test('an entry whose spring bones have no isRoot: no-chain-root naming them', async () => {
    const noRoots = structuredClone(metadata);
    for (const entry of Object.values(noRoots.models)) for (const node of Object.values(entry)) delete node.isRoot;
    const { result, lines } = await recordingWarnings(async () => {
      const wearable = await loadWithPlugin({ sb, springBones: noRoots, glb: wearableBytes });
      const { avatars } = twoAvatars();
      return { wearable, worn: avatars.map((a) => wearable.wear(a)) };
    });
    const line = assertOneLine(lines, 'no-chain-root');
    assert.match(line, /SpringBone_ponytail/);
    assert.match(line, /isRoot/);
    const { wearable, worn } = result;
    assert.equal(wearable.rig.joints.length, 0);
    assert.deepEqual(codes(wearable.warnings), ['no-chain-root']);
    for (const w of worn) assertExplained(w.warnings, 'no-chain-root');
    wearable.dispose();
  });

  test('a hash that matches nothing: the rig\'s model-not-found, said with its fix', async () => {
    const { result, lines } = await recordingWarnings(async () => {
      const wearable = await loadWithPlugin({ sb, springBones: metadata, contentHash: 'bafkreianothermodel' });
      const { avatars } = twoAvatars();
      return { wearable, worn: avatars.map((a) => wearable.wear(a)) };
    });
    assert.match(assertOneLine(lines, 'model-not-found'), /bafkreianothermodel/);
    const { wearable, worn } = result;
    assert.deepEqual(codes(wearable.warnings), ['model-not-found'], 'the core\'s warning, listed once');
    for (const w of worn) assertExplained(w.warnings, 'model-not-found');
    wearable.dispose();
  });

  test('avatar bones wear() cannot match: bone-not-matched, and the others still match', async () => {
    const { result, lines } = await recordingWarnings(async () => {
      const wearable = await loadWithPlugin({ sb, springBones: metadata, glb: wearableBytes });
      const { avatars } = twoAvatars({ Avatar_Head: 'mixamorig:Head' });
      return { wearable, avatars, worn: avatars.map((a) => wearable.wear(a)) };
    });
    const line = assertOneLine(lines, 'bone-not-matched');
    assert.match(line, /Avatar_Head/);
    const { wearable, avatars, worn } = result;
    for (const [i, w] of worn.entries()) {
      assert.deepEqual(codes(w.warnings), ['bone-not-matched']);
      assertExplained(w.warnings, 'bone-not-matched');
      // What the warning says: the ponytail hangs from the avatar root, not from a head bone.
      const ponytail = w.jointObjects[w.rig.joints.findIndex((j) => j.name === 'SpringBone_ponytail')];
      let up = ponytail.parent;
      while (up && up !== avatars[i] && up.name !== 'mixamorigHead') up = up.parent;
      assert.equal(up, avatars[i]);
    }
    wearable.dispose();
  });

  test('the sample as it should be worn says nothing', async () => {
    const { result, lines } = await recordingWarnings(async () => {
      const wearable = await loadWithPlugin({ sb, springBones: entity.metadata.data.springBones, entity, bodyShape });
      const { avatars } = twoAvatars();
      return { wearable, worn: avatars.map((a) => wearable.wear(a)) };
    });
    assert.deepEqual(lines, []);
    assert.deepEqual(result.wearable.warnings, []);
    for (const w of result.worn) assert.deepEqual(w.warnings, []);
    result.wearable.dispose();
  });

  test('attachWearable on its own says it once per attachment; onWarning takes the place of the console', async () => {
    const noRoots = structuredClone(metadata);
    for (const entry of Object.values(noRoots.models)) for (const node of Object.values(entry)) delete node.isRoot;
    const rig = sb.loadRig(wearableBytes, noRoots);
    const received = [];
    const { result, lines } = await recordingWarnings(() => {
      const { avatars } = twoAvatars();
      const wear = (avatar, options) => {
        const copy = SkeletonUtils.clone(wearableGltf.scene);
        return attachWearable(avatar, copy, rig, { nodes: wearableNodes(wearableGltf, copy), ...options });
      };
      const worn = wear(avatars[0]);
      worn.setRig(rig);  // the same rig again (an editor's rebuild): not said again
      const quiet = wear(avatars[1], { onWarning: (w) => received.push(w) });
      return [worn, quiet];
    });
    // Without the models entry at hand, the adapter says what it sees: spring-bone nodes, no chain.
    assert.match(assertOneLine(lines, 'no-chains'), /SpringBone_ponytail/);
    assert.deepEqual(codes(received), ['no-chains']);
    for (const w of result) assertExplained(w.warnings, 'no-chains');
    for (const w of result) w.dispose();
    const copy = SkeletonUtils.clone(wearableGltf.scene);
    assert.throws(() => attachWearable(SkeletonUtils.clone(avatarGltf.scene), copy, rig, { nodes: wearableNodes(wearableGltf, copy), onWarning: 'log' }),
        (error) => error instanceof TypeError && /onWarning must be a function/.test(error.message));
    rig.dispose();
  });
});

describe('entity without bodyShape, the module as a promise', () => {
  test('rejects through worn.ready with a clear error; the Node process is not ended by it', () => {
    // In a child process: an unhandled rejection would end it with exit code 1.
    const script = `
      import { readFileSync } from 'node:fs';
      import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';
      import { createSpringBones } from '../../web/springbones.js';
      import { SpringBonesLoaderPlugin } from '../../web/three/index.js';
      const assets = new URL('../../web/demo/assets/', ${JSON.stringify(import.meta.url)});
      const read = (name) => new Uint8Array(readFileSync(new URL(name, assets)));
      const entity = JSON.parse(readFileSync(new URL('hair_wearable.entity.json', assets), 'utf8'));
      const loader = new GLTFLoader();
      loader.register((parser) => new SpringBonesLoaderPlugin(parser,
        { sb: createSpringBones(), springBones: entity.metadata.data.springBones, entity }));
      const item = await loader.parseAsync(read('hair_wearable.glb').buffer, '');
      const avatar = await new GLTFLoader().parseAsync(read('avatar.glb').buffer, '');
      const worn = item.userData.springBones.wear(avatar.scene);
      worn.ready.then(() => console.log('resolved'), (e) => console.log('caught ' + e.name + ': ' + e.message));
    `;
    const child = spawnSync(process.execPath, ['--input-type=module', '-e', script], {
      cwd: fileURLToPath(new URL('.', import.meta.url)), encoding: 'utf8',
    });
    assert.equal(child.status, 0, child.stderr);
    assert.match(child.stdout, /^caught TypeError: .*with an entity, bodyShape must be a string/m);
    assert.match(child.stderr, /springbones \[rig-failed\] wearable urn:decentraland:off-chain:springbones-demo:hair_wearable: .*bodyShape.* Fix: /);
    assert.doesNotMatch(child.stderr, /Unhandled|triggerUncaughtException/);
  });
});
