// The README's JavaScript samples work as written on a Decentraland avatar: the code blocks of its
// "three.js" and "JavaScript API" sections are taken from README.md as they are, run against the
// package itself (the 'springbones' imports resolve to the repository's package.json exports, the
// minified bundles in web/dist/) on the bundled sample avatar and hair wearable, with only the
// page's own objects (scene, renderer, URLs, the catalyst entity, the GLB bytes, the drivers'
// world matrices) defined before them. The collider of the API sample must keep the hair out of a
// head-sized sphere, centimetres in Avatar_Head's space, which a shaken head otherwise swings the
// side locks into; the sample as it was (offset 0.08, radius 0.1: a 1 mm sphere) would not.
import assert from 'node:assert/strict';
import { mkdirSync, readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { after, before, test } from 'node:test';
import { pathToFileURL } from 'node:url';
import { Scene } from 'three';
import { startServer } from '../../scripts/lib/serve.mjs';
import { root } from './helpers.mjs';

const readme = readFileSync(join(root, 'README.md'), 'utf8');
const assets = join(root, 'web', 'demo', 'assets');
const entity = JSON.parse(readFileSync(join(assets, 'hair_wearable.entity.json'), 'utf8'));
const glbBytes = new Uint8Array(readFileSync(join(assets, 'hair_wearable.glb')));

/** The first ```js block of the README section with this heading. */
function sampleOf(heading) {
  const start = readme.indexOf(`\n## ${heading}\n`);
  assert.ok(start >= 0, `README has a "## ${heading}" section`);
  const end = readme.indexOf('\n## ', start + 1);
  const block = readme.slice(start, end < 0 ? undefined : end).match(/```js\n([\s\S]*?)```/);
  assert.ok(block, `the "${heading}" section has a js code block`);
  return block[1];
}

/**
 * Runs a README sample as a module in this process: `given` names the objects the page has (taken
 * from globalThis.readmeSample), `exported` what the test reads afterwards. The file is written
 * under the repository (tests/artifacts/), where 'springbones' resolves to the package itself.
 */
async function runSample(name, code, given, exported) {
  const dir = join(root, 'tests', 'artifacts');
  mkdirSync(dir, { recursive: true });
  const file = join(dir, `readme_${name}.mjs`);
  writeFileSync(file, `const { ${given.join(', ')} } = globalThis.readmeSample;\n${code}\nexport { ${exported.join(', ')} };\n`);
  return import(`${pathToFileURL(file).href}?${Date.now()}`);
}

let server;
let baseUrl;
before(async () => {
  ({ server } = await startServer({ port: 0, root, isolated: false }));
  baseUrl = `http://127.0.0.1:${server.address().port}/web/demo/assets/`;
});
after(() => server?.close());

/** A side-to-side shake of the whole avatar, 15 cm at 3 Hz: every driver matrix moves along x. */
function shake(matrices, rest, driverCount, t) {
  matrices.set(rest);
  for (let d = 0; d < driverCount; d++) matrices[16 * d + 12] += 0.15 * Math.sin(2 * Math.PI * 3 * t);
}

/** Closest any simulated joint (a tail of its parent) comes to `sphere`'s centre over 4 s of shaking. */
function closestApproach(rig, inst, rest, sphereOf) {
  let closest = Infinity;
  for (let frame = 1; frame <= 240; frame++) {
    shake(inst.driverMatrices, rest, rig.drivers.length, frame / 60);
    inst.step(1 / 60);
    const { center } = sphereOf(inst.driverMatrices);
    const world = inst.worldMatrices;
    rig.joints.forEach((joint, k) => {
      if (joint.parent < 0) return;  // a chain root is where its parent puts it
      closest = Math.min(closest, Math.hypot(world[16 * k + 12] - center[0], world[16 * k + 13] - center[1], world[16 * k + 14] - center[2]));
    });
  }
  return closest;
}

test('the JavaScript API sample: the catalyst entity\'s springBones, and a head collider that keeps the hair out', async () => {
  const code = sampleOf('JavaScript API');
  assert.match(code, /entity\.metadata\.data\.springBones/, 'the sample reads a catalyst entity');
  // The drivers at rest for the first frame the sample steps (any world matrices would do).
  const { createSpringBones } = await import('springbones');
  const sb = await createSpringBones();
  const probe = sb.loadRig(glbBytes, entity.metadata.data.springBones, { entity, bodyShape: 'BaseMale' });
  const rest = Float32Array.from(probe.createInstance().driverMatrices);
  globalThis.readmeSample = { glbBytes, entity, driverWorldMatrices: rest, dt: 1 / 60 };
  const { rig, inst } = await runSample('api', code, ['glbBytes', 'entity', 'driverWorldMatrices', 'dt'], ['rig', 'inst']);
  assert.equal(rig.joints.length, 15, 'the entity\'s entry for this GLB was found');
  assert.deepEqual(rig.warnings, []);
  assert.equal(rig.colliders.length, 1);

  // The sphere in the world: its node's world matrix applied to offset, radius scaled with it.
  const collider = rig.colliders[0];
  const sphereOf = (matrices) => {
    const m = matrices.subarray(16 * collider.driver, 16 * collider.driver + 16);
    const [x, y, z] = collider.offset;
    return {
      center: [0, 1, 2].map((r) => m[r] * x + m[4 + r] * y + m[8 + r] * z + m[12 + r]),
      radius: collider.radius * Math.hypot(m[0], m[1], m[2]),
    };
  };
  const { radius } = sphereOf(rest);
  assert.ok(radius > 0.08 && radius < 0.12, `a head-sized sphere in the world: ${radius} m`);
  const hitRadius = 0.01;

  // Without the collider the shake swings the side locks into the head's sphere; with the
  // README's, no tail comes closer than radius + hitRadius (float32 rounding aside).
  const bare = probe.createInstance({ integrator: 'xpbd' });
  const without = closestApproach(probe, bare, rest, sphereOf);
  assert.ok(without < radius, `without the collider the hair reaches ${without} m from the centre`);
  inst.reset();
  const withCollider = closestApproach(rig, inst, rest, sphereOf);
  assert.ok(withCollider >= radius + hitRadius - 1e-3,
    `with it, no tail comes closer than ${withCollider} m (radius ${radius} + hitRadius ${hitRadius})`);
  for (const r of [rig, probe]) r.dispose();
});

test('the three.js sample: worn from the GLTFLoader plugin, the hair follows the avatar, nothing to warn about', async () => {
  const code = sampleOf('three.js');
  // GLTFLoader.loadAsync reports progress with the browser's ProgressEvent, which Node lacks.
  globalThis.ProgressEvent ??= class ProgressEvent extends Event {
    constructor(type, { lengthComputable = false, loaded = 0, total = 0 } = {}) {
      super(type);
      Object.assign(this, { lengthComputable, loaded, total });
    }
  };
  const scene = new Scene();
  let frame = null;
  const renderer = { setAnimationLoop: (callback) => { frame = callback; }, render: () => {} };
  const errors = [];
  const warnings = [];
  const warn = console.warn;
  console.warn = (...args) => warnings.push(args.join(' '));
  // The sample's clock starts at performance.now() when it runs; held there, its first frame's dt
  // is the test's 1/60 s, not however long the loading took on a busy machine, so the clip plays
  // from the same phase on every run.
  const now = performance.now;
  const start = now.call(performance);
  performance.now = () => start;
  try {
    globalThis.readmeSample = {
      scene, renderer, camera: {}, entity, showError: (e) => errors.push(e),
      avatarUrl: `${baseUrl}avatar.glb`, wearableUrl: `${baseUrl}hair_wearable.glb`,
    };
    const { avatar, worn, mixer } = await runSample('three', code,
      ['scene', 'renderer', 'camera', 'entity', 'showError', 'avatarUrl', 'wearableUrl'], ['avatar', 'worn', 'mixer']);
    assert.equal(typeof frame, 'function', 'the sample runs its frame loop');
    // The sample plays the avatar's first clip, not a T-pose in which the hair settles and stops.
    assert.equal(mixer.existingAction(avatar.animations[0])?.isRunning(), true, 'an animation plays');
    await worn.ready;
    assert.equal(worn.simulating, true);
    const ponytail = worn.jointObjects[worn.rig.joints.findIndex((j) => j.name === 'SpringBone_ponytail')];
    const head = avatar.scene.getObjectByName('Avatar_Head');
    // Two seconds of the sample's own frames, nothing else moving the avatar: the clip moves the
    // head and the ponytail keeps swinging after the first second (no settling into stillness).
    let time = start;
    const headStart = head.quaternion.clone();
    let swing = 0;
    let previous = null;
    for (let f = 0; f < 120; f++) {
      time += 1000 / 60;
      frame(time);
      const q = ponytail.quaternion.toArray();
      if (f >= 60 && previous) swing = Math.max(swing, ...q.map((v, i) => Math.abs(v - previous[i])));
      previous = q;
    }
    assert.ok(head.quaternion.angleTo(headStart) > 1e-3, 'the clip turns the head');
    assert.ok(swing > 1e-4, `the ponytail still moves in the second second (${swing} per frame)`);
    assert.deepEqual(worn.warnings, []);
    assert.deepEqual(errors, []);
    assert.deepEqual(warnings, []);
  } finally {
    performance.now = now;
    console.warn = warn;
  }
});
