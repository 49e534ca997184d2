// The Babylon.js drop-in as Decentraland's wearable preview calls its own SpringBoneSimulation
// (the call pattern of its render(), Builder tuning and wearable swaps), in Babylon 4.2 (the UMD
// `babylonjs`) and the current major (@babylonjs/core), on a NullEngine with the demo's sample:
// constructed with no argument, URN item ids with the models entry, updateParams as live tuning
// (measured: no pop), dispose then register again, and every case that leaves hair still saying
// so once per wearable (console and `warnings`).
import assert from 'node:assert/strict';
import { before, describe, test } from 'node:test';
import { createSpringBones } from '../../web/springbones.js';
import { SpringBoneSimulation } from '../../web/babylon/index.js';
import { babylonKit, kBabylonVersions, readAsset, readJsonAsset } from './babylon_kit.mjs';

const metadata = readJsonAsset('hair_wearable.metadata.json');
const entity = readJsonAsset('hair_wearable.entity.json');
const [hash] = Object.keys(metadata.models);
const entry = metadata.models[hash];
const urn = entity.metadata.id;  // what the preview passes as the item id
const glb = readAsset('hair_wearable.glb');

let sb;
before(async () => {
  sb = await createSpringBones();
});

/** console.warn, recorded while `run` runs (and not printed). */
async function consoleWarnings(run) {
  const seen = [];
  const original = console.warn;
  console.warn = (...args) => seen.push(args.join(' '));
  try {
    await run();
  } finally {
    console.warn = original;
  }
  return seen;
}

const nodeNamed = (container, name) => [...container.transformNodes, ...container.meshes].find((n) => n.name === name);
const quaternionOf = (node) => {
  const q = node.rotationQuaternion;
  return [q.x, q.y, q.z, q.w];
};
/**
 * The angle between two rotations, radians: from the chord between them (acos of a dot product
 * near 1 would turn float32 rounding into milliradians).
 */
const turn = (a, b) => {
  const s = Math.sign(a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]) || 1;
  const na = Math.hypot(...a);
  const nb = Math.hypot(...b);
  const chord = Math.hypot(...a.map((x, i) => x / na - (s * b[i]) / nb));
  return 4 * Math.asin(Math.min(1, chord / 2));
};
const kSpringNodes = ['SpringBone_ponytail', 'SpringBone_ponytail_1', 'SpringBone_ponytail_2', 'SpringBone_ponytail_3',
  'hair_springbone_l', 'hair_springbone_r', 'springbone_earring_l', 'springbone_earring_r'];

// First in this file, so that nothing has started the page's module yet (one per process).
test('new SpringBoneSimulation() with no argument starts no module until a wearable is registered', async () => {
  const simulation = new SpringBoneSimulation();
  let settled = false;
  simulation.ready.then(() => { settled = true; }, () => { settled = true; });
  for (let i = 0; i < 20; i++) await new Promise((resolve) => setImmediate(resolve));
  assert.equal(settled, false, 'no module before a wearable is registered');
  assert.equal(simulation.springBones, null);
});

for (const which of kBabylonVersions) {
  describe(`Babylon ${which}`, () => {
    let kit;
    before(async () => {
      kit = await babylonKit(which);
    });

    /** The sample in a scene, registered as the preview registers it (URN, models entry), started. */
    async function previewScene({ simulation = new SpringBoneSimulation(sb), params = entry, itemId = urn, scene = kit.scene() } = {}) {
      const container = await kit.load(scene, glb);
      container.addAllToScene();
      simulation.registerWearable(scene, container, itemId, params);
      simulation.start(scene);
      const head = nodeNamed(container, 'Avatar_Head');
      const springs = kSpringNodes.map((name) => nodeNamed(container, name)).filter(Boolean);
      const rest = new Map(springs.map((n) => [n, quaternionOf(n)]));
      /** A frame of a head swaying and turning (an emote): renders the scene. */
      const frame = (f) => {
        head.position.x = 0.15 * Math.sin(f * 0.15);
        head.rotation.y = 0.5 * Math.sin(f * 0.11);
        if (head.rotationQuaternion) head.rotationQuaternion = kit.BABYLON.Quaternion.FromEulerAngles(0, 0.5 * Math.sin(f * 0.11), 0);
        scene.render();
      };
      const pose = () => springs.map(quaternionOf);
      return { scene, container, simulation, frame, springs, rest, pose };
    }

    test('new SpringBoneSimulation() with no argument starts the module itself at the first registerWearable, once, shared by every simulation', async () => {
      const a = await previewScene({ simulation: new SpringBoneSimulation() });
      const b = await previewScene({ simulation: new SpringBoneSimulation() });
      await Promise.all([a.simulation.ready, b.simulation.ready]);
      assert.ok(a.simulation.springBones, 'the module is there');
      assert.equal(a.simulation.springBones, b.simulation.springBones, 'one module for both');
      assert.notEqual(a.simulation.springBones, sb, 'its own, not the test\'s');
      assert.equal(a.simulation.rigOf(urn).joints.length, 15);
      let moved = 0;
      for (let f = 0; f < 40; f++) {
        a.frame(f);
        moved = Math.max(moved, ...a.springs.map((n) => turn(quaternionOf(n), a.rest.get(n))));
      }
      assert.ok(moved > 0.02, `the hair swings (${moved})`);
      a.simulation.dispose(a.scene);
      b.simulation.dispose(b.scene);
    });

    test('setInertia: at 0 the hair feels none of the head\'s motion, at 1 all of it; on wearables registered later too', async () => {
      // How far the hair of a swaying, turning head moves from the hair of a still one (both
      // settling from rest alike), at most over 40 frames.
      const swing = async (inertia, before) => {
        const scenes = [];
        for (let k = 0; k < 2; k++) {
          const simulation = new SpringBoneSimulation(sb);
          if (before) simulation.setInertia(inertia);
          scenes.push(await previewScene({ simulation }));
          if (!before) simulation.setInertia(inertia);
        }
        const [moving, still] = scenes;
        let moved = 0;
        for (let f = 0; f < 40; f++) {
          moving.frame(f);
          still.scene.render();
          moved = Math.max(moved, ...moving.springs.map((n, i) => turn(quaternionOf(n), quaternionOf(still.springs[i]))));
        }
        for (const s of scenes) s.simulation.dispose(s.scene);
        return moved;
      };
      const all = await swing(1, false);
      const none = await swing(0, false);
      assert.ok(all > 0.02, `at 1 the hair swings (${all})`);
      assert.ok(none < all / 4, `at 0 it barely moves (${none} against ${all})`);
      assert.equal(await swing(0, true), none, 'set before registering: the same');
      assert.throws(() => new SpringBoneSimulation(sb).setInertia(1.5), RangeError);
    });

    test('URN ids with the models entry; the whole springBones resolves when it is unambiguous', async () => {
      const { simulation, scene, container } = await previewScene();
      assert.equal(simulation.rigOf(urn).joints.length, 15);
      assert.deepEqual(simulation.warnings, []);
      // The whole springBones under a URN: its only model.
      const warnings = await consoleWarnings(() => simulation.registerWearable(scene, container, urn, metadata));
      assert.equal(simulation.rigOf(urn).joints.length, 15, 'its only model');
      assert.deepEqual(warnings, []);
      // Two models, one under the item id: that one.
      const other = { ...entry, SpringBone_ponytail: { ...entry.SpringBone_ponytail, isRoot: false } };
      simulation.registerWearable(scene, container, urn, { version: 1, models: { [urn]: other, [hash]: entry } });
      assert.equal(simulation.rigOf(urn).chains.length, 4, 'the entry under the item id');
      simulation.dispose(scene);
    });

    test('the whole springBones with several models and none under the URN: a warning that says so, no throw', async () => {
      const scene = kit.scene();
      const simulation = new SpringBoneSimulation(sb);
      const ambiguous = { version: 1, models: { [hash]: entry, bafkreiother: entry } };
      const warnings = await consoleWarnings(async () => {
        await previewScene({ simulation, scene, params: ambiguous });
      });
      assert.equal(warnings.length, 1, warnings.join('\n'));
      assert.match(warnings[0], /springbones-ambiguous/);
      assert.match(warnings[0], /models\[hash\]/, 'the fix');
      assert.deepEqual(simulation.warnings.map((w) => [w.code, w.itemId]), [['springbones-ambiguous', urn]]);
      assert.equal(simulation.rigOf(urn).joints.length, 0);
      // The Builder then pushes the entry: the wearable moves, the warning is gone.
      simulation.updateParams(urn, entry);
      assert.equal(simulation.rigOf(urn).joints.length, 15);
      assert.deepEqual(simulation.warnings, []);
      simulation.dispose(scene);
    });

    test('updateParams with the same entry (every reload, every emote start) changes nothing: as a twin never updated', async () => {
      const updated = await previewScene();
      const twin = await previewScene();
      for (let f = 0; f < 60; f++) {
        updated.frame(f);
        twin.frame(f);
      }
      updated.simulation.updateParams(urn, structuredClone(entry));
      let apart = 0;
      let moving = 0;
      for (let f = 60; f < 120; f++) {
        const before = updated.pose();
        updated.frame(f);
        twin.frame(f);
        apart = Math.max(apart, ...updated.pose().map((q, i) => turn(q, twin.pose()[i])));
        moving = Math.max(moving, ...updated.pose().map((q, i) => turn(q, before[i])));
      }
      assert.ok(moving > 1e-3, `the chains keep moving (${moving})`);
      assert.ok(apart < 1e-5, `within ${apart} rad of the twin`);
      updated.simulation.dispose();
      twin.simulation.dispose();
    });

    test('updateParams is live tuning: no pop at an edit, untouched chains go on as before, new values merged over the old', async () => {
      const { simulation, frame, springs, rest, pose } = await previewScene();
      const twin = await previewScene();  // never edited
      let ordinary = 0;
      let last = pose();
      for (let f = 0; f < 90; f++) {
        frame(f);
        twin.frame(f);
        const now = pose();
        if (f >= 30) ordinary = Math.max(ordinary, ...now.map((q, i) => turn(q, last[i])));  // past the settle from rest
        last = now;
      }
      const displaced = Math.max(...springs.map((n) => turn(quaternionOf(n), rest.get(n))));
      // A restart from rest (the preview class's behaviour before) would change the pose by `displaced` at once.
      assert.ok(displaced > 10 * ordinary, `the chains are away from rest (${displaced}), far more than a frame moves them (${ordinary})`);
      // A slider step in the Builder: the whole entry with the ponytail's stiffness changed.
      const edited = { ...entry, SpringBone_ponytail: { ...entry.SpringBone_ponytail, stiffness: 1.5 } };
      simulation.updateParams(urn, edited);
      assert.deepEqual(pose(), last, 'nothing changes before the next frame');
      frame(90);
      twin.frame(90);
      const changes = pose().map((q, i) => turn(q, last[i]));
      const fromTwin = pose().map((q, i) => turn(q, twin.pose()[i]));
      const ponytail = springs.map((n) => n.name.startsWith('SpringBone_ponytail'));
      // The chains whose entries did not change go on exactly as if nothing happened.
      assert.ok(Math.max(...fromTwin.filter((_, i) => !ponytail[i])) < 1e-6, `untouched chains: ${fromTwin}`);
      // The edited chain answers its new stiffness at once (in VRM's update stiffness moves the tail
      // every step, so it changes the velocity, not a force): more than a steady frame, far from a restart.
      const pop = Math.max(...changes);
      assert.ok(pop <= 2 * ordinary && pop < displaced / 10, `the edit frame turns a joint by ${pop}: a steady frame up to ${ordinary}, a restart ${displaced}`);
      const rig = simulation.rigOf(urn);
      assert.equal(rig.joints.find((j) => j.name === 'SpringBone_ponytail').params.stiffness, 1.5, 'the new value');
      assert.equal(rig.chains.length, 5);
      last = pose();
      simulation.updateParams(urn, { ...edited, hair_springbone_l: { drag: 0.45 } });  // no isRoot: merged over the old entry
      frame(91);
      const merged = simulation.rigOf(urn).joints.find((j) => j.name === 'hair_springbone_l');
      assert.equal(merged.params.drag, 0.45);
      assert.equal(merged.params.stiffness, entry.hair_springbone_l.stiffness, 'the other fields kept');
      assert.equal(simulation.rigOf(urn).chains.length, 5, 'still a root (isRoot merged from before)');
      const second = Math.max(...pose().map((q, i) => turn(q, last[i])));
      assert.ok(second <= 2 * ordinary, `no pop either (${second})`);
      simulation.dispose();
      twin.simulation.dispose();
    });

    test('updateParams: a removed chain goes back to rest, an added one starts from where it is drawn', async () => {
      const { SpringBone_ponytail, SpringBone_ponytail_3, ...withoutPonytail } = entry;
      const { simulation, frame, container, rest, pose } = await previewScene();
      // How much a chain that starts from rest moves per frame while it settles (as on every load).
      let settling = 0;
      let last = pose();
      for (let f = 0; f < 30; f++) {
        frame(f);
        const now = pose();
        settling = Math.max(settling, ...now.map((q, i) => turn(q, last[i])));
        last = now;
      }
      const ponytail = nodeNamed(container, 'SpringBone_ponytail_1');
      simulation.updateParams(urn, withoutPonytail);
      assert.deepEqual(quaternionOf(ponytail), rest.get(ponytail), 'at rest at once');
      for (let f = 30; f < 90; f++) frame(f);
      assert.deepEqual(quaternionOf(ponytail), rest.get(ponytail));
      last = pose();
      simulation.updateParams(urn, entry);
      assert.deepEqual(pose(), last, 'drawn where it was until the next frame');
      frame(90);
      const pop = Math.max(...pose().map((q, i) => turn(q, last[i])));
      assert.ok(pop <= settling, `adding the chain turns a joint by ${pop}; a chain settling from rest by up to ${settling}`);
      let moved = 0;
      for (let f = 91; f < 120; f++) {
        frame(f);
        moved = Math.max(moved, turn(quaternionOf(ponytail), rest.get(ponytail)));
      }
      assert.ok(moved > 1e-3, `the added chain moves (${moved})`);
      simulation.dispose();
    });

    test('updateParams on an unknown id, or after dispose, does nothing and warns once', async () => {
      const { simulation, scene } = await previewScene();
      const warnings = await consoleWarnings(() => {
        for (let i = 0; i < 3; i++) simulation.updateParams('urn:decentraland:unknown', entry);  // the Builder's 500 ms pushes
      });
      assert.equal(warnings.length, 1);
      assert.match(warnings[0], /unknown-item.*urn:decentraland:unknown/);
      assert.deepEqual(simulation.warnings.map((w) => w.code), ['unknown-item']);
      simulation.dispose(scene);
      const afterDispose = await consoleWarnings(() => {
        simulation.updateParams(urn, entry);
        simulation.updateParams(urn, entry);
      });
      assert.equal(afterDispose.length, 1);
      assert.match(afterDispose[0], /unknown-item/);
    });

    test('registering an id again mid-swing takes the rest pose, not the swung one, and clears its unknown-item warning', async () => {
      const { simulation, scene, container, frame, springs, rest } = await previewScene({ itemId: 'first' });
      const warned = await consoleWarnings(() => simulation.updateParams(urn, entry));  // not registered yet
      assert.equal(warned.length, 1);
      for (let f = 0; f < 40; f++) frame(f);
      assert.ok(springs.some((n) => turn(quaternionOf(n), rest.get(n)) > 0.01), 'swinging');
      simulation.registerWearable(scene, container, 'first', entry);  // the same container again
      // A new instance starts at the rig's rest rotations: the first rest pose, not the swung one.
      const rig = simulation.rigOf('first');
      const probe = rig.createInstance();
      for (const n of springs) {
        const j = rig.joints.findIndex((joint) => joint.name === n.name);
        if (j < 0) continue;
        assert.ok(turn(Array.from(probe.rotations.subarray(4 * j, 4 * j + 4)), rest.get(n)) < 1e-6, n.name);
      }
      probe.dispose();
      simulation.registerWearable(scene, container, urn, entry);
      assert.deepEqual(simulation.warnings, [], 'the unknown-item warning went with the registration');
      for (let f = 40; f < 60; f++) frame(f);
      simulation.dispose(scene);
      for (const n of springs) assert.deepEqual(quaternionOf(n), rest.get(n), `${n.name}: back at the first rest pose`);
    });

    test('dispose, then registerWearable and start again: it simulates', async () => {
      const simulation = new SpringBoneSimulation(sb);
      const first = await previewScene({ simulation });
      for (let f = 0; f < 10; f++) first.frame(f);
      simulation.dispose(first.scene);
      const again = await previewScene({ simulation, scene: first.scene });
      let moved = 0;
      for (let f = 0; f < 40; f++) {
        again.frame(f);
        moved = Math.max(moved, ...again.springs.map((n) => turn(quaternionOf(n), again.rest.get(n))));
      }
      assert.ok(moved > 0.02, `the hair swings after the swap (${moved})`);
      assert.equal(first.springs.every((n) => turn(quaternionOf(n), first.rest.get(n)) === 0), true, 'the disposed one is at rest');
      simulation.dispose(first.scene);
    });

    describe('never silent: one console warning per wearable, with a code and the fix, and an entry in warnings', () => {
      test('the module fails to load', async () => {
        const failure = new Error('fetch failed: 404 springbones_wasm.wasm');
        const simulation = new SpringBoneSimulation(Promise.reject(failure));
        const scene = kit.scene();
        const warnings = await consoleWarnings(async () => {
          await previewScene({ simulation, scene, itemId: 'urn:a' });
          await previewScene({ simulation, scene, itemId: 'urn:b' });
          await assert.rejects(simulation.ready, (e) => e === failure);
          await previewScene({ simulation, scene, itemId: 'urn:c' });  // after the failure too
          for (let f = 0; f < 3; f++) scene.render();
        });
        assert.equal(warnings.length, 3, warnings.join('\n'));
        for (const w of warnings) assert.match(w, /\[module-failed\].*404 springbones_wasm\.wasm.*Fix:/);
        assert.deepEqual(simulation.warnings.map((w) => [w.code, w.itemId]),
          [['module-failed', 'urn:a'], ['module-failed', 'urn:b'], ['module-failed', 'urn:c']]);
        simulation.dispose(scene);
      });

      test('a promise of something that is not the module', async () => {
        const simulation = new SpringBoneSimulation(Promise.resolve({ version: '0.2.0' }));
        const scene = kit.scene();
        const warnings = await consoleWarnings(async () => {
          await previewScene({ simulation, scene });
          await assert.rejects(simulation.ready, TypeError);
        });
        assert.equal(warnings.length, 1, warnings.join('\n'));
        assert.match(warnings[0], /\[module-failed\].*expected the springbones module/);
        simulation.dispose(scene);
      });

      test('an entry whose springbone nodes have no isRoot (the preview\'s class would move them)', async () => {
        const noRoots = Object.fromEntries(Object.entries(entry).map(([name, e]) => {
          const { isRoot, ...rest } = e;
          return [name, rest];
        }));
        const simulation = new SpringBoneSimulation(sb);
        const scene = kit.scene();
        const warnings = await consoleWarnings(async () => {
          await previewScene({ simulation, scene, params: noRoots });
          for (let i = 0; i < 3; i++) simulation.updateParams(urn, noRoots);  // the Builder's pushes: no more warnings
        });
        assert.equal(warnings.length, 1, warnings.join('\n'));
        assert.match(warnings[0], /\[no-chain-root\].*Fix: add "isRoot": true to .*"SpringBone_ponytail"/);
        assert.doesNotMatch(warnings[0], /SpringBone_ponytail_3/, 'a tip-side member needs no root of its own once the chain has one');
        assert.deepEqual(simulation.warnings.map((w) => w.code), ['no-chain-root']);
        // isRoot where the message says: the warning goes, the hair moves.
        simulation.updateParams(urn, entry);
        assert.deepEqual(simulation.warnings, []);
        assert.equal(simulation.rigOf(urn).chains.length, 5);
        simulation.dispose(scene);
      });

      test('a hash or an entry that matches nothing', async () => {
        const simulation = new SpringBoneSimulation(sb);
        const scene = kit.scene();
        const warnings = await consoleWarnings(async () => {
          await previewScene({ simulation, scene, itemId: 'wrong-hash', params: { springBones: metadata, contentHash: 'bafkreiwrong' } });
          await previewScene({ simulation, scene, itemId: 'other-file', params: { Other_springbone: { isRoot: true } } });
        });
        assert.equal(warnings.length, 2, warnings.join('\n'));
        assert.match(warnings[0], /\[model-not-found\] wearable wrong-hash: .*Fix:/);
        assert.match(warnings[1], /\[entry-not-matched\] wearable other-file: .*"Other_springbone".*Fix:/);
        assert.deepEqual(simulation.warnings.map((w) => w.code), ['model-not-found', 'entry-not-matched']);
        simulation.dispose(scene);
      });

      test('avatar bones the adapter cannot find', async () => {
        const simulation = new SpringBoneSimulation(sb);
        const scene = kit.scene();
        const colliders = [{ node: 'Avatar_NotInThisScene', shape: 'sphere', radius: 0.1 }];
        const warnings = await consoleWarnings(async () => {
          await previewScene({ simulation, scene, params: { springBones: metadata, contentHash: hash, colliders } });
        });
        assert.equal(warnings.length, 1, warnings.join('\n'));
        assert.match(warnings[0], /\[bone-not-matched\].*"Avatar_NotInThisScene".*colliders.*Fix:/);
        assert.deepEqual(simulation.warnings.map((w) => w.code), ['bone-not-matched']);
        simulation.dispose(scene);
      });

      test('metadata the core rejects: a warning, not a throw', async () => {
        const simulation = new SpringBoneSimulation(sb);
        const scene = kit.scene();
        const warnings = await consoleWarnings(async () => {
          await previewScene({ simulation, scene, params: { version: 1, models: 3 } });
        });
        assert.equal(warnings.length, 1);
        assert.match(warnings[0], /\[rig-failed\].*metadata-invalid/);
        assert.equal(simulation.rigOf(urn), null);
        simulation.dispose(scene);
      });
    });

    test('sideways gravity: the standard\'s glTF reading by default, the preview\'s scene reading as an option', async () => {
      const sideways = Object.fromEntries(Object.entries(entry).map(([name, e]) => [name, { ...e, gravityPower: 2, gravityDir: [1, 0, 0], stiffness: 0.2 }]));
      /** How far the ponytail's tip leans along the scene's +X after 2 s, in a scene of either hand. */
      const lean = async (options, rightHanded) => {
        const scene = kit.scene({ rightHanded });
        const simulation = new SpringBoneSimulation(sb, options);
        const { container } = await previewScene({ simulation, scene, params: sideways });
        const tip = nodeNamed(container, 'SpringBone_ponytail_3');
        const x0 = tip.getAbsolutePosition().x;
        for (let f = 0; f < 120; f++) scene.render();
        const x = tip.getAbsolutePosition().x - x0;
        simulation.dispose(scene);
        return x;
      };
      const gltf = await lean({}, false);
      const preview = await lean({ gravityDirSpace: 'scene' }, false);
      assert.ok(gltf < -0.01, `glTF reading: toward the file's +X, the left-handed scene's -X (${gltf})`);
      assert.ok(preview > 0.01, `scene reading: toward the scene's +X, as the preview leans (${preview})`);
      // A right-handed scene has the glTF's axes: both readings agree.
      const [a, b] = [await lean({}, true), await lean({ gravityDirSpace: 'scene' }, true)];
      assert.ok(a > 0.01 && Math.abs(a - b) < 1e-6, `right-handed: ${a} and ${b}`);
      assert.throws(() => new SpringBoneSimulation(sb, { gravityDirSpace: 'babylon' }), RangeError);
    });
  });
}

