// One answer everywhere: 1,000 frames of a rig under the scripted sway of bin/sway.mjs,
// hashed. tools/dump_rotations.cpp --hash computes the same hash natively; Node
// (tests/wasm/frame_hash.test.mjs) and Chromium (tests/browser/frame_hash.test.mjs) run this
// module on the WebAssembly build, and the tests compare the three.
//
// The hash is FNV-1a 64 over the bytes (little-endian, as WebAssembly memory holds them) of every
// frame's rotations, so any difference in any bit of any frame changes it.

import { swayDrivers } from '../../bin/sway.mjs';

const kOffset = 14695981039346656037n;
const kPrime = 1099511628211n;
const kMask = (1n << 64n) - 1n;

/** FNV-1a 64 of `bytes`, continuing from `hash`. */
function fnv1a64(bytes, hash) {
  // Eight bits at a time in BigInt is slow; 1,000 frames of a few dozen joints are ~1 MB.
  let h = hash;
  for (let i = 0; i < bytes.length; i++) h = ((h ^ BigInt(bytes[i])) * kPrime) & kMask;
  return h;
}

/**
 * The hash of `frames` frames at `fps` of a fresh instance of `rig` (createInstance's `options`,
 * default none), its drivers swayed frame k at time k / fps.
 * @returns {{frames: number, joints: number, hash: string}} as dump_rotations --hash prints it
 */
export function frameHash(rig, { frames = 1000, fps = 60, options } = {}) {
  const inst = rig.createInstance(options);
  try {
    const rest = Float32Array.from(inst.driverMatrices);
    let hash = kOffset;
    for (let k = 1; k <= frames; k++) {
      swayDrivers(rest, inst.driverMatrices, k / fps);
      inst.step(1 / fps);
      const r = inst.rotations;
      hash = fnv1a64(new Uint8Array(r.buffer, r.byteOffset, r.byteLength), hash);
    }
    return { frames, joints: rig.joints.length, hash: hash.toString(16).padStart(16, '0') };
  } finally {
    inst.dispose();
  }
}

/**
 * The hashes of the cases of frameHashCases below, from the JS API.
 * @param sb a module from createSpringBones()
 * @param {(path: string) => Promise<Uint8Array>} read a repository file's bytes
 */
export async function frameHashes(sb, read) {
  const out = {};
  for (const c of frameHashCases) {
    const bytes = await read(c.file);
    const rig = c.vrm ? sb.loadVrm(bytes) : sb.loadRig(bytes, JSON.parse(new TextDecoder().decode(await read(c.metadata))));
    try {
      out[c.name] = frameHash(rig);
    } finally {
      rig.dispose();
    }
  }
  return out;
}

/** The sample wearable and the three VRM fixtures, by repository path. */
export const frameHashCases = [
  { name: 'sample wearable', file: 'web/demo/assets/hair_wearable.glb', metadata: 'web/demo/assets/hair_wearable.metadata.json' },
  { name: 'VRM 0.x fixture', file: 'tests/fixtures/vrm0_springs.vrm', vrm: true },
  { name: 'VRM 1.0 fixture', file: 'tests/fixtures/vrm10_springs.vrm', vrm: true },
  { name: 'VRM 1.0 extended colliders fixture', file: 'tests/fixtures/vrm10_extended_colliders.vrm', vrm: true },
];
