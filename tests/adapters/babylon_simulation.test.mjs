// The Babylon.js drop-in (web/babylon/): SpringBoneSimulation with the four methods of
// Decentraland's preview class, run on Babylon's NullEngine in Babylon 4.2 (the UMD `babylonjs`,
// what the preview pins) and the current major (@babylonjs/core), with the demo's sample wearable
// loaded by Babylon's own glTF loader.
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import { dirname, join } from 'node:path';
import { before, describe, test } from 'node:test';
import { fileURLToPath } from 'node:url';
import { createSpringBones } from '../../web/springbones.js';
import { SpringBoneSimulation } from '../../web/babylon/index.js';
import { babylonKit, kBabylonVersions, readAsset, readJsonAsset } from './babylon_kit.mjs';

const here = dirname(fileURLToPath(import.meta.url));
const metadata = readJsonAsset('hair_wearable.metadata.json');
const entity = readJsonAsset('hair_wearable.entity.json');
const [hash] = Object.keys(metadata.models);
const entry = metadata.models[hash];
const glb = readAsset('hair_wearable.glb');

let sb;
before(async () => {
  sb = await createSpringBones();
});

const nodeNamed = (container, name) => [...container.transformNodes, ...container.meshes].find((n) => n.name === name);
const quaternionOf = (node) => {
  const q = node.rotationQuaternion;
  return q ? [q.x, q.y, q.z, q.w] : null;
};
const maxAbsDiff = (a, b) => Math.max(...a.map((x, i) => Math.abs(x - b[i])));

for (const which of kBabylonVersions) {
  describe(`Babylon ${which}`, () => {
    let kit;
    before(async () => {
      kit = await babylonKit(which);
    });

    /** A scene with the sample wearable registered (itemId = its hash), started. */
    async function sample({ params = entry, module = sb, itemId = hash, scene = kit.scene() } = {}) {
      const container = await kit.load(scene, glb);
      container.addAllToScene();
      const simulation = new SpringBoneSimulation(module);
      simulation.registerWearable(scene, container, itemId, params);
      simulation.start(scene);
      const head = nodeNamed(container, 'Avatar_Head');
      const rest = new Map(container.transformNodes.map((n) => [n, quaternionOf(n)]));
      /** A frame of a head swaying sideways (in its parent's space): renders the scene. */
      const frame = (f) => {
        head.position.x = 0.15 * Math.sin(f * 0.15);
        scene.render();
      };
      return { scene, container, simulation, frame, rest };
    }

    test('the rig is read from the container: the same joints, drivers and parameters as loadRig on the GLB', async () => {
      const { simulation, scene } = await sample();
      const fromContainer = simulation.rigOf(hash);
      const fromGlb = sb.loadRig(glb, metadata);
      const describeRig = (rig) => ({
        joints: rig.joints.map((j) => [j.name, j.tail, rig.joints[j.chain].name, j.params, Number(j.restLength.toFixed(6))]),
        drivers: rig.drivers.map((d) => d.name),
        warnings: rig.warnings.map((w) => w.code),
      });
      assert.deepEqual(describeRig(fromContainer), describeRig(fromGlb));
      assert.equal(fromContainer.joints.length, 15);
      assert.equal(fromContainer.chains.length, 5);
      fromGlb.dispose();
      simulation.dispose(scene);
    });

    test('every shape of springBonesParams finds the same entry', async () => {
      const shapes = [
        entry,
        metadata,
        { springBones: metadata, entity, bodyShape: 'BaseMale' },
        { springBones: metadata, contentHash: hash },
        { springBones: metadata, glb },
      ];
      for (const [i, params] of shapes.entries()) {
        const { simulation, scene } = await sample({ params, itemId: i === 1 ? hash : `item-${i}` });
        const rig = simulation.rigOf(i === 1 ? hash : `item-${i}`);
        assert.equal(rig.joints.length, 15, `shape ${i}`);
        assert.equal(rig.contentHash, i === 0 ? `item-${i}` : hash, `shape ${i}`);
        simulation.dispose(scene);
      }
    });

    test('the joints swing with the head, and every wearable steps in one scene.step per frame', async () => {
      const scene = kit.scene();
      // The module as the simulation sees it, counting the springbones scene's steps. (Every
      // instance's own step() is never called by the adapter: the rotations below change only
      // through the one scene.step.)
      let sceneSteps = 0;
      const bound = (target, key) => (typeof target[key] === 'function' ? target[key].bind(target) : target[key]);
      const counted = new Proxy(sb, {
        get: (target, key) => (key !== 'createScene' ? bound(target, key) : () => {
          const springScene = target.createScene();
          return new Proxy(springScene, {
            get: (s, k) => (k !== 'step' ? bound(s, k) : (dt) => {
              sceneSteps += 1;
              s.step(dt);
            }),
          });
        }),
      });
      const simulation = new SpringBoneSimulation(counted);
      const containers = [];
      for (const itemId of ['a', 'b', 'c']) {
        const container = await kit.load(scene, glb);
        container.addAllToScene();
        simulation.registerWearable(scene, container, itemId, { springBones: metadata, contentHash: hash });
        containers.push(container);
      }
      simulation.start(scene);
      const heads = containers.map((c) => nodeNamed(c, 'Avatar_Head'));
      const joints = containers.map((c) => nodeNamed(c, 'SpringBone_ponytail_1'));
      const rest = quaternionOf(joints[0]);
      let moved = 0;
      for (let f = 0; f < 60; f++) {
        for (const head of heads) head.position.x = 0.15 * Math.sin(f * 0.15);
        scene.render();
        moved = Math.max(moved, maxAbsDiff(quaternionOf(joints[0]), rest));
        // Three wearables under the same motion: the same rotations, bit for bit.
        assert.deepEqual(quaternionOf(joints[1]), quaternionOf(joints[0]));
        assert.deepEqual(quaternionOf(joints[2]), quaternionOf(joints[0]));
      }
      assert.ok(moved > 0.02, `the ponytail swings (${moved})`);
      assert.equal(sceneSteps, 60, 'one scene.step per rendered frame, for the three wearables');
      simulation.dispose(scene);
      assert.deepEqual(quaternionOf(joints[0]), rest, 'dispose puts the joints back at rest');
    });

    test('setWind blows every wearable, set before the module comes too; null stops it', async () => {
      const scene = kit.scene();
      let resolve;
      const simulation = new SpringBoneSimulation(new Promise((r) => { resolve = r; }));
      const gusty = { direction: [1, 0, 0], strength: 2, gustFrequency: 0.5, seed: 3 };
      simulation.setWind(gusty);  // before the module: kept
      const containers = [];
      for (const itemId of ['windy', 'calm']) {
        const container = await kit.load(scene, glb);
        container.addAllToScene();
        simulation.registerWearable(scene, container, itemId, { springBones: metadata, contentHash: hash });
        containers.push(container);
      }
      resolve(sb);
      await simulation.ready;
      const calm = new SpringBoneSimulation(sb);
      const still = await kit.load(scene, glb);
      still.addAllToScene();
      calm.registerWearable(scene, still, 'still', { springBones: metadata, contentHash: hash });
      simulation.start(scene);
      calm.start(scene);
      const tip = (c) => nodeNamed(c, 'SpringBone_ponytail_3');
      for (let f = 0; f < 90; f++) scene.render();
      const blown = maxAbsDiff(quaternionOf(tip(containers[0])), quaternionOf(tip(still)));
      assert.ok(blown > 0.02, `the wind turns the ponytail (${blown})`);
      assert.deepEqual(quaternionOf(tip(containers[1])), quaternionOf(tip(containers[0])), 'every wearable, the same gusts');
      assert.throws(() => simulation.setWind({ direction: [0, 0, 0], strength: 1 }), RangeError);
      simulation.setWind(null);
      simulation.reset();
      calm.reset();
      for (let f = 0; f < 90; f++) scene.render();
      assert.deepEqual(quaternionOf(tip(containers[0])), quaternionOf(tip(still)), 'no wind: as the calm one, bit for bit');
      simulation.dispose(scene);
      calm.dispose(scene);
    });

    test('updateParams: a removed chain is back at rest at once, an added root starts a chain, a non-root adds none', async () => {
      const { simulation, scene, container, frame, rest } = await sample();
      for (let f = 0; f < 30; f++) frame(f);
      const ponytail = nodeNamed(container, 'SpringBone_ponytail_1');
      const leftLock = nodeNamed(container, 'hair_springbone_l');
      assert.ok(maxAbsDiff(quaternionOf(ponytail), rest.get(ponytail)) > 1e-3, 'the ponytail swings');
      const { SpringBone_ponytail, SpringBone_ponytail_3, ...withoutPonytail } = entry;
      simulation.updateParams(hash, withoutPonytail);
      assert.deepEqual(quaternionOf(ponytail), rest.get(ponytail), 'at rest right after the edit, before any frame');
      for (let f = 30; f < 60; f++) frame(f);
      assert.deepEqual(quaternionOf(ponytail), rest.get(ponytail), 'and it stays there');
      assert.ok(maxAbsDiff(quaternionOf(leftLock), rest.get(leftLock)) > 1e-4, 'the other chains still move');
      assert.equal(simulation.rigOf(hash).chains.length, 4);
      // An entry without isRoot is no root by the standard's rules (the preview's class would start a chain).
      simulation.updateParams(hash, { ...withoutPonytail, SpringBone_ponytail: { ...SpringBone_ponytail, isRoot: false } });
      assert.equal(simulation.rigOf(hash).chains.length, 4);
      simulation.updateParams(hash, { ...withoutPonytail, SpringBone_ponytail });
      assert.equal(simulation.rigOf(hash).chains.length, 5);
      let moved = 0;
      for (let f = 60; f < 90; f++) {
        frame(f);
        moved = Math.max(moved, maxAbsDiff(quaternionOf(ponytail), rest.get(ponytail)));
      }
      assert.ok(moved > 1e-3, `the added chain moves at once (${moved})`);
      simulation.dispose(scene);
    });

    test('the module as a promise: registered before it resolves, at rest until it does, then simulated', async () => {
      let resolve;
      const pending = new Promise((r) => {
        resolve = r;
      });
      const { simulation, scene, container, frame, rest } = await sample({ module: pending });
      const ponytail = nodeNamed(container, 'SpringBone_ponytail_1');
      for (let f = 0; f < 20; f++) frame(f);
      assert.deepEqual(quaternionOf(ponytail), rest.get(ponytail), 'drawn at rest while the module loads');
      assert.equal(simulation.rigOf(hash), null);
      resolve(sb);
      await simulation.ready;
      assert.equal(simulation.rigOf(hash).joints.length, 15);
      let moved = 0;
      for (let f = 20; f < 60; f++) {
        frame(f);
        moved = Math.max(moved, maxAbsDiff(quaternionOf(ponytail), rest.get(ponytail)));
      }
      assert.ok(moved > 1e-3, `the springs take over once it is there (${moved})`);
      simulation.dispose(scene);
    });

    test('bad input: TypeErrors for wrong kinds of argument; rejected metadata and unknown ids are warnings', async () => {
      const scene = kit.scene();
      const simulation = new SpringBoneSimulation(sb);
      const container = await kit.load(scene, glb);
      assert.throws(() => simulation.registerWearable(scene, {}, 'x'), TypeError);
      assert.throws(() => simulation.registerWearable(scene, container, ''), TypeError);
      assert.throws(() => simulation.registerWearable({}, container, 'x'), TypeError);
      assert.throws(() => simulation.registerWearable(scene, container, 'x', [1, 2]), TypeError);
      assert.equal(simulation.rigOf('x'), null);
      const warn = console.warn;
      const warned = [];
      console.warn = (message) => warned.push(message);
      try {
        // The preview's class never throws for an entry it cannot read: neither does the drop-in.
        simulation.registerWearable(scene, container, 'x', { version: 1, models: 3 });
        simulation.updateParams('never-registered', {});
      } finally {
        console.warn = warn;
      }
      assert.equal(simulation.rigOf('x'), null);
      assert.deepEqual(simulation.warnings.map((w) => [w.code, w.itemId]), [['rig-failed', 'x'], ['unknown-item', 'never-registered']]);
      assert.equal(warned.length, 2);
      simulation.registerWearable(scene, container, 'x', entry);
      assert.throws(() => simulation.updateParams('x', null), TypeError);
      assert.throws(() => new SpringBoneSimulation({}), TypeError);
      simulation.dispose(scene);
    });

    /** babylon_frame_heap.mjs in a child process with these V8 flags: its JSON. */
    const ownAllocations = (flags) => {
      // Optimized on the main thread, where the code gets hot, so that a loaded machine does not
      // leave the measured frames running code that is not optimized yet.
      const child = spawnSync(process.execPath, ['--allow-natives-syntax', '--no-concurrent-recompilation', ...flags, join(here, 'babylon_frame_heap.mjs'), which],
        { encoding: 'utf8' });
      assert.equal(child.status, 0, child.stderr);
      return JSON.parse(child.stdout.trim().split('\n').pop());
    };

    test('a frame allocates nothing: no bytes allocated by web/babylon/ over 4,000 frames (child process)', () => {
      const { own, total, frames } = ownAllocations([]);
      assert.ok(total >= 0);
      assert.deepEqual(own, {}, `bytes allocated by web/babylon/ functions over ${frames} frames`);
    });

    test('a frame allocates nothing, with no escape analysis to hide an object (child process)', () => {
      // With the optimizing compilers off altogether the interpreter boxes every double it
      // handles (each value read from a Float32Array is a new HeapNumber), so no JavaScript is
      // allocation-free there. What optimizing could hide is a temporary object that escape
      // analysis removes: with --no-turbo-escape it is allocated, and the sampling profiler names
      // the function that allocated it (a `{}` per frame in the adapter shows as ~130 KB here).
      const { own, total, frames } = ownAllocations(['--no-turbo-escape']);
      assert.ok(total > 0, 'the profiler saw the frames (Babylon\'s own work allocates there)');
      assert.deepEqual(own, {}, `bytes allocated by web/babylon/ functions over ${frames} frames`);
    });
  });
}
