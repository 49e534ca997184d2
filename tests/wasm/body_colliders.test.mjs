// The 'dcl-body' collider preset through loadRig: the shapes the core measures from the armature
// in the GLB (the demo's wearable carries Hips to Head; the fixture avatar all 62 bones), the
// argument checks, and the test: under the demo's shake and spin the sample's ponytail and
// side locks never get more than 1 mm inside the head, neck or torso shapes, with either
// integrator. The neck is thinner than the bones that swing around it: when the ponytail wraps
// around it, a bone can lie across the neck, and one push of the tail followed by the bone's
// length back left its tail 21 mm inside for a frame; with the preset the VRM update repeats its
// pushes (Rig::collider_passes), and the neck is held like the rest.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { describe, test } from 'node:test';
import { fileURLToPath } from 'node:url';
import { Matrix4, Vector3 } from 'three';
import { loadSampleWearable } from './sample_wearable.mjs';
import { glbOfDoc } from '../../scripts/lib/fixtures/glb.mjs';
import { metadataKeyOf } from './helpers.mjs';
import { kShakeSeconds, kSpinSpeed, shakeOffset } from '../../web/demo/js/motion.js';

const { sb, wearableBytes, metadata, wear } = await loadSampleWearable();
const fixtures = join(dirname(fileURLToPath(import.meta.url)), '..', 'fixtures');
const kHitRadius = 0.01;  // the demo's
const kDt = 1 / 60;

describe('the shapes', () => {
  test("the demo's wearable: head, neck and two chest shapes, the arms left out with a warning", () => {
    const rig = sb.loadRig(wearableBytes, metadata, { colliders: 'dcl-body', hitRadius: kHitRadius });
    assert.deepEqual(rig.colliders.map((c) => [c.node, c.shape]), [
      ['Avatar_Head', 'sphere'], ['Avatar_Neck', 'capsule'], ['Avatar_Spine2', 'capsule'], ['Avatar_Spine1', 'capsule'],
    ]);
    // Bone space is centimetres (the Armature's 0.01): head radius 0.94 x the 10.05 cm neck.
    assert.ok(Math.abs(rig.colliders[0].radius - 0.94 * Math.hypot(10, 1)) < 1e-3, `${rig.colliders[0].radius}`);
    const skipped = rig.warnings.filter((w) => w.code === 'body-collider-skipped');
    assert.equal(skipped.length, 1);
    assert.match(skipped[0].message, /left-shoulder.*Avatar_LeftShoulder/);
    assert.ok(rig.joints.every((j) => j.hitRadius === kHitRadius));
    rig.dispose();
  });

  test('the fixture avatar with all 62 bones: eight shapes, on the bones the GLB has', () => {
    const glb = new Uint8Array(readFileSync(join(fixtures, 'avatar_hair.glb')));
    const springBones = JSON.parse(readFileSync(join(fixtures, 'avatar_hair.metadata.json'), 'utf8'));
    const rig = sb.loadRig(glb, springBones, { colliders: 'dcl-body' });
    assert.deepEqual(rig.colliders.map((c) => c.node), [
      'Avatar_Head', 'Avatar_Neck', 'Avatar_Spine2', 'Avatar_Spine1', 'Avatar_LeftShoulder', 'Avatar_RightShoulder',
      'Avatar_LeftArm', 'Avatar_RightArm',
    ]);
    assert.ok(rig.colliders.every((c) => rig.drivers[c.driver].node >= 0), 'every carrier is a node of the GLB');
    assert.equal(rig.warnings.filter((w) => w.code === 'body-collider-skipped').length, 0);
    // The upper arm runs from the arm to the forearm bone, 27 cm along +x (bone space is world-aligned cm).
    const arm = rig.colliders[6];
    assert.deepEqual(arm.offset, [0, 0, 0]);
    assert.ok(Math.abs(arm.tail[0] - 27) < 1e-3 && Math.abs(arm.radius - 0.17 * 27) < 1e-3);
    rig.dispose();
  });

  test('a larger avatar: the same shapes in bone space, larger in the world', () => {
    // The fixture's node hierarchy alone (the core reads no meshes), its Armature scaled 1.5 times.
    const bytes = readFileSync(join(fixtures, 'avatar_hair.glb'));
    const json = JSON.parse(bytes.subarray(20, 20 + bytes.readUInt32LE(12)).toString('utf8'));
    const nodes = json.nodes.map(({ mesh, skin, ...node }) => node);
    const springBones = JSON.parse(readFileSync(join(fixtures, 'avatar_hair.metadata.json'), 'utf8'));
    const options = { contentHash: metadataKeyOf('avatar_hair.glb'), colliders: 'dcl-body' };
    const load = (scale) => {
      const scaled = nodes.map((n) => (n.name === 'Armature' ? { ...n, scale: n.scale.map((v) => v * scale) } : n));
      return sb.loadRig(glbOfDoc({ asset: json.asset, scene: json.scene, scenes: json.scenes, nodes: scaled }), springBones, options);
    };
    const normal = load(1), large = load(1.5);
    assert.equal(large.colliders.length, 8);
    /** World centre of the head sphere at rest: its driver's rest matrix applied to its offset. */
    const headCentre = (rig) => {
      const instance = rig.createInstance();
      const m = instance.driverMatrices.subarray(16 * rig.colliders[0].driver);
      const [x, y, z] = rig.colliders[0].offset;
      const centre = [0, 1, 2].map((r) => m[r] * x + m[4 + r] * y + m[8 + r] * z + m[12 + r]);
      instance.dispose();
      return centre;
    };
    large.colliders.forEach((c, i) => {
      const n = normal.colliders[i];
      assert.equal(c.node, n.node);
      assert.ok(Math.abs(c.radius - n.radius) < 1e-3, `${c.node}: ${c.radius} vs ${n.radius} in bone space`);
      c.offset.forEach((v, k) => assert.ok(Math.abs(v - n.offset[k]) < 1e-3, `${c.node} offset`));
    });
    const [a, b] = [headCentre(normal), headCentre(large)];
    a.forEach((v, k) => assert.ok(Math.abs(b[k] - 1.5 * v) < 1e-4, `head centre ${b} is not 1.5 x ${a}`));
    normal.dispose();
    large.dispose();
  });

  test('off unless asked for', () => {
    const rig = sb.loadRig(wearableBytes, metadata);
    assert.equal(rig.colliders.length, 0);
    rig.dispose();
  });

  test('a preset name that is not one is a RangeError, another type a TypeError, before crossing', () => {
    assert.throws(() => sb.loadRig(wearableBytes, metadata, { colliders: 'dcl-bodies' }), RangeError);
    assert.throws(() => sb.loadRig(wearableBytes, metadata, { colliders: 5 }), TypeError);
  });
});

/** The sample on the demo's avatar, in a holder that is shaken and spun as the demo does it. */
function wornSample(integrator, options) {
  const rig = sb.loadRig(wearableBytes, metadata, options);
  const worn = wear(rig, { instance: { integrator }, watchMixer: true });
  worn.actions.walk.play();
  return { rig, ...worn };
}

// The shapes as the preset builds them for the sample (the rig with colliders reports them).
const bodyShapes = (() => {
  const rig = sb.loadRig(wearableBytes, metadata, { colliders: 'dcl-body' });
  const shapes = rig.colliders;
  rig.dispose();
  return shapes;
})();

const scratch = { m: new Matrix4(), tail: new Vector3(), a: new Vector3(), b: new Vector3(), ab: new Vector3() };

/** How far `p` is inside a shape (metres; negative outside). */
function depthInside(p, a, b, radius) {
  const { ab } = scratch;
  ab.subVectors(b, a);
  const length2 = ab.lengthSq();
  const t = length2 > 0 ? Math.min(1, Math.max(0, ab.dot(scratch.tail.copy(p).sub(a)) / length2)) : 0;
  return radius - p.distanceTo(ab.multiplyScalar(t).add(a));
}

/**
 * 10 s of the demo's walk, shaken again and again (every 1.6 s) while spinning at its 120 degrees
 * per second. Returns the deepest tail of the ponytail and side locks in the head and torso shapes
 * and in the neck (metres, negative outside; the shapes on the avatar's bones).
 */
function deepestUnderShakeAndSpin(integrator, options) {
  const { rig, scene, holder, mixer, attachment, avatarRoot } = wornSample(integrator, options);
  const chains = rig.joints.map((j) => rig.joints[j.chain].name);
  const watched = rig.joints.map((j, i) => /ponytail|hair_springbone/i.test(chains[i]));
  assert.ok(watched.filter(Boolean).length >= 6, 'the ponytail and both side locks are simulated');
  const shapes = bodyShapes.map((c) => ({ c, object: avatarRoot.getObjectByName(c.node) }));
  assert.ok(shapes.every((s) => s.object), 'every shape rides on a bone of the avatar');
  const out = { x: 0, y: 0, roll: 0 };
  const spinRate = (kSpinSpeed * Math.PI) / 180;
  const deepest = { body: { depth: -Infinity }, neck: { depth: -Infinity, radius: 0 } };
  for (let f = 0; f < 600; f++) {
    shakeOffset((f * kDt) % (kShakeSeconds + 0.2), out);
    holder.position.set(out.x, out.y, 0);
    holder.rotation.set(0, spinRate * f * kDt, out.roll);
    mixer.update(kDt);
    scene.updateMatrixWorld();
    attachment.update(kDt);
    const world = attachment.instance.worldMatrices;
    rig.joints.forEach((joint, j) => {
      if (!watched[j]) return;
      const tail = new Vector3().fromArray(joint.tailOffset).applyMatrix4(scratch.m.fromArray(world, 16 * j));
      for (const { c, object } of shapes) {
        const a = scratch.a.fromArray(c.offset).applyMatrix4(object.matrixWorld);
        const b = scratch.b.fromArray(c.tail ?? c.offset).applyMatrix4(object.matrixWorld);
        const radius = c.radius * object.matrixWorld.getMaxScaleOnAxis();
        const depth = depthInside(tail, a, b, radius);
        const kind = c.node === 'Avatar_Neck' ? 'neck' : 'body';
        if (depth > deepest[kind].depth) deepest[kind] = { depth, joint: joint.name, shape: c.node, frame: f, radius };
      }
    });
  }
  attachment.dispose();
  rig.dispose();
  return deepest;
}

describe("under the demo's shake and spin", () => {
  for (const integrator of ['vrm', 'xpbd']) {
    test(`${integrator}: the ponytail and side locks stay within 1 mm of the head, neck and torso shapes`, (t) => {
      const without = deepestUnderShakeAndSpin(integrator, {});
      const { body, neck } = deepestUnderShakeAndSpin(integrator, { colliders: 'dcl-body', hitRadius: kHitRadius });
      const mm = (m) => (m * 1000).toFixed(2);
      t.diagnostic(`${integrator}: deepest in the head and torso ${mm(body.depth)} mm (${body.joint} in ${body.shape}, ` +
        `frame ${body.frame}), in the neck ${mm(neck.depth)} mm (${neck.joint}, frame ${neck.frame}); without ` +
        `colliders ${mm(without.body.depth)} mm (${without.body.joint} in ${without.body.shape}) and ${mm(without.neck.depth)} mm`);
      // The same motion without colliders puts hair inside the body: the check below can fail.
      assert.ok(without.body.depth > 0.01, `without colliders the deepest tail is only ${mm(without.body.depth)} mm inside`);
      assert.ok(body.depth <= 0.001, `${body.joint} went ${mm(body.depth)} mm into ${body.shape}`);
      assert.ok(neck.depth <= 0.001, `${neck.joint} went ${mm(neck.depth)} mm into the neck (frame ${neck.frame})`);
    });
  }
});
