// Writes the shared test fixtures into tests/fixtures/: GLB / glTF files with spring-bone
// hierarchies, their data.springBones metadata, a few malformed hierarchies, and manifest.json
// (content hash of every file, and which metadata key each GLB is meant to be loaded with).
//
//   node scripts/generate/make_fixtures.mjs
//
// Node 20 with the npm devDependencies (@dcl/hashing for the content hashes). Deterministic: the
// same bytes on every run (no timestamps, no Math.random, no trigonometry — every rotation is a
// quaternion with literal components).
// tests/fixtures/README.md describes each file and what it is meant to exercise.
import { mkdirSync, writeFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import hashing from '@dcl/hashing';  // CommonJS: named imports do not resolve, the default does
import { AVATAR_BONES, dclArmature, flatten, restPose } from '../lib/fixtures/dcl_armature.mjs';
import { BinaryBuffer, glbOfDoc } from '../lib/fixtures/glb.mjs';
import { add, cross, invert, length, near, normalize, position, scale, sub } from '../lib/fixtures/vec.mjs';

const root = join(dirname(fileURLToPath(import.meta.url)), '..', '..');
const outDir = join(root, 'tests', 'fixtures');

const gltfText = (doc) => Buffer.from(JSON.stringify(doc, null, 2) + '\n', 'utf8');
const jsonText = (value) => Buffer.from(JSON.stringify(value, null, 2) + '\n', 'utf8');

function check(condition, message) {
  if (!condition) throw new Error(`fixture check failed: ${message}`);
}

// ---------------------------------------------------------------------------------------------
// (a) The ADR's Full Example, verbatim: no transforms, so every bone has zero length.

const ADR_HASH = 'bafkreialsvt77jvpy673cnugp5ggnxfaalfncufweayuk3jbxskh3pelkm';

const adrExampleDoc = {
  asset: { version: '2.0' },
  nodes: [
    { name: 'Avatar_Head', children: [1, 2] },
    { name: 'SpringBone_earring_r', children: [3] },
    { name: 'SpringBone_hair_left', children: [4] },
    { name: 'springbone_earring_r_tip' },
    { name: 'SpringBone_hair_left_tip' },
  ],
};

// The ADR writes 1.0 and 2.0; JSON has one number type, so they are written as 1 and 2.
const adrExampleMetadata = {
  version: 1,
  models: {
    [ADR_HASH]: {
      SpringBone_earring_r: {
        stiffness: 0.5,
        gravityPower: 1.0,
        gravityDir: [0, -1, 0],
        drag: 0.6,
        isRoot: true,
        center: 'Avatar_Hips',
      },
      SpringBone_hair_left: {
        stiffness: 2.0,
        gravityPower: 0.8,
        gravityDir: [0, -1, 0],
        drag: 0.4,
        isRoot: true,
      },
    },
  },
};

// (b) Same names, indices and hierarchy, with translations in metres: the head 1.6 m up, the
// earring hanging 4 cm below the right side of the head, the hair strand 10 cm long.
const adrPosedDoc = {
  asset: { version: '2.0' },
  nodes: [
    { name: 'Avatar_Head', children: [1, 2], translation: [0, 1.6, 0] },
    { name: 'SpringBone_earring_r', children: [3], translation: [-0.08, -0.02, 0] },
    { name: 'SpringBone_hair_left', children: [4], translation: [0.07, 0.1, -0.03] },
    { name: 'springbone_earring_r_tip', translation: [0, -0.04, 0] },
    { name: 'SpringBone_hair_left_tip', translation: [0, -0.1, 0] },
  ],
};
{
  const w = restPose(adrPosedDoc.nodes).world;
  check(near(position(w[3]), [-0.08, 1.54, 0]), 'posed earring tip');
  check(Math.abs(length(sub(position(w[4]), position(w[2]))) - 0.1) < 1e-9, 'posed hair length');
}

// ---------------------------------------------------------------------------------------------
// (c) A Decentraland-like avatar with a hair wearable.
//
// The armature of scripts/lib/fixtures/dcl_armature.mjs with its fixture proportions (the Leg
// 44.89 cm below the UpLeg, as in Decentraland's own armature), a hair wearable under the head and
// two decoys. World positions are checked below.

// A linear chain: root at `t`, then segments (each an offset from the previous node), named
// `${name}_1`, `_2`, ... and the last one `${name}${tipSuffix}`.
function strand(name, t, segments, tipSuffix = '_tip') {
  let tree = null;
  for (let i = segments.length; i >= 1; i--) {
    tree = {
      name: i === segments.length ? `${name}${tipSuffix}` : `${name}_${i}`,
      t: segments[i - 1],
      children: tree ? [tree] : undefined,
    };
  }
  return { name, t, children: [tree] };
}

const hair = [
  // Linear: root + 3 members + tip, 5 cm segments, over the left ear. _2 has an override entry.
  strand('SpringBone_hair_left', [7, 8, -2], [[0, -5, 0], [0, -5, 0], [0, -5, 0], [0, -4, 0]]),
  // ADR naming variant; the chain continues through a node without the token (hair_r_bead).
  {
    name: 'hair_springbone_r', t: [-7, 8, -2], children: [{
      name: 'hair_springbone_r_1', t: [0, -6, 0], children: [{
        name: 'hair_r_bead', t: [0, -6, 0], children: [{ name: 'hair_r_bead_tip', t: [0, -3, 0] }],
      }],
    }],
  },
  // Earring on the right ear, center Avatar_Hips.
  strand('springbone_earring_r', [-8, -2, 0], [[0, -4, 0]]),
  // Branching: braid_1 has two children; braid_a (first) is its tail, braid_b starts a branch.
  {
    name: 'SpringBone_braid', t: [0, 4, -9], children: [{
      name: 'SpringBone_braid_1', t: [0, -6, -1], children: [
        { name: 'SpringBone_braid_a', t: [2, -6, 0], children: [{ name: 'SpringBone_braid_a_tip', t: [0, -5, 0] }] },
        { name: 'SpringBone_braid_b', t: [-2, -6, 0], children: [{ name: 'SpringBone_braid_b_tip', t: [0, -5, 0] }] },
      ],
    }],
  },
  // Nested root: SpringBone_bangs_1 has its own isRoot: true entry inside the bangs chain.
  strand('SpringBone_bangs', [0, 10, 8], [[0, -4, 1], [0, -4, 0], [0, -3, 0]]),
  // Root whose center names no node.
  strand('SpringBone_ribbon', [5, 6, -7], [[0, -8, 0]]),
  // Root whose center is a spring node.
  strand('SpringBone_tassel', [-5, 6, -7], [[0, -8, 0]]),
  // Upper-case token.
  strand('ponytail_SPRINGBONE', [0, 8, -10], [[0, -8, -2], [0, -10, 0]]),
];

const avatarTree = dclArmature({
  extraChildren: {
    Avatar_Head: hair,
    // A candidate name whose entry has no isRoot: not a chain.
    Avatar_Spine2: [{ name: 'SpringBoneCollider', t: [0, 5, 10], children: [{ name: 'SpringBoneCollider_end', t: [0, 0, 3] }] }],
    // No "springbone" token: never a chain, although the metadata has an entry for it.
    Avatar_Hips: [{ name: 'skirt_1', t: [0, -8, 12], children: [{ name: 'skirt_1_end', t: [0, -20, 0] }] }],
  },
});

const down = [0, -1, 0];
const params = (stiffness, gravityPower, drag, extra = {}, gravityDir = down) =>
  ({ stiffness, gravityPower, gravityDir, drag, ...extra });

const avatarHairEntries = {
  SpringBone_hair_left: params(1.5, 0.5, 0.4, { isRoot: true }),
  SpringBone_hair_left_2: params(0.8, 0.5, 0.4, { isRoot: false }),  // member override
  hair_springbone_r: params(1.5, 0.5, 0.4, { isRoot: true }),
  springbone_earring_r: params(0.5, 1.0, 0.6, { isRoot: true, center: 'Avatar_Hips' }),
  SpringBone_braid: params(1.0, 0.3, 0.5, { isRoot: true, center: 'Avatar_Head' }),
  SpringBone_bangs: params(3.0, 0.1, 0.7, { isRoot: true }),
  SpringBone_bangs_1: params(0.5, 0.2, 0.3, { isRoot: true }, [0, -1, -1]),  // nested root
  SpringBone_ribbon: params(1.0, 0.5, 0.5, { isRoot: true, center: 'Avatar_Nonexistent' }),
  SpringBone_tassel: params(1.0, 0.5, 0.5, { isRoot: true, center: 'SpringBone_hair_left' }),
  ponytail_SPRINGBONE: params(2.0, 0.6, 0.3, { isRoot: true }),
  skirt_1: params(1.0, 0.5, 0.5, { isRoot: true }),          // not a candidate: ignored
  SpringBoneCollider: params(2.0, 0.0, 0.5),                 // candidate, no isRoot: not a root
  SpringBone_missing_node: params(2.0, 0.0, 0.5, { isRoot: true }),  // no such node
};

function buildAvatarHair() {
  const { nodes, index, roots, world } = flatten([avatarTree]);
  for (const bone of AVATAR_BONES) check(index.has(bone), `missing ${bone}`);
  check(AVATAR_BONES.length === 62, '62 avatar bones');
  check(new Set(AVATAR_BONES).size === 62, 'avatar bone names unique');

  // --- world positions, checked against the intended avatar (metres, +Y up, facing +Z)
  const at = (name) => position(world[index.get(name)]);
  const expectNear = (name, p, eps = 1e-6) =>
    check(near(at(name), p, eps), `${name} at ${at(name).map((v) => v.toFixed(4))}, expected ${p}`);
  expectNear('Avatar_Hips', [0, 1.0, 0]);
  expectNear('Avatar_Spine2', [0, 1.34, 0]);
  expectNear('Avatar_Head', [0, 1.6, 0]);
  expectNear('Avatar_LeftUpLeg', [0.09, 0.94, 0]);
  expectNear('Avatar_LeftLeg', [0.09, 0.4911, 0]);
  expectNear('Avatar_LeftFoot', [0.09, 0.0811, 0]);
  expectNear('Avatar_LeftToeBase', [0.09, 0.0211, 0.12]);  // in front of the ankle: facing +Z
  expectNear('Avatar_RightToeBase', [-0.09, 0.0211, 0.12]);
  expectNear('Avatar_LeftHand', [0.67, 1.45, -0.01]);      // T-pose, left hand on +X
  expectNear('Avatar_RightHand', [-0.67, 1.45, -0.01]);
  expectNear('SpringBone_hair_left', [0.07, 1.68, -0.02]);
  expectNear('SpringBone_hair_left_tip', [0.07, 1.49, -0.02]);
  expectNear('springbone_earring_r_tip', [-0.08, 1.54, 0]);
  // The rotations of Armature and Hips cancel, so every node below the hips is axis-aligned.
  const hipsWorld = world[index.get('Avatar_Hips')];
  check(near(hipsWorld.slice(0, 11), [0.01, 0, 0, 0, 0, 0.01, 0, 0, 0, 0, 0.01], 1e-9), 'hips axes');
  const ys = nodes.map((_, i) => world[i][13]).filter((_, i) => nodes[i].name !== 'Armature');
  const top = Math.max(...ys);
  check(Math.min(...ys) > 0 && top < 1.76 && top > 1.69, `joints between 0 and 1.75 m (top ${top})`);

  // --- a skinned mesh: one thin box per wearable bone segment (parent head -> child head),
  // weighted fully to the parent, so a viewer shows the hair move with the joints.
  const avatarSet = new Set(['Armature', ...AVATAR_BONES]);
  const jointNodes = nodes.map((_, i) => i).filter((i) => nodes[i].name !== 'Armature');
  const jointSlot = new Map(jointNodes.map((n, slot) => [n, slot]));
  const positions = [];
  const joints = [];
  const weights = [];
  const indices = [];
  const half = 0.004;  // 8 mm wide strands
  nodes.forEach((node, p) => {
    if (avatarSet.has(node.name)) return;
    for (const c of node.children ?? []) {
      const a = position(world[p]);
      const b = position(world[c]);
      const d = normalize(sub(b, a));
      const ref = Math.abs(d[0]) < 0.9 ? [1, 0, 0] : [0, 0, 1];
      const u = scale(normalize(cross(d, ref)), half);
      const v = scale(normalize(cross(d, u)), half);
      const base = positions.length / 3;
      for (const end of [a, b]) {
        for (const [su, sv] of [[-1, -1], [1, -1], [1, 1], [-1, 1]]) {
          positions.push(...add(end, scale(u, su), scale(v, sv)));
          joints.push(jointSlot.get(p), 0, 0, 0);
          weights.push(1, 0, 0, 0);
        }
      }
      const quads = [[0, 1, 2, 3], [7, 6, 5, 4], [0, 4, 5, 1], [1, 5, 6, 2], [2, 6, 7, 3], [3, 7, 4, 0]];
      for (const [q0, q1, q2, q3] of quads) {
        indices.push(base + q0, base + q2, base + q1, base + q0, base + q3, base + q2);
      }
    }
  });
  const buffer = new BinaryBuffer();
  const positionAccessor = buffer.accessor(Float32Array.from(positions), 'VEC3', { target: 34962, minMax: true });
  const jointsAccessor = buffer.accessor(Uint16Array.from(joints), 'VEC4', { target: 34962 });
  const weightsAccessor = buffer.accessor(Float32Array.from(weights), 'VEC4', { target: 34962 });
  const indicesAccessor = buffer.accessor(Uint16Array.from(indices), 'SCALAR', { target: 34963 });
  const inverseBind = buffer.accessor(Float32Array.from(jointNodes.flatMap((n) => invert(world[n]))), 'MAT4');

  const meshNode = nodes.length;
  const doc = {
    asset: { version: '2.0', generator: 'springbones scripts/generate/make_fixtures.mjs' },
    scene: 0,
    scenes: [{ name: 'avatar_hair', nodes: [...roots, meshNode] }],
    nodes: [...nodes, { name: 'HairMesh', mesh: 0, skin: 0 }],
    meshes: [{
      name: 'HairMesh',
      primitives: [{
        attributes: { POSITION: positionAccessor, JOINTS_0: jointsAccessor, WEIGHTS_0: weightsAccessor },
        indices: indicesAccessor,
        material: 0,
      }],
    }],
    materials: [{ name: 'Hair', pbrMetallicRoughness: { baseColorFactor: [0.35, 0.2, 0.1, 1], metallicFactor: 0, roughnessFactor: 0.8 } }],
    skins: [{ name: 'Armature', joints: jointNodes, inverseBindMatrices: inverseBind, skeleton: index.get('Armature') }],
  };
  check(positions.length / 3 < 65536, 'indices fit in 16 bits');
  return { bytes: buffer.glb(doc), nodes };
}

// ---------------------------------------------------------------------------------------------
// (d) Malformed hierarchies (the loader must reject them).

const twoParentsDoc = {
  asset: { version: '2.0' },
  nodes: [
    { name: 'ParentA', children: [2] },
    { name: 'ParentB', children: [2] },
    { name: 'SpringBone_shared' },
  ],
};

// Node 0 is a proper root; nodes 1 and 2 are each other's parent, so no root leads to them.
const cycleDoc = {
  asset: { version: '2.0' },
  nodes: [
    { name: 'Root' },
    { name: 'SpringBone_a', children: [2] },
    { name: 'SpringBone_b', children: [1] },
  ],
};

// ---------------------------------------------------------------------------------------------
// Write everything

mkdirSync(outDir, { recursive: true });
const manifest = {};
const written = [];

// The content hash Decentraland gives the file (the CIDv1 of @dcl/hashing hashV1).
async function write(name, bytes, info = {}) {
  writeFileSync(join(outDir, name), bytes);
  manifest[name] = { bytes: bytes.length, contentHash: await hashing.hashV1(bytes), ...info };
  written.push(name);
}

await write('adr_example.glb', glbOfDoc(adrExampleDoc), {
  metadata: 'adr_example.metadata.json', metadataKey: ADR_HASH,
});
await write('adr_example.gltf', gltfText(adrExampleDoc), {
  metadata: 'adr_example.metadata.json', metadataKey: ADR_HASH,
});
await write('adr_example_posed.glb', glbOfDoc(adrPosedDoc), {
  metadata: 'adr_example.metadata.json', metadataKey: ADR_HASH,
});
await write('adr_example.metadata.json', jsonText(adrExampleMetadata));

const avatar = buildAvatarHair();
const avatarHash = await hashing.hashV1(avatar.bytes);
await write('avatar_hair.glb', avatar.bytes, {
  metadata: 'avatar_hair.metadata.json', metadataKey: avatarHash,
});
await write('avatar_hair.metadata.json', jsonText({ version: 1, models: { [avatarHash]: avatarHairEntries } }));

await write('two_parents.gltf', gltfText(twoParentsDoc));
await write('cycle.gltf', gltfText(cycleDoc));

// Manifest last (it describes the others, not itself).
const sortedManifest = Object.fromEntries(Object.keys(manifest).sort().map((k) => [k, manifest[k]]));
writeFileSync(join(outDir, 'manifest.json'), jsonText({
  comment: 'Written by scripts/generate/make_fixtures.mjs. contentHash: the CIDv1 Decentraland computes for ' +
    'the file (@dcl/hashing hashV1). metadataKey: the models key to load the file with.',
  files: sortedManifest,
}));

for (const name of written) {
  const m = manifest[name];
  console.log(`${name.padEnd(28)} ${String(m.bytes).padStart(6)} B  ${m.contentHash}`);
}
console.log(`avatar_hair: ${avatar.nodes.length} skeleton nodes, metadata key ${avatarHash}`);
