// The contract of web/springbones.js (web/springbones.d.ts): loading, the rig description,
// instances and their views, stepping, reset and dispose.
import assert from 'node:assert/strict';
import { readFile } from 'node:fs/promises';
import { before, describe, test } from 'node:test';

import { createSpringBones, SpringBonesError } from '../../web/springbones.js';
import { gltfOf } from '../../scripts/lib/fixtures/glb.mjs';
import { contentHashOf, fixture, loadFixtureRig, metadataKeyOf, springRig, swayFrames } from './helpers.mjs';
import { swayDrivers } from '../../bin/sway.mjs';

let sb;
before(async () => {
  sb = await createSpringBones();
});

const kBaseMale = 'urn:decentraland:off-chain:base-avatars:BaseMale';
const kBaseFemale = 'urn:decentraland:off-chain:base-avatars:BaseFemale';

describe('createSpringBones', () => {
  test('resolves to an object with every entry point of the runtime and stats', () => {
    for (const name of ['loadRig', 'loadVrm', 'contentHash', 'creatorTools', 'createScene', 'stats']) {
      assert.equal(typeof sb[name], 'function', name);
    }
    for (const name of ['validateSpringBones', 'detectSpringBones', 'setSpringBoneParams']) {
      assert.equal(sb[name], undefined, `${name} is a creator tool (sb.creatorTools())`);
    }
    assert.deepEqual(Object.keys(sb.stats()).sort(), ['heapBytes', 'heapInUse', 'instances', 'rigs', 'scenes']);
  });

  test('accepts the .wasm bytes from the caller', async () => {
    const bytes = await readFile(new URL('../../web/dist/springbones_wasm.wasm', import.meta.url));
    const other = await createSpringBones({ wasmBinary: bytes });
    assert.equal(other.loadRig(springRig().glb, springRig().springBones, { contentHash: 'test-hash' }).joints.length, 3);
  });

  test('creates independent modules: a rig of one is unknown to the other', async () => {
    const other = await createSpringBones();
    const { glb, springBones, hash } = springRig();
    other.loadRig(glb, springBones, { contentHash: hash });
    assert.equal(other.stats().rigs, 1);
    assert.notEqual(other.stats().heapBytes, 0);
  });

  test('rejects a missing .wasm with a SpringBonesError module-load-failed', async () => {
    await assert.rejects(createSpringBones({ wasmUrl: './does-not-exist.wasm' }),
                         (e) => e instanceof SpringBonesError && e.code === 'module-load-failed');
  });

  test('rejects bad options with TypeError before loading anything', async () => {
    await assert.rejects(createSpringBones(42), TypeError);
    await assert.rejects(createSpringBones({ wasmBinary: 'bytes' }), TypeError);
    await assert.rejects(createSpringBones({ wasmUrl: 7 }), TypeError);
    await assert.rejects(createSpringBones({ wasmURL: 'typo' }), TypeError);
  });
});

describe('creatorTools', () => {
  test('loads the creator-tools module once: every call gives the same tools', async () => {
    const other = await createSpringBones();
    const first = other.creatorTools();
    assert.equal(other.creatorTools(), first, 'a second call while loading waits for the same load');
    const tools = await first;
    for (const name of ['validateSpringBones', 'detectSpringBones', 'setSpringBoneParams', 'stats']) {
      assert.equal(typeof tools[name], 'function', name);
    }
    assert.equal(await other.creatorTools(), tools);
    assert.deepEqual(Object.keys(tools.stats()).sort(), ['heapBytes', 'heapInUse']);
    assert.equal(other.stats().rigs, 0, 'the tools leave no rig in the runtime');
  });

  test('takes the module\'s bytes or its URL, as createSpringBones does', async () => {
    const bytes = await readFile(new URL('../../web/dist/springbones_creator_tools.wasm', import.meta.url));
    const fromBytes = await (await createSpringBones()).creatorTools({ wasmBinary: bytes });
    assert.deepEqual(fromBytes.validateSpringBones({ metadata: { data: {} } }), []);
    const fromUrl = await (await createSpringBones()).creatorTools({ wasmUrl: './springbones_creator_tools.wasm' });
    assert.equal(fromUrl.detectSpringBones(springRig().glb).length, 4, 'three joints and the tip');
  });

  test('a failed load rejects with module-load-failed, bad options with TypeError, and the next call tries again', async () => {
    const other = await createSpringBones();
    await assert.rejects(other.creatorTools({ wasmUrl: './does-not-exist.wasm' }),
                         (e) => e instanceof SpringBonesError && e.code === 'module-load-failed');
    await assert.rejects(other.creatorTools(42), TypeError);
    await assert.rejects(other.creatorTools({ wasmURL: 'typo' }), TypeError);
    await assert.rejects(other.creatorTools({ wasmBinary: 'bytes' }), TypeError);
    const tools = await other.creatorTools();
    assert.equal(typeof tools.validateSpringBones, 'function');
  });

  test('detectSpringBones reads the entity through the runtime, as loadRig does', async () => {
    const tools = await sb.creatorTools();
    const { glb, springBones, hash } = springRig();
    const entity = { content: [{ file: 'a.glb', hash }], metadata: { data: { representations: [
      { bodyShapes: [kBaseMale], mainFile: 'a.glb' }] } } };
    const byEntity = tools.detectSpringBones(glb, springBones, { entity, bodyShape: kBaseMale });
    assert.deepEqual(byEntity, tools.detectSpringBones(glb, springBones, { contentHash: hash }));
    assert.ok(byEntity.some((c) => c.hasEntry));
    assert.throws(() => tools.detectSpringBones(glb, springBones, { entity, bodyShape: kBaseFemale }),
                  (e) => e instanceof SpringBonesError && e.code === 'invalid-argument');
  });
});

describe('loadRig', () => {
  test('describes the chains, drivers and warnings of the hair fixture as frozen plain data', () => {
    const rig = loadFixtureRig(sb, 'avatar_hair.glb');
    assert.equal(rig.contentHash, metadataKeyOf('avatar_hair.glb'));
    assert.ok(rig.joints.length > 10);
    assert.deepEqual(rig.drivers.map((d) => d.name), ['Avatar_Head', 'Avatar_Hips']);
    const hair = rig.joints.find((j) => j.name === 'SpringBone_hair_left');
    assert.deepEqual(hair.params, { stiffness: 1.5, gravityPower: 0.5, gravityDir: [0, -1, 0], drag: 0.4 });
    assert.equal(hair.tail, 'SpringBone_hair_left_1');
    assert.equal(rig.joints.find((j) => j.name === 'SpringBone_hair_left_1').node, hair.tailNode);
    const tailTranslation = gltfOf(fixture('avatar_hair.glb')).nodes[hair.tailNode].translation;
    hair.tailOffset.forEach((v, k) => assert.ok(Math.abs(v - tailTranslation[k]) < 1e-6, 'the tail child\'s translation'));
    assert.equal(hair.hitRadius, 0);
    assert.equal(rig.format, 'dcl');
    assert.deepEqual(rig.colliders, []);
    assert.equal(hair.parent, -1);
    assert.equal(rig.drivers[hair.parentDriver].name, 'Avatar_Head');
    assert.equal(rig.joints[hair.chain], hair);
    for (const [i, j] of rig.joints.entries()) {
      assert.ok(j.parent < i, 'parents come before children');
      assert.ok(rig.chains.includes(j.chain));
    }
    assert.ok(rig.warnings.some((w) => w.code === 'center-not-found' && w.path.endsWith('/SpringBone_ribbon/center')));
    for (const w of rig.warnings) assert.deepEqual(Object.keys(w).sort(), ['code', 'message', 'path']);

    assert.ok(Object.isFrozen(rig) && Object.isFrozen(rig.joints) && Object.isFrozen(hair.params.gravityDir));
    assert.throws(() => { rig.joints[0].name = 'x'; }, TypeError);
    assert.throws(() => { rig.joints.push({}); }, TypeError);
    assert.throws(() => { rig.warnings[0].code = 'x'; }, TypeError);
  });

  test('the description lists are built once, stay readable after dispose, and keep names and shortest floats', () => {
    const nodes = [
      { name: 'Avatar_Head', children: [1] },
      { name: 'springbone_été_中', translation: [0.1, 2097152.25, -0], children: [2] },
      { name: 'springbone_tip', translation: [0.30000001192092896, -0.05, 1e-30] },
    ];
    const glb = new TextEncoder().encode(JSON.stringify({ asset: { version: '2.0' }, nodes }));
    const springBones = { version: 1, models: { h: { [nodes[1].name]: {
      isRoot: true, stiffness: 0.4, gravityPower: 1.1, gravityDir: [0, -3, 0], drag: 0.123456789 } } } };
    const rig = sb.loadRig(glb, springBones, { contentHash: 'h', hitRadius: 0.07, colliders: [{ node: 'Avatar_Head', radius: 0.2 }] });
    const first = rig.joints;
    assert.equal(rig.joints, first, 'the same frozen array on every read');
    assert.equal(rig.drivers, rig.drivers);
    assert.equal(rig.warnings, rig.warnings);
    const [joint] = first;
    assert.equal(joint.name, nodes[1].name);
    assert.equal(joint.tail, 'springbone_tip');
    assert.deepEqual(joint.params, { drag: 0.12345679, gravityDir: [0, -1, 0], gravityPower: 1.1, stiffness: 0.4 });
    assert.equal(joint.hitRadius, 0.07);
    assert.deepEqual(joint.tailOffset, [0.3, -0.05, 1e-30], 'the shortest decimal that reads back as the float');
    assert.deepEqual(Object.keys(joint), ['centerDriver', 'chain', 'hitRadius', 'limit', 'name', 'node', 'params', 'parent',
      'parentDriver', 'restLength', 'tail', 'tailNode', 'tailOffset']);
    assert.equal(joint.limit, null);
    assert.deepEqual(rig.drivers, [{ name: 'Avatar_Head', node: 0 }]);
    assert.deepEqual(rig.colliders, [{ driver: 0, node: 'Avatar_Head', offset: [0, 0, 0], radius: 0.2, shape: 'sphere', inside: false }]);
    const drivers = rig.drivers;
    rig.dispose();
    assert.equal(rig.joints, first);
    assert.equal(rig.drivers, drivers);
    assert.deepEqual(rig.chains, [0]);
    // Never read before dispose: still there.
    const other = sb.loadRig(glb, springBones, { contentHash: 'h', hitRadius: 0.07, colliders: [{ node: 'Avatar_Head', radius: 0.2 }] });
    other.dispose();
    assert.deepEqual(other.joints, first);
    assert.deepEqual(other.colliders, rig.colliders);
    assert.equal(other.nodeCount, 3);
  });

  test('takes GLB bytes as Uint8Array, Buffer or ArrayBuffer (a subarray is read from its offset)', () => {
    const { glb, springBones, hash } = springRig();
    const padded = new Uint8Array(glb.length + 8);
    padded.set(glb, 4);
    for (const bytes of [glb, Buffer.from(glb), glb.slice().buffer, padded.subarray(4, 4 + glb.length)]) {
      assert.equal(sb.loadRig(bytes, springBones, { contentHash: hash }).joints.length, 3);
    }
  });

  test('takes springBones as an object or as JSON text, with the same rig, warnings and errors', () => {
    const { glb, springBones, hash } = springRig({ chains: 2 });
    // One entry out of range and one missing its params: warnings as well as joints.
    const [first, second] = Object.keys(springBones.models[hash]);
    springBones.models[hash][first] = { ...springBones.models[hash][first], drag: 7 };
    springBones.models[hash][second] = {};
    const a = sb.loadRig(glb, springBones, { contentHash: hash });
    const b = sb.loadRig(glb, JSON.stringify(springBones), { contentHash: hash });
    assert.deepEqual(a.joints, b.joints);
    assert.deepEqual(a.drivers, b.drivers);
    assert.ok(a.warnings.some((w) => w.code === 'param-out-of-range'));
    assert.ok(a.warnings.some((w) => w.code === 'param-missing'));
    assert.deepEqual(a.warnings, b.warnings);
    const errorOf = (load) => {
      try {
        load();
      } catch (error) {
        return { code: error.code, message: error.message, path: error.path };
      }
      assert.fail('expected an error');
    };
    const broken = { version: 1, models: { [hash]: 42 } };
    const fromObject = errorOf(() => sb.loadRig(glb, broken, { contentHash: hash }));
    assert.equal(fromObject.code, 'metadata-invalid');
    assert.deepEqual(fromObject, errorOf(() => sb.loadRig(glb, JSON.stringify(broken), { contentHash: hash })));
  });

  test('null or undefined springBones means no spring bones and no warning', () => {
    const { glb } = springRig();
    for (const none of [null, undefined]) {
      const rig = sb.loadRig(glb, none);
      assert.equal(rig.joints.length, 0);
      assert.equal(rig.drivers.length, 0);
      assert.deepEqual(rig.warnings, []);
    }
  });

  test('without a hash, uses the GLB content hash, the same one @dcl/hashing computes', () => {
    const rig = sb.loadRig(fixture('avatar_hair.glb'), fixture('avatar_hair.metadata.json').toString());
    assert.equal(rig.contentHash, contentHashOf('avatar_hair.glb'));
    assert.ok(rig.joints.length > 10);
    assert.equal(sb.contentHash(fixture('adr_example.glb')), contentHashOf('adr_example.glb'));
  });

  test('an entry for another hash gives no joints and a model-not-found warning', () => {
    const rig = sb.loadRig(fixture('adr_example.glb'), fixture('adr_example.metadata.json').toString());
    assert.equal(rig.joints.length, 0);
    assert.equal(rig.warnings[0].code, 'model-not-found');
  });

  test('with {entity, bodyShape}, uses the hash of that body shape\'s main file', () => {
    const { glb, springBones } = springRig({ hash: 'hash-of-male-glb' });
    springBones.models['hash-of-female-glb'] = {};
    const entity = {
      content: [{ file: 'male.glb', hash: 'hash-of-male-glb' }, { file: 'female.glb', hash: 'hash-of-female-glb' }],
      metadata: { data: { representations: [
        { bodyShapes: [kBaseMale], mainFile: 'male.glb', contents: ['male.glb'] },
        { bodyShapes: [kBaseFemale], mainFile: 'female.glb', contents: ['female.glb'] },
      ] } },
    };
    const male = sb.loadRig(glb, springBones, { entity, bodyShape: kBaseMale });
    assert.equal(male.contentHash, 'hash-of-male-glb');
    assert.equal(male.joints.length, 3);
    const female = sb.loadRig(glb, springBones, { entity: JSON.stringify(entity), bodyShape: 'BaseFemale' });
    assert.equal(female.contentHash, 'hash-of-female-glb');
    assert.equal(female.joints.length, 0);
    // The caller's contentHash comes first (docs/semantics.md, Which models entry).
    assert.equal(sb.loadRig(glb, springBones, { contentHash: 'x', entity, bodyShape: kBaseMale }).contentHash, 'x');
  });
});

describe('instances', () => {
  test('views have 16 floats per driver and 4 per joint; rotations start at the rest rotations', () => {
    const glb = fixture('avatar_hair.glb');
    const nodes = gltfOf(glb).nodes;
    const rig = loadFixtureRig(sb, 'avatar_hair.glb');
    const inst = rig.createInstance();
    assert.ok(inst.driverMatrices instanceof Float32Array);
    assert.equal(inst.driverMatrices.length, 16 * rig.drivers.length);
    assert.equal(inst.rotations.length, 4 * rig.joints.length);
    rig.joints.forEach((j, i) => {
      const rest = nodes[j.node].rotation ?? [0, 0, 0, 1];
      assert.deepEqual(Array.from(inst.rotations.subarray(4 * i, 4 * i + 4)), rest.map(Math.fround));
    });
    // Drivers start at their rest world matrices: a rigid transform with a bottom row 0 0 0 1.
    const m = inst.driverMatrices;
    assert.deepEqual([m[3], m[7], m[11], m[15]], [0, 0, 0, 1]);
  });

  test('a view is the same object on every read while memory does not grow (nothing allocated per frame)', () => {
    const inst = loadFixtureRig(sb, 'avatar_hair.glb').createInstance();
    assert.equal(inst.rotations, inst.rotations);
    assert.equal(inst.driverMatrices, inst.driverMatrices);
    inst.step(1 / 60);
    assert.equal(inst.rotations, inst.rotations);
  });

  test('moving the drivers moves the chains; dt 0 and negative dt change nothing', () => {
    const inst = loadFixtureRig(sb, 'avatar_hair.glb').createInstance();
    const atRest = Float32Array.from(inst.rotations);
    swayFrames(inst, 30);
    const moved = Float32Array.from(inst.rotations);
    assert.notDeepEqual(moved, atRest);
    for (const r of moved) assert.ok(Number.isFinite(r));
    inst.step(0);
    inst.step(-1);
    assert.deepEqual(inst.rotations, moved);
  });

  test('reset() restarts from rest: the next step matches a fresh instance', () => {
    const rig = loadFixtureRig(sb, 'avatar_hair.glb');
    const a = rig.createInstance();
    swayFrames(a, 40);
    a.reset();
    const b = rig.createInstance();
    b.driverMatrices.set(a.driverMatrices);
    a.step(1 / 60);
    b.step(1 / 60);
    assert.deepEqual(a.rotations, b.rotations);
  });

  test('options: stepHz and maxSubsteps change how many steps a frame runs', () => {
    const rig = loadFixtureRig(sb, 'avatar_hair.glb');
    const run = (options, dt, frames) => {
      const inst = rig.createInstance(options);
      const rest = Float32Array.from(inst.driverMatrices);
      for (let k = 1; k <= frames; ++k) {
        swayDrivers(rest, inst.driverMatrices, k * dt);
        inst.step(dt);
      }
      return Float32Array.from(inst.rotations);
    };
    assert.deepEqual(run({ stepHz: 60, maxSubsteps: 4, integrator: 'vrm' }, 1 / 60, 30), run(undefined, 1 / 60, 30));
    assert.notDeepEqual(run({ stepHz: 120 }, 1 / 60, 30), run({ stepHz: 60 }, 1 / 60, 30));
    assert.notDeepEqual(run({ maxSubsteps: 1 }, 1 / 20, 30), run({ maxSubsteps: 4 }, 1 / 20, 30));
  });

  test('two instances of one rig are independent', () => {
    const rig = loadFixtureRig(sb, 'avatar_hair.glb');
    const a = rig.createInstance();
    const b = rig.createInstance();
    const rest = Float32Array.from(a.driverMatrices);
    swayDrivers(rest, a.driverMatrices, 0.5);
    for (let k = 0; k < 20; ++k) a.step(1 / 60);
    for (let k = 0; k < 20; ++k) b.step(1 / 60);
    assert.notDeepEqual(a.rotations, b.rotations);
    assert.deepEqual(Array.from(b.driverMatrices), Array.from(rest));
  });
});

describe('dispose', () => {
  test('instance: idempotent, then every use throws SpringBonesError disposed', () => {
    const inst = loadFixtureRig(sb, 'avatar_hair.glb').createInstance();
    assert.equal(inst.disposed, false);
    inst.dispose();
    inst.dispose();
    assert.equal(inst.disposed, true);
    const disposed = (e) => e instanceof SpringBonesError && e.code === 'disposed';
    assert.throws(() => inst.step(1 / 60), disposed);
    assert.throws(() => inst.reset(), disposed);
    assert.throws(() => inst.rotations, disposed);
    assert.throws(() => inst.driverMatrices, disposed);
  });

  test('rig: createInstance throws disposed afterwards; its live instances keep working', () => {
    const before = sb.stats();
    const rig = loadFixtureRig(sb, 'avatar_hair.glb');
    const inst = rig.createInstance();
    rig.dispose();
    rig.dispose();
    assert.equal(rig.disposed, true);
    assert.throws(() => rig.createInstance(), (e) => e instanceof SpringBonesError && e.code === 'disposed');
    assert.ok(rig.joints.length > 0, 'the description stays readable');
    swayDrivers(Float32Array.from(inst.driverMatrices), inst.driverMatrices, 0.3);
    inst.step(1 / 60);
    assert.ok(inst.rotations.every(Number.isFinite));
    assert.equal(sb.stats().rigs, before.rigs);
    assert.equal(sb.stats().instances, before.instances + 1);
    inst.dispose();
    assert.deepEqual([sb.stats().rigs, sb.stats().instances], [before.rigs, before.instances]);
  });
});
