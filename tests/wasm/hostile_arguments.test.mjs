// Adversarial arguments through the JS API, one class of defect per describe block (issue 31,
// "Never silent, everywhere" item 7): what JSON.stringify, TextEncoder or a float32 would silently
// change is refused with a TypeError or RangeError that says so, or made to work; a load error
// names what was read.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { describe, test } from 'node:test';

import { createSpringBones, SpringBonesError } from '../../web/springbones.js';
import { createSpringBones as createInline } from '../../web/inline.js';
import { kBinarySource } from '../../web/module_loader.js';
import { springRig } from './helpers.mjs';

const sb = await createSpringBones();
const tools = await sb.creatorTools();

const kBaseMale = 'urn:decentraland:off-chain:base-avatars:BaseMale';
const kHash = 'bafkreiadversarial';
const entity = {
  content: [{ file: 'hair.glb', hash: kHash }],
  metadata: { data: { representations: [{ bodyShapes: [kBaseMale], mainFile: 'hair.glb', contents: ['hair.glb'] }] } },
};
const params = { stiffness: 1, gravityPower: 0.5, gravityDir: [0, -1, 0], drag: 0.4, isRoot: true };

// `fn` throws `type` (TypeError or RangeError, never a SpringBonesError) and its message matches.
function refuses(type, pattern, fn) {
  assert.throws(fn, (e) => {
    assert.equal(e.constructor, type, `${e.constructor.name}: ${e.message}`);
    assert.match(e.message, pattern);
    return true;
  });
}

const sparse = (values) => {
  const out = [...values];
  delete out[1];
  return out;
};

describe('sparse arrays are TypeErrors, like undefined entries', () => {
  const { glb, springBones, hash } = springRig({ hash: kHash });
  const sphere = { node: 'Avatar_Head', radius: 0.1 };

  test('loadRig colliders with a hole', () => {
    refuses(TypeError, /colliders\[1\] is a hole/, () => sb.loadRig(glb, springBones, { contentHash: hash, colliders: sparse([sphere, sphere, sphere]) }));
    refuses(TypeError, /colliders\[0\]/, () => sb.loadRig(glb, springBones, { contentHash: hash, colliders: new Array(1) }));
    refuses(TypeError, /colliders\[1\] is undefined/, () => sb.loadRig(glb, springBones, { contentHash: hash, colliders: [sphere, undefined] }));
  });

  test('vectors with a hole (offset, tail, normal, wind direction)', () => {
    refuses(TypeError, /offset\[1\] is a hole/, () => sb.loadRig(glb, springBones, { contentHash: hash, colliders: [{ ...sphere, offset: sparse([0, 0, 0]) }] }));
    refuses(TypeError, /tail\[1\] is a hole/, () => sb.loadRig(glb, springBones, { contentHash: hash, colliders: [{ ...sphere, tail: sparse([0, 0, 0]) }] }));
    refuses(TypeError, /normal\[1\] is a hole/, () => sb.loadRig(glb, springBones, { contentHash: hash, colliders: [{ node: 'Avatar_Head', shape: 'plane', normal: sparse([0, 0, 1]) }] }));
    const instance = sb.loadRig(glb, springBones, { contentHash: hash }).createInstance();
    refuses(TypeError, /direction\[1\] is a hole/, () => instance.setWind({ direction: sparse([1, 0, 0]), strength: 1 }));
    refuses(TypeError, /direction\[2\] is undefined/, () => instance.setWind({ direction: [1, 0, undefined], strength: 1 }));
  });

  test('holes anywhere in springBones, an entity or params (JSON would write null)', () => {
    const withHole = structuredClone(springBones);
    withHole.models[hash].SpringBone_0_0.gravityDir = sparse([0, -1, 0]);
    refuses(TypeError, /springBones\.models\.bafkreiadversarial\.SpringBone_0_0\.gravityDir\[1\] is a hole/, () => sb.loadRig(glb, withHole, { contentHash: hash }));
    const withUndefined = structuredClone(springBones);
    withUndefined.models[hash].SpringBone_0_0.gravityDir = [0, undefined, -1];
    refuses(TypeError, /gravityDir\[1\] is undefined/, () => sb.loadRig(glb, withUndefined, { contentHash: hash }));

    const holeyEntity = structuredClone(entity);
    holeyEntity.content = sparse([entity.content[0], entity.content[0], entity.content[0]]);
    refuses(TypeError, /entity\.content\[1\] is a hole/, () => sb.loadRig(glb, springBones, { entity: holeyEntity, bodyShape: kBaseMale }));
    refuses(TypeError, /entity\.content\[1\] is a hole/, () => tools.setSpringBoneParams(null, holeyEntity, kBaseMale, 'SpringBone_0_0', params));
    refuses(TypeError, /params\.gravityDir\[1\] is a hole/, () => tools.setSpringBoneParams(null, entity, kBaseMale, 'SpringBone_0_0', { ...params, gravityDir: sparse([0, -1, 0]) }));
    refuses(TypeError, /hole/, () => tools.detectSpringBones(glb, withHole));
    refuses(TypeError, /hole/, () => tools.validateSpringBones(holeyEntity));
  });

  test('a dense array still loads as before', () => {
    const rig = sb.loadRig(glb, springBones, { contentHash: hash, colliders: [sphere, sphere] });
    assert.equal(rig.colliders.length, 2);
    rig.dispose();
  });
});

describe('setSpringBoneParams refuses non-finite numbers at any depth, and typed arrays', () => {
  const edit = (p, springBones = null, e = entity) => tools.setSpringBoneParams(springBones, e, kBaseMale, 'SpringBone_0_0', p);

  test('NaN and Infinity at the top level and nested', () => {
    refuses(RangeError, /params\.stiffness must be finite, got NaN/, () => edit({ ...params, stiffness: NaN }));
    refuses(RangeError, /params\.gravityDir\[2\] must be finite, got -Infinity/, () => edit({ ...params, gravityDir: [0, 0, -Infinity] }));
    refuses(RangeError, /params\.extra\.deep\[0\]\.x must be finite, got Infinity/, () => edit({ ...params, extra: { deep: [{ x: Infinity }] } }));
    refuses(RangeError, /params\.gravityDir\[0\]\[0\] must be finite/, () => edit({ ...params, gravityDir: [[NaN], 0, 0] }));
  });

  test('NaN in the springBones or entity argument', () => {
    const springBones = { version: 1, models: { [kHash]: { SpringBone_0_0: { ...params, drag: NaN } } } };
    refuses(RangeError, /springBones\.models\.bafkreiadversarial\.SpringBone_0_0\.drag must be finite/, () => edit(params, springBones));
    refuses(RangeError, /entity\.metadata\.data\.x must be finite/, () => edit(params, null, { ...entity, metadata: { data: { ...entity.metadata.data, x: Infinity } } }));
  });

  test('typed arrays (JSON writes an object of indices)', () => {
    refuses(TypeError, /params\.gravityDir is a Float32Array/, () => edit({ ...params, gravityDir: new Float32Array([0, -1, 0]) }));
    refuses(TypeError, /params\.a\.b is a Float64Array/, () => edit({ ...params, a: { b: new Float64Array(3) } }));
    refuses(TypeError, /params must be an object/, () => edit(new Float32Array(4)));
    refuses(TypeError, /DataView/, () => edit({ ...params, view: new DataView(new ArrayBuffer(4)) }));
  });

  test("what toJSON() returns is checked like the value itself", () => {
    refuses(RangeError, /must be finite, got NaN/, () => edit({ toJSON: () => ({ ...params, stiffness: NaN }) }));
    refuses(RangeError, /params\.gravityDir\[1\] must be finite/, () => edit({ ...params, gravityDir: { toJSON: () => [0, NaN, 0] } }));
    refuses(TypeError, /Float32Array/, () => edit({ ...params, gravityDir: { toJSON: () => new Float32Array(3) } }));
    refuses(TypeError, /hole/, () => edit({ ...params, gravityDir: { toJSON: () => sparse([0, -1, 0]) } }));
    // A toJSON giving no object would write null (removing the entry) or another kind of value.
    refuses(TypeError, /params must be an object.*toJSON/, () => edit({ toJSON: () => null }));
    refuses(TypeError, /params must be an object.*toJSON/, () => edit({ toJSON: () => [1, 2] }));
    refuses(TypeError, /params must be an object.*toJSON/, () => edit({ toJSON: () => undefined }));
    // A toJSON giving a good object is written.
    const out = edit({ toJSON: () => params });
    assert.equal(out.models[kHash].SpringBone_0_0.stiffness, 1);
  });

  test('finite values at every depth are written unchanged', () => {
    const out = edit({ ...params, gravityDir: [1e-300, -1e300, 0] });
    assert.deepEqual(out.models[kHash].SpringBone_0_0.gravityDir, [1e-300, -1e300, 0]);
  });
});

describe('a name with a lone surrogate is refused everywhere alike', () => {
  const { glb, springBones, hash } = springRig({ hash: kHash });
  const lone = ['Hair_springbone\uD800', 'Hair_\uDC00springbone', '\uDBFF'];

  for (const name of lone) {
    const shown = JSON.stringify(name);
    test(`${shown} as a collider node, contentHash, bodyShape, nodeName`, () => {
      refuses(RangeError, /colliders\[0\]\.node contains a lone surrogate/, () => sb.loadRig(glb, springBones, { contentHash: hash, colliders: [{ node: name, radius: 0.1 }] }));
      refuses(RangeError, /contentHash contains a lone surrogate/, () => sb.loadRig(glb, springBones, { contentHash: name }));
      refuses(RangeError, /bodyShape contains a lone surrogate/, () => sb.loadRig(glb, springBones, { entity, bodyShape: name }));
      refuses(RangeError, /nodeName contains a lone surrogate/, () => tools.setSpringBoneParams(null, entity, kBaseMale, name, params));
      refuses(RangeError, /bodyShape contains a lone surrogate/, () => tools.setSpringBoneParams(null, entity, name, 'SpringBone_0_0', params));
      refuses(RangeError, /bodyShape contains a lone surrogate/, () => tools.detectSpringBones(glb, springBones, { entity, bodyShape: name }));
    });

    test(`${shown} as a key or value in springBones, an entity or params, as objects or JSON text`, () => {
      const asKey = { version: 1, models: { [hash]: { [name]: params } } };
      refuses(RangeError, /springBones\.models\.bafkreiadversarial\[.*\]: its key contains a lone surrogate/, () => sb.loadRig(glb, asKey, { contentHash: hash }));
      // JSON text with the surrogate itself in it (JSON.stringify would escape it as \\udXXX,
      // which the core's parser refuses: metadata-bad-json, tests/wasm/hostile_input.test.mjs).
      const asText = `{"version":1,"models":{"${hash}":{"${name}":${JSON.stringify(params)}}}}`;
      refuses(RangeError, /springBones contains a lone surrogate/, () => sb.loadRig(glb, asText, { contentHash: hash }));
      refuses(RangeError, /springBones contains a lone surrogate/, () => tools.setSpringBoneParams(asText, entity, kBaseMale, 'SpringBone_0_0', params));
      refuses(RangeError, /lone surrogate/, () => tools.setSpringBoneParams(asKey, entity, kBaseMale, 'SpringBone_0_0', params));
      refuses(RangeError, /params\.center contains a lone surrogate/, () => tools.setSpringBoneParams(null, entity, kBaseMale, 'SpringBone_0_0', { ...params, center: name }));
      const badEntity = { ...entity, content: [{ file: name, hash: kHash }] };
      refuses(RangeError, /entity\.content\[0\]\.file contains a lone surrogate/, () => tools.setSpringBoneParams(null, badEntity, kBaseMale, 'SpringBone_0_0', params));
      const badEntityText = JSON.stringify(entity).replace('hair.glb', name);
      refuses(RangeError, /entity contains a lone surrogate/, () => tools.setSpringBoneParams(null, badEntityText, kBaseMale, 'SpringBone_0_0', params));
      refuses(RangeError, /entity\.content\[0\]\.file contains a lone surrogate/, () => tools.validateSpringBones(badEntity));
      refuses(RangeError, /entity contains a lone surrogate/, () => tools.validateSpringBones(badEntityText));
      refuses(RangeError, /entity contains a lone surrogate/, () => sb.loadRig(glb, springBones, { entity: badEntityText, bodyShape: kBaseMale }));
      refuses(RangeError, /springBones.*lone surrogate/, () => tools.detectSpringBones(glb, asKey));
    });
  }

  test('a well-formed pair (an emoji) is kept, never replaced', () => {
    const name = 'Hair_springbone\u{1F600}';
    const out = tools.setSpringBoneParams(null, entity, kBaseMale, name, params);
    assert.deepEqual(Object.keys(out.models[kHash]), [name]);
  });
});

describe('a direction whose float32 length overflows or underflows works', () => {
  const { glb, springBones, hash } = springRig({ hash: kHash, params: { gravityPower: 0, stiffness: 0.2 } });
  const rig = sb.loadRig(glb, springBones, { contentHash: hash });

  // Rotations after 60 frames under a wind.
  function blown(wind) {
    const instance = rig.createInstance();
    instance.setWind(wind);
    for (let i = 0; i < 60; ++i) instance.step(1 / 60);
    const out = Array.from(instance.rotations);
    instance.dispose();
    return out;
  }

  test('wind directions of any finite size blow as the unit one does', () => {
    const calm = blown(null);
    const reference = blown({ direction: [1, 0, 0], strength: 2 });
    assert.notDeepEqual(reference, calm, 'the wind moves the chain');
    for (const size of [1e20, 1e-25, 1e39, 1e-46, 1e300, 5e-324]) {
      assert.deepEqual(blown({ direction: [size, 0, 0], strength: 2 }), reference, `direction [${size}, 0, 0]`);
    }
    // Components of different sizes keep their ratio.
    const diagonal = blown({ direction: [1, 0, 1], strength: 2 });
    for (const size of [1e20, 1e-25, 1e39, 1e-40]) {
      const rotations = blown({ direction: [size, 0, size], strength: 2 });
      rotations.forEach((v, i) => assert.ok(Math.abs(v - diagonal[i]) < 1e-6, `direction [${size}, 0, ${size}]`));
    }
  });

  test("a scene's wind alike", () => {
    const reference = blown({ direction: [0, 0, 1], strength: 2 });
    const instance = rig.createInstance();
    const scene = sb.createScene();
    scene.add(instance);
    scene.setWind({ direction: [0, 0, 1e-30], strength: 2 });
    for (let i = 0; i < 60; ++i) scene.step(1 / 60);
    assert.deepEqual(Array.from(instance.rotations), reference);
    scene.dispose();
    instance.dispose();
  });

  test('plane collider normals of any finite size are the unit normal', () => {
    for (const size of [1e20, 1e-25, 1e39, 1e-46, 1e300]) {
      const planeRig = sb.loadRig(glb, springBones, { contentHash: hash, colliders: [{ node: 'Avatar_Head', shape: 'plane', normal: [0, size, 0] }] });
      assert.deepEqual(planeRig.warnings, [], `normal [0, ${size}, 0]`);
      assert.deepEqual(planeRig.colliders[0].normal, [0, 1, 0], `normal [0, ${size}, 0]`);
      planeRig.dispose();
    }
  });
});

describe('a load error names what was actually read', () => {
  const garbage = new Uint8Array([0, 97, 115, 109, 1, 0, 0, 0, 1, 2, 3]);
  const failed = (pattern) => (e) => {
    assert.ok(e instanceof SpringBonesError, `${e}`);
    assert.equal(e.code, 'module-load-failed');
    assert.match(e.message, pattern);
    return true;
  };

  test('wasmBinary: the option, not the default URL', async () => {
    await assert.rejects(createSpringBones({ wasmBinary: garbage }), failed(/the wasmBinary option/));
    await assert.rejects(createSpringBones({ wasmBinary: garbage }), (e) => !e.message.includes('springbones_wasm.wasm'));
    await assert.rejects(createInline({ wasmBinary: garbage }), failed(/the wasmBinary option/));
    await assert.rejects(sb.creatorTools.call(await createSpringBones(), { wasmBinary: garbage }), failed(/the wasmBinary option/));
  });

  test('the inline module names itself', async () => {
    // What inline.js passes: its own bytes under the name it gives them.
    await assert.rejects(createSpringBones({ wasmBinary: garbage, [kBinarySource]: 'the inline module' }), failed(/the inline module/));
    assert.ok((await createInline()).version);
  });

  test('a URL: the URL read', async () => {
    const url = new URL('../../web/dist/missing-module.wasm', import.meta.url);
    await assert.rejects(createSpringBones({ wasmUrl: url }), failed(/missing-module\.wasm/));
    const wrongModule = new URL('../../web/dist/springbones_creator_tools.wasm', import.meta.url);
    // The creator tools' module is a module, but not the runtime's: its glue fails on it.
    await assert.rejects(createSpringBones({ wasmUrl: wrongModule }), failed(/springbones_creator_tools\.wasm/));
    assert.ok(readFileSync(wrongModule).length > 0);
  });
});

describe('a value the core would zero or ignore because it is out of range warns', () => {
  const { glb, springBones, hash } = springRig({ hash: kHash });
  const sphere = { node: 'Avatar_Head', radius: 0.1 };

  test('hitRadius beyond 1e6 (or beyond float32) is clamped with hit-radius-out-of-range', () => {
    for (const hitRadius of [1e30, 1e39, Number.MAX_VALUE]) {
      const rig = sb.loadRig(glb, springBones, { contentHash: hash, colliders: [sphere], hitRadius });
      const warning = rig.warnings.find((w) => w.code === 'hit-radius-out-of-range');
      assert.ok(warning, `hitRadius ${hitRadius}: ${JSON.stringify(rig.warnings)}`);
      assert.match(warning.message, /hitRadius/);
      for (const joint of rig.joints) assert.equal(joint.hitRadius, 1e6);
      const instance = rig.createInstance();
      for (let i = 0; i < 10; ++i) instance.step(1 / 60);
      assert.ok(instance.rotations.every(Number.isFinite));
      assert.ok(instance.worldMatrices.every(Number.isFinite));
      instance.dispose();
      rig.dispose();
    }
    const rig = sb.loadRig(glb, springBones, { contentHash: hash, colliders: [sphere], hitRadius: 1e6 });
    assert.deepEqual(rig.warnings, []);
    rig.dispose();
  });

  test('a collider radius, offset or tail beyond 1e6 is left out with collider-invalid', () => {
    for (const collider of [{ ...sphere, radius: 1e30 }, { ...sphere, offset: [0, 1e7, 0] }, { ...sphere, tail: [1e39, 0, 0] }]) {
      const rig = sb.loadRig(glb, springBones, { contentHash: hash, colliders: [collider] });
      assert.equal(rig.colliders.length, 0, JSON.stringify(collider));
      assert.ok(rig.warnings.some((w) => w.code === 'collider-invalid' && w.message.includes('Avatar_Head')), JSON.stringify(rig.warnings));
      rig.dispose();
    }
  });

  test('a viewer coordinate beyond float32 is a RangeError (the core would ignore the viewer)', () => {
    const scene = sb.createScene();
    refuses(RangeError, /viewerX must be within float32's range/, () => scene.setBudget(1, 1e39, 0, 0));
    refuses(RangeError, /viewerZ/, () => scene.setBudget(1, 0, 0, -Number.MAX_VALUE));
    scene.setBudget(1, 3e38, 0, 0);
    scene.dispose();
  });

  test('the budget tells avatars 1e20 or 1e-25 apart', () => {
    const rig = sb.loadRig(glb, springBones, { contentHash: hash });
    for (const unit of [1e20, 1e-25]) {
      const scene = sb.createScene();
      const far = rig.createInstance();
      const near = rig.createInstance();
      scene.add(far);
      scene.add(near);
      scene.positions.set([3 * unit, 0, 0, unit, 0, 0]);
      scene.setBudget(1, 0, 0, 0);
      scene.step(1 / 60);
      assert.deepEqual([scene.isActive(far), scene.isActive(near)], [false, true], `unit ${unit}`);
      scene.dispose();
      far.dispose();
      near.dispose();
    }
    rig.dispose();
  });
});

describe('world matrices stay finite whenever the drivers are finite', () => {
  const { glb, springBones, hash } = springRig({ hash: kHash });
  const scaled = (s, t) => [s[0], 0, 0, 0, 0, s[1], 0, 0, 0, 0, s[2], 0, t[0], t[1], t[2], 1];
  const drivers = {
    'scale 1e30': scaled([1e30, 1e30, 1e30], [0, 1.6, 0]),
    'scale 3e38': scaled([3e38, 3e38, 3e38], [0, 1.6, 0]),
    'scale 0': scaled([0, 0, 0], [0, 1.6, 0]),
    'scale 1e-30': scaled([1e-30, 1e-30, 1e-30], [0, 1.6, 0]),
    'non-uniform 1e30': scaled([1e30, 1, 1], [0, 1.6, 0]),
    'translation 1e30': scaled([1, 1, 1], [1e30, -1e30, 1e30]),
    'translation 3e38, scale 1e30': scaled([1e30, 1e30, 1e30], [3e38, 3e38, 3e38]),
    // At the bound of docs/semantics.md (1e12), where drivers are still taken.
    'scale and translation 1e12': scaled([1e12, 1e12, 1e12], [1e12, -1e12, 1e12]),
    'non-uniform 1e12 and 1e-30': scaled([1e12, 1e-30, 1], [0, 1.6, 0]),
    'mirrored 1e12': scaled([-1e12, 1e12, 1e12], [0, 1.6, 0]),
  };
  for (const integrator of ['vrm', 'xpbd']) {
    for (const colliders of [undefined, [{ node: 'Avatar_Head', radius: 0.05 }]]) {
      test(`${integrator}${colliders ? ', with a collider' : ''}`, () => {
        const rig = sb.loadRig(glb, springBones, { contentHash: hash, colliders, hitRadius: 0.01 });
        for (const [what, matrix] of Object.entries(drivers)) {
          const instance = rig.createInstance({ integrator });
          instance.setWind({ direction: [1, 0, 0], strength: 1 });
          const rest = Array.from(instance.driverMatrices.subarray(0, 16));
          for (let frame = 0; frame < 20; ++frame) {
            instance.driverMatrices.set(frame >= 5 && frame < 15 ? matrix : rest);
            instance.step(1 / 60);
            assert.ok(instance.worldMatrices.every(Number.isFinite), `${what}, frame ${frame}`);
            assert.ok(instance.rotations.every(Number.isFinite), `${what}, frame ${frame}`);
          }
          instance.driverMatrices.set(matrix);
          instance.reset();
          instance.step(1 / 60);
          assert.ok(instance.worldMatrices.every(Number.isFinite), `${what}, seeded under it`);
          instance.dispose();
        }
        rig.dispose();
      });
    }
  }
});
