// Shared helpers of the WebAssembly tests: fixture paths and the manifest, a small spring rig built
// in memory (GLBs are written by scripts/lib/fixtures/glb.mjs), the scripted sway, the frame hash.
import { existsSync, readFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { glbOfDoc } from '../../scripts/lib/fixtures/glb.mjs';
import { swayDrivers } from '../../bin/sway.mjs';

export const root = join(dirname(fileURLToPath(import.meta.url)), '..', '..');
export const fixturesDir = join(root, 'tests', 'fixtures');

/**
 * Where the spring-bone files made by others are read in place (never copied into the repository):
 * $SPRINGBONES_REAL_FIXTURES, else the team's shared folder beside the checkout, else where that
 * folder lives on the development machines, for a clone made elsewhere (CI's). A test that needs
 * them fails when none is there.
 */
export function realFixturesDir() {
  const candidates = [process.env.SPRINGBONES_REAL_FIXTURES, join(root, '..', 'shared', 'fixtures', 'real'),
    '/work/shared/fixtures/real'].filter(Boolean);
  const found = candidates.find((dir) => existsSync(dir));
  if (!found) throw new Error(`the real fixtures are missing: looked in ${candidates.join(', ')} (set SPRINGBONES_REAL_FIXTURES)`);
  return found;
}

export function fixture(name) {
  return readFileSync(join(fixturesDir, name));
}

export function hasFixture(name) {
  return existsSync(join(fixturesDir, name));
}

/**
 * A head node with `chains` spring chains of `joints` simulated joints each (plus a tip), bones
 * 5 cm long pointing down, and the metadata that makes each chain a root under `hash`.
 */
export function springRig({ chains = 1, joints = 3, hash = 'test-hash', params = {} } = {}) {
  const nodes = [{ name: 'Avatar_Head', children: [], translation: [0, 1.6, 0] }];
  const bones = {};
  for (let c = 0; c < chains; ++c) {
    let parent = 0;
    for (let j = 0; j <= joints; ++j) {
      const index = nodes.length;
      const name = j === joints ? `SpringBone_${c}_tip` : `SpringBone_${c}_${j}`;
      nodes.push({ name, translation: j === 0 ? [0.01 * c, 0, 0.05] : [0, -0.05, 0] });
      (nodes[parent].children ??= []).push(index);
      parent = index;
    }
    bones[`SpringBone_${c}_0`] = {
      stiffness: 1, gravityPower: 0.5, gravityDir: [0, -1, 0], drag: 0.4, isRoot: true, ...params,
    };
  }
  for (const n of nodes) if (n.children?.length === 0) delete n.children;
  const doc = { asset: { version: '2.0' }, scene: 0, scenes: [{ nodes: [0] }], nodes };
  return { doc, glb: glbOfDoc(doc), springBones: { version: 1, models: { [hash]: bones } }, hash };
}

let manifest;
/** The models key a fixture GLB is meant to be loaded with (tests/fixtures/manifest.json). */
export function metadataKeyOf(name) {
  manifest ??= JSON.parse(fixture('manifest.json').toString('utf8'));
  return manifest.files[name].metadataKey;
}

/** The content hash of a fixture as @dcl/hashing computes it (tests/fixtures/manifest.json). */
export function contentHashOf(name) {
  manifest ??= JSON.parse(fixture('manifest.json').toString('utf8'));
  return manifest.files[name].contentHash;
}

/** Loads a fixture GLB with its metadata file and manifest key. */
export function loadFixtureRig(sb, name) {
  manifest ??= JSON.parse(fixture('manifest.json').toString('utf8'));
  const entry = manifest.files[name];
  return sb.loadRig(fixture(name), fixture(entry.metadata).toString('utf8'), { contentHash: entry.metadataKey });
}

/** World position of every joint's tail: its world matrix (instance.worldMatrices) applied to its tail offset. */
export function tailPositions(rig, instance) {
  const w = instance.worldMatrices;
  return rig.joints.map((joint, i) => {
    const m = w.subarray(16 * i, 16 * i + 16);
    const [x, y, z] = joint.tailOffset;
    return [m[0] * x + m[4] * y + m[8] * z + m[12], m[1] * x + m[5] * y + m[9] * z + m[13], m[2] * x + m[6] * y + m[10] * z + m[14]];
  });
}

/**
 * Sways an instance's drivers about the pose they hold now (bin/sway.mjs) for `frames`
 * frames at `fps`, stepping after each; returns that rest pose, to sway on from.
 */
export function swayFrames(instance, frames, fps = 60) {
  const rest = Float32Array.from(instance.driverMatrices);
  for (let k = 1; k <= frames; ++k) {
    swayDrivers(rest, instance.driverMatrices, k / fps);
    instance.step(1 / fps);
  }
  return rest;
}

/** FNV-1a (32-bit) over the bytes of a typed array, as tests/native/determinism_test.cpp hashes. */
export function fnv1a(typed) {
  const bytes = new Uint8Array(typed.buffer, typed.byteOffset, typed.byteLength);
  let hash = 2166136261;
  for (const b of bytes) hash = Math.imul(hash ^ b, 16777619) >>> 0;
  return hash;
}
