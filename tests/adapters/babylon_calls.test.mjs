// The Babylon drop-in's calls under arguments a page gets wrong (issue 39, classes 8-10):
// dispose(otherScene) still takes the frame hook off the started scene, dispose('x') is our
// TypeError (not the engine's), grab with an id never registered is an unknown-item warning that
// names the call and the id (so are settle and release), and grab's point is checked as three
// numbers before it is mirrored into the glTF's space, in either handedness.
import assert from 'node:assert/strict';
import { before, describe, test } from 'node:test';
import { createSpringBones } from '../../web/springbones.js';
import { SpringBoneSimulation } from '../../web/babylon/index.js';
import { babylonKit, kBabylonVersions, readAsset, readJsonAsset } from './babylon_kit.mjs';

const metadata = readJsonAsset('hair_wearable.metadata.json');
const [hash] = Object.keys(metadata.models);
const glb = readAsset('hair_wearable.glb');

let sb;
before(async () => {
  sb = await createSpringBones();
});

const settledTurn = () => new Promise((resolve) => setTimeout(resolve, 5));

/** Runs fn with console.warn recorded; returns the lines. */
function warnedBy(fn) {
  const lines = [];
  const original = console.warn;
  console.warn = (...args) => lines.push(args.join(' '));
  try {
    fn();
  } finally {
    console.warn = original;
  }
  return lines;
}

for (const which of kBabylonVersions) {
  describe(`Babylon ${which}`, () => {
    let kit;
    before(async () => {
      kit = await babylonKit(which);
    });

    async function started({ rightHanded = false } = {}) {
      const scene = kit.scene({ rightHanded });
      const container = await kit.load(scene, glb);
      container.addAllToScene();
      const simulation = new SpringBoneSimulation(sb);
      simulation.registerWearable(scene, container, hash, { springBones: metadata, contentHash: hash });
      simulation.start(scene);
      scene.render();
      return { scene, simulation };
    }

    test('dispose(otherScene) takes the hook off the started scene: its renders go on without error', async () => {
      const { scene, simulation } = await started();
      const other = kit.scene();
      const hooks = scene.onBeforeRenderObservable.observers.length;
      simulation.dispose(other);
      await settledTurn();  // Babylon removes an observer after the current turn
      assert.equal(scene.onBeforeRenderObservable.observers.length, hooks - 1, 'the frame hook is gone from the started scene');
      for (let f = 0; f < 3; f++) scene.render();  // threw "Cannot read properties of null" before
      // Started again after that dispose, it steps: the simulation is reusable.
      const container = await kit.load(scene, glb);
      container.addAllToScene();
      simulation.registerWearable(scene, container, hash, { springBones: metadata, contentHash: hash });
      simulation.start(scene);
      scene.render();
      assert.equal(scene.onBeforeRenderObservable.observers.length, hooks);
      simulation.dispose(scene);
      await settledTurn();
      assert.equal(scene.onBeforeRenderObservable.observers.length, hooks - 1);
    });

    test('dispose with a value that is not a scene is our TypeError, before anything changes', async () => {
      const { scene, simulation } = await started();
      for (const bad of ['x', 5, {}, [scene]]) {
        assert.throws(() => simulation.dispose(bad), (e) => e instanceof TypeError && /^dispose: scene must be a Babylon Scene or left out/.test(e.message));
      }
      assert.notEqual(simulation.rigOf(hash), null, 'still registered');
      simulation.dispose();
      assert.equal(simulation.rigOf(hash), null);
      scene.render();
    });

    test('grab, settle and release with an id never registered: one unknown-item warning each, naming the call and the id', async () => {
      const { scene, simulation } = await started();
      const lines = warnedBy(() => {
        simulation.grab('urn:nothing', 0, [0, 1, 0]);
        simulation.grab('urn:nothing', 0, [0, 1, 0]);
        simulation.settle('urn:settle', 1);
        simulation.release('urn:release');
      });
      assert.equal(lines.length, 3, lines.join('\n'));
      assert.match(lines[0], /\[unknown-item\] wearable urn:nothing: grab: no wearable is registered as "urn:nothing"/);
      assert.match(lines[1], /settle: no wearable is registered as "urn:settle"/);
      assert.match(lines[2], /release: no wearable is registered as "urn:release"/);
      for (const w of simulation.warnings) assert.doesNotMatch(w.message, /^undefined/);
      assert.deepEqual(simulation.warnings.map((w) => w.itemId), ['urn:nothing', 'urn:settle', 'urn:release']);
      simulation.dispose(scene);
    });

    for (const rightHanded of [false, true]) {
      test(`grab's point is three numbers, checked before mirroring (${rightHanded ? 'right' : 'left'}-handed scene)`, async () => {
        const { scene, simulation } = await started({ rightHanded });
        const instance = () => simulation.rigOf(hash) && simulation.internalsForTests.wearable(hash).instance;
        for (const bad of [['1', 0, 0], [null, 0, 0], [true, 0, 0], [1, 2, 3, 4], [1, 2], { x: '5', y: 0, z: 0 }, { x: 1, y: 2 }, 'point', null, true]) {
          assert.throws(() => simulation.grab(hash, 0, bad), (e) => e instanceof TypeError && /^grab: point must be \[x, y, z\] or \{x, y, z\}/.test(e.message),
            JSON.stringify(bad));
          assert.equal(instance().grabbedJoint, -1, `nothing grabbed for ${JSON.stringify(bad)}`);
        }
        // Numbers go through, as an array or as a Vector3-like object, mirrored in a left-handed scene.
        simulation.grab(hash, 1, [0.1, 1.5, 0]);
        assert.equal(instance().grabbedJoint, 1);
        simulation.release(hash);
        simulation.grab(hash, 1, new kit.BABYLON.Vector3(0.1, 1.5, 0));
        assert.equal(instance().grabbedJoint, 1);
        assert.throws(() => simulation.grab(hash, 1, [Infinity, 0, 0]), RangeError, 'a non-finite number is the instance\'s RangeError');
        simulation.dispose(scene);
      });
    }
  });
}
