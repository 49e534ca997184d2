// Writes the shared test fixtures into tests/fixtures/: GLB / glTF files with spring-bone
// hierarchies, their data.springBones metadata, a few malformed hierarchies, and manifest.json
// (content hash of every file, and which metadata key each GLB is meant to be loaded with).
//
//   node scripts/make_fixtures.mjs
//
// Node 20, no npm dependencies. Deterministic: the same bytes on every run (no timestamps, no
// Math.random, no trigonometry — every rotation is a quaternion with literal components).
// tests/fixtures/README.md describes each file and what it is meant to exercise.
import { createHash } from 'node:crypto';
import { mkdirSync, writeFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const root = join(dirname(fileURLToPath(import.meta.url)), '..');
const outDir = join(root, 'tests', 'fixtures');
const H = Math.SQRT1_2;  // cos(45°) = sin(45°): the components of a 90° quaternion

// ---------------------------------------------------------------------------------------------
// Container writing

/** GLB 2.0: 12-byte header, JSON chunk padded with spaces to 4 bytes, optional BIN chunk padded
 *  with zeros (glTF 2.0 spec, "Binary glTF Layout"). */
function glb(doc, bin) {
  const jsonBytes = Buffer.from(JSON.stringify(doc), 'utf8');
  const jsonPadded = Buffer.concat([jsonBytes, Buffer.alloc((4 - (jsonBytes.length % 4)) % 4, 0x20)]);
  const chunks = [chunk(0x4e4f534a, jsonPadded)];  // "JSON"
  if (bin) {
    const binPadded = Buffer.concat([bin, Buffer.alloc((4 - (bin.length % 4)) % 4, 0)]);
    chunks.push(chunk(0x004e4942, binPadded));  // "BIN\0"
  }
  const body = Buffer.concat(chunks);
  const header = Buffer.alloc(12);
  header.writeUInt32LE(0x46546c67, 0);  // "glTF"
  header.writeUInt32LE(2, 4);
  header.writeUInt32LE(12 + body.length, 8);
  return Buffer.concat([header, body]);
}

function chunk(type, data) {
  const head = Buffer.alloc(8);
  head.writeUInt32LE(data.length, 0);
  head.writeUInt32LE(type, 4);
  return Buffer.concat([head, data]);
}

const gltfText = (doc) => Buffer.from(JSON.stringify(doc, null, 2) + '\n', 'utf8');
const jsonText = (value) => Buffer.from(JSON.stringify(value, null, 2) + '\n', 'utf8');

// ---------------------------------------------------------------------------------------------
// Content hash, as Decentraland computes it (@dcl/hashing hashV1) for files of at most 256 KiB:
// a single raw leaf, so the CID is CIDv1(raw 0x55, sha2-256) in multibase base32 ('b' prefix).
// Bigger files need the UnixFS dag-pb tree, which the fixtures never reach (checked below).

function contentHash(bytes) {
  if (bytes.length > 262144) throw new Error('fixture larger than one 256 KiB leaf');
  const digest = createHash('sha256').update(bytes).digest();
  const cid = Buffer.concat([Buffer.from([0x01, 0x55, 0x12, 0x20]), digest]);
  return 'b' + base32(cid);
}

function base32(bytes) {  // RFC 4648, lower case, no padding
  const alphabet = 'abcdefghijklmnopqrstuvwxyz234567';
  let out = '';
  let bits = 0;
  let value = 0;
  for (const byte of bytes) {
    value = (value << 8) | byte;
    bits += 8;
    while (bits >= 5) {
      out += alphabet[(value >>> (bits - 5)) & 31];
      bits -= 5;
    }
    value &= (1 << bits) - 1;
  }
  if (bits > 0) out += alphabet[(value << (5 - bits)) & 31];
  return out;
}

// ---------------------------------------------------------------------------------------------
// Node trees. A tree is { name, t?, r?, s?, children? }; it is flattened depth-first, pre-order,
// so a parent always precedes its children in the glTF `nodes` array.

function flatten(roots) {
  const nodes = [];
  const index = new Map();
  const visit = (tree) => {
    const i = nodes.length;
    if (index.has(tree.name)) throw new Error(`duplicate node name ${tree.name}`);
    index.set(tree.name, i);
    const node = { name: tree.name };
    nodes.push(node);
    if (tree.t) node.translation = tree.t;
    if (tree.r) node.rotation = tree.r;
    if (tree.s) node.scale = tree.s;
    const kids = (tree.children ?? []).map(visit);
    if (kids.length) node.children = kids;
    return i;
  };
  const rootIndices = roots.map(visit);
  // Key order of each node: name, children, then TRS (stable, readable in the .gltf).
  const ordered = nodes.map(({ name, children, translation, rotation, scale }) =>
    Object.fromEntries(Object.entries({ name, children, translation, rotation, scale })
      .filter(([, v]) => v !== undefined)));
  return { nodes: ordered, index, rootIndices };
}

// Column-major 4x4 matrices, as glTF and three.js store them.
function trsMatrix(node) {
  const [x, y, z, w] = node.rotation ?? [0, 0, 0, 1];
  const [sx, sy, sz] = node.scale ?? [1, 1, 1];
  const [tx, ty, tz] = node.translation ?? [0, 0, 0];
  return [
    (1 - 2 * (y * y + z * z)) * sx, (2 * (x * y + z * w)) * sx, (2 * (x * z - y * w)) * sx, 0,
    (2 * (x * y - z * w)) * sy, (1 - 2 * (x * x + z * z)) * sy, (2 * (y * z + x * w)) * sy, 0,
    (2 * (x * z + y * w)) * sz, (2 * (y * z - x * w)) * sz, (1 - 2 * (x * x + y * y)) * sz, 0,
    tx, ty, tz, 1,
  ];
}

function mul(a, b) {
  const out = new Array(16).fill(0);
  for (let c = 0; c < 4; c++) {
    for (let r = 0; r < 4; r++) {
      let s = 0;
      for (let k = 0; k < 4; k++) s += a[k * 4 + r] * b[c * 4 + k];
      out[c * 4 + r] = s;
    }
  }
  return out;
}

function invert(m) {  // general 4x4 inverse by cofactors
  const inv = new Array(16);
  inv[0] = m[5] * m[10] * m[15] - m[5] * m[11] * m[14] - m[9] * m[6] * m[15] + m[9] * m[7] * m[14] + m[13] * m[6] * m[11] - m[13] * m[7] * m[10];
  inv[4] = -m[4] * m[10] * m[15] + m[4] * m[11] * m[14] + m[8] * m[6] * m[15] - m[8] * m[7] * m[14] - m[12] * m[6] * m[11] + m[12] * m[7] * m[10];
  inv[8] = m[4] * m[9] * m[15] - m[4] * m[11] * m[13] - m[8] * m[5] * m[15] + m[8] * m[7] * m[13] + m[12] * m[5] * m[11] - m[12] * m[7] * m[9];
  inv[12] = -m[4] * m[9] * m[14] + m[4] * m[10] * m[13] + m[8] * m[5] * m[14] - m[8] * m[6] * m[13] - m[12] * m[5] * m[10] + m[12] * m[6] * m[9];
  inv[1] = -m[1] * m[10] * m[15] + m[1] * m[11] * m[14] + m[9] * m[2] * m[15] - m[9] * m[3] * m[14] - m[13] * m[2] * m[11] + m[13] * m[3] * m[10];
  inv[5] = m[0] * m[10] * m[15] - m[0] * m[11] * m[14] - m[8] * m[2] * m[15] + m[8] * m[3] * m[14] + m[12] * m[2] * m[11] - m[12] * m[3] * m[10];
  inv[9] = -m[0] * m[9] * m[15] + m[0] * m[11] * m[13] + m[8] * m[1] * m[15] - m[8] * m[3] * m[13] - m[12] * m[1] * m[11] + m[12] * m[3] * m[9];
  inv[13] = m[0] * m[9] * m[14] - m[0] * m[10] * m[13] - m[8] * m[1] * m[14] + m[8] * m[2] * m[13] + m[12] * m[1] * m[10] - m[12] * m[2] * m[9];
  inv[2] = m[1] * m[6] * m[15] - m[1] * m[7] * m[14] - m[5] * m[2] * m[15] + m[5] * m[3] * m[14] + m[13] * m[2] * m[7] - m[13] * m[3] * m[6];
  inv[6] = -m[0] * m[6] * m[15] + m[0] * m[7] * m[14] + m[4] * m[2] * m[15] - m[4] * m[3] * m[14] - m[12] * m[2] * m[7] + m[12] * m[3] * m[6];
  inv[10] = m[0] * m[5] * m[15] - m[0] * m[7] * m[13] - m[4] * m[1] * m[15] + m[4] * m[3] * m[13] + m[12] * m[1] * m[7] - m[12] * m[3] * m[5];
  inv[14] = -m[0] * m[5] * m[14] + m[0] * m[6] * m[13] + m[4] * m[1] * m[14] - m[4] * m[2] * m[13] - m[12] * m[1] * m[6] + m[12] * m[2] * m[5];
  inv[3] = -m[1] * m[6] * m[11] + m[1] * m[7] * m[10] + m[5] * m[2] * m[11] - m[5] * m[3] * m[10] - m[9] * m[2] * m[7] + m[9] * m[3] * m[6];
  inv[7] = m[0] * m[6] * m[11] - m[0] * m[7] * m[10] - m[4] * m[2] * m[11] + m[4] * m[3] * m[10] + m[8] * m[2] * m[7] - m[8] * m[3] * m[6];
  inv[11] = -m[0] * m[5] * m[11] + m[0] * m[7] * m[9] + m[4] * m[1] * m[11] - m[4] * m[3] * m[9] - m[8] * m[1] * m[7] + m[8] * m[3] * m[5];
  inv[15] = m[0] * m[5] * m[10] - m[0] * m[6] * m[9] - m[4] * m[1] * m[10] + m[4] * m[2] * m[9] + m[8] * m[1] * m[6] - m[8] * m[2] * m[5];
  const det = m[0] * inv[0] + m[1] * inv[4] + m[2] * inv[8] + m[3] * inv[12];
  if (Math.abs(det) < 1e-30) throw new Error('singular matrix');
  return inv.map((v) => v / det);
}

/** World matrix of every node (rest pose), parents first. */
function worldMatrices(nodes, rootIndices) {
  const world = new Array(nodes.length);
  const stack = rootIndices.map((i) => [i, null]);
  while (stack.length) {
    const [i, parent] = stack.pop();
    const local = trsMatrix(nodes[i]);
    world[i] = parent ? mul(parent, local) : local;
    for (const c of nodes[i].children ?? []) stack.push([c, world[i]]);
  }
  return world;
}

const position = (m) => [m[12], m[13], m[14]];
const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const len = (v) => Math.hypot(v[0], v[1], v[2]);
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const scale = (v, s) => [v[0] * s, v[1] * s, v[2] * s];
const add = (...vs) => vs.reduce((a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]]);
const normalize = (v) => scale(v, 1 / len(v));

function check(condition, message) {
  if (!condition) throw new Error(`fixture check failed: ${message}`);
}

const near = (a, b, eps = 1e-6) => a.every((v, i) => Math.abs(v - b[i]) <= eps);

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
  const w = worldMatrices(adrPosedDoc.nodes, [0]);
  check(near(position(w[3]), [-0.08, 1.54, 0]), 'posed earring tip');
  check(Math.abs(len(sub(position(w[4]), position(w[2]))) - 0.1) < 1e-9, 'posed hair length');
}

// ---------------------------------------------------------------------------------------------
// (c) A Decentraland-like avatar with a hair wearable.
//
// `Armature` carries Decentraland's scale 0.01 and a +90° rotation about X, as exported armatures
// do; `Avatar_Hips` carries the opposite rotation (-90° about X), so below the hips every offset
// is in centimetres in glTF's frame: +Y up, the avatar faces +Z, +X is the avatar's left. The legs
// are Blender-style: each UpLeg is turned 180° about Z so its bones run along their local +Y
// (Avatar_LeftLeg sits at (0, 44.89, 0) in its parent, as in Decentraland's own armature).
// World positions are checked below.

const ARMATURE_ROTATION = [H, 0, 0, H];   // +90° about X
const HIPS_ROTATION = [-H, 0, 0, H];      // -90° about X: undoes the armature's turn
const LEG_ROTATION = [0, 0, 1, 0];        // 180° about Z: the leg bones point down

function fingers(side, sx) {
  // [first joint offset from the hand, then three segment lengths along the arm's axis]
  const layout = {
    Thumb: [[3, -1, 3], [3, 0, 1.5], [3, 0, 0], [2.5, 0, 0]],
    Index: [[9, 0, 2.5], [4, 0, 0], [2.5, 0, 0], [2, 0, 0]],
    Middle: [[9.5, 0, 0.5], [4.5, 0, 0], [3, 0, 0], [2, 0, 0]],
    Ring: [[9, 0, -1.5], [4, 0, 0], [2.5, 0, 0], [2, 0, 0]],
    Pinky: [[8, 0, -3.5], [3, 0, 0], [2, 0, 0], [1.8, 0, 0]],
  };
  return Object.entries(layout).map(([finger, offsets]) => {
    let tree = null;
    for (let j = 4; j >= 1; j--) {
      const [x, y, z] = offsets[j - 1];
      tree = {
        name: `Avatar_${side}Hand${finger}${j}`,
        t: [x * sx, y, z],
        children: tree ? [tree] : undefined,
      };
    }
    return tree;
  });
}

function arm(side, sx, wearable = []) {
  return {
    name: `Avatar_${side}Shoulder`, t: [3 * sx, 11, -1], children: [{
      name: `Avatar_${side}Arm`, t: [12 * sx, 0, 0], children: [{
        name: `Avatar_${side}ForeArm`, t: [27 * sx, 0, 0], children: [{
          name: `Avatar_${side}Hand`, t: [25 * sx, 0, 0], children: [...fingers(side, sx), ...wearable],
        }],
      }],
    }],
  };
}

function leg(side, sx) {
  return {
    name: `Avatar_${side}UpLeg`, t: [9 * sx, -6, 0], r: LEG_ROTATION, children: [{
      name: `Avatar_${side}Leg`, t: [0, 44.89, 0], children: [{
        name: `Avatar_${side}Foot`, t: [0, 41, 0], children: [{
          name: `Avatar_${side}ToeBase`, t: [0, 6, 12],  // local (0, 6, 12) is 6 cm down, 12 forward
        }],
      }],
    }],
  };
}

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

const avatarTree = {
  name: 'Armature', r: ARMATURE_ROTATION, s: [0.01, 0.01, 0.01], children: [{
    name: 'Avatar_Hips', t: [0, 0, -100], r: HIPS_ROTATION, children: [
      leg('Left', 1),
      leg('Right', -1),
      {
        name: 'Avatar_Spine', t: [0, 10, 0], children: [{
          name: 'Avatar_Spine1', t: [0, 12, 0], children: [{
            name: 'Avatar_Spine2', t: [0, 12, 0], children: [
              arm('Left', 1),
              arm('Right', -1),
              {
                name: 'Avatar_Neck', t: [0, 16, -1], children: [{
                  name: 'Avatar_Head', t: [0, 10, 1], children: hair,
                }],
              },
              // A candidate name whose entry has no isRoot: not a chain.
              { name: 'SpringBoneCollider', t: [0, 5, 10], children: [{ name: 'SpringBoneCollider_end', t: [0, 0, 3] }] },
            ],
          }],
        }],
      },
      // No "springbone" token: never a chain, although the metadata has an entry for it.
      { name: 'skirt_1', t: [0, -8, 12], children: [{ name: 'skirt_1_end', t: [0, -20, 0] }] },
    ],
  }],
};

const AVATAR_BONES = [
  'Hips', 'Spine', 'Spine1', 'Spine2', 'Neck', 'Head',
  ...['Left', 'Right'].flatMap((s) => [
    `${s}Shoulder`, `${s}Arm`, `${s}ForeArm`, `${s}Hand`,
    ...['Thumb', 'Index', 'Middle', 'Ring', 'Pinky'].flatMap((f) => [1, 2, 3, 4].map((j) => `${s}Hand${f}${j}`)),
    `${s}UpLeg`, `${s}Leg`, `${s}Foot`, `${s}ToeBase`,
  ]),
].map((n) => `Avatar_${n}`);

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
  const { nodes, index, rootIndices } = flatten([avatarTree]);
  for (const bone of AVATAR_BONES) check(index.has(bone), `missing ${bone}`);
  check(AVATAR_BONES.length === 62, '62 avatar bones');
  check(new Set(AVATAR_BONES).size === 62, 'avatar bone names unique');

  // --- world positions, checked against the intended avatar (metres, +Y up, facing +Z)
  const world = worldMatrices(nodes, rootIndices);
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
  const vertexCount = positions.length / 3;
  const pos32 = Float32Array.from(positions);
  const min = [0, 1, 2].map((k) => Math.min(...pos32.filter((_, i) => i % 3 === k)));
  const max = [0, 1, 2].map((k) => Math.max(...pos32.filter((_, i) => i % 3 === k)));
  const views = [
    Buffer.from(pos32.buffer),
    Buffer.from(Uint16Array.from(joints).buffer),
    Buffer.from(Float32Array.from(weights).buffer),
    Buffer.from(Uint16Array.from(indices).buffer),
    Buffer.from(Float32Array.from(jointNodes.flatMap((n) => invert(world[n]))).buffer),
  ];
  const bufferViews = [];
  let offset = 0;
  const parts = [];
  views.forEach((bytes, i) => {
    const pad = (4 - (offset % 4)) % 4;
    if (pad) parts.push(Buffer.alloc(pad));
    offset += pad;
    const view = { buffer: 0, byteOffset: offset, byteLength: bytes.length };
    if (i < 3) view.target = 34962;  // ARRAY_BUFFER
    if (i === 3) view.target = 34963;  // ELEMENT_ARRAY_BUFFER
    bufferViews.push(view);
    parts.push(bytes);
    offset += bytes.length;
  });
  const bin = Buffer.concat(parts);

  const meshNode = nodes.length;
  const doc = {
    asset: { version: '2.0', generator: 'springbones scripts/make_fixtures.mjs' },
    scene: 0,
    scenes: [{ name: 'avatar_hair', nodes: [...rootIndices, meshNode] }],
    nodes: [...nodes, { name: 'HairMesh', mesh: 0, skin: 0 }],
    meshes: [{
      name: 'HairMesh',
      primitives: [{
        attributes: { POSITION: 0, JOINTS_0: 1, WEIGHTS_0: 2 },
        indices: 3,
        material: 0,
      }],
    }],
    materials: [{ name: 'Hair', pbrMetallicRoughness: { baseColorFactor: [0.35, 0.2, 0.1, 1], metallicFactor: 0, roughnessFactor: 0.8 } }],
    skins: [{ name: 'Armature', joints: jointNodes, inverseBindMatrices: 4, skeleton: index.get('Armature') }],
    accessors: [
      { bufferView: 0, componentType: 5126, count: vertexCount, type: 'VEC3', min, max },
      { bufferView: 1, componentType: 5123, count: vertexCount, type: 'VEC4' },
      { bufferView: 2, componentType: 5126, count: vertexCount, type: 'VEC4' },
      { bufferView: 3, componentType: 5123, count: indices.length, type: 'SCALAR' },
      { bufferView: 4, componentType: 5126, count: jointNodes.length, type: 'MAT4' },
    ],
    bufferViews,
    buffers: [{ byteLength: bin.length }],
  };
  check(vertexCount < 65536, 'indices fit in 16 bits');
  return { doc, bin, world, index, nodes };
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

function write(name, bytes, info = {}) {
  writeFileSync(join(outDir, name), bytes);
  manifest[name] = { bytes: bytes.length, contentHash: contentHash(bytes), ...info };
  written.push(name);
}

write('adr_example.glb', glb(adrExampleDoc), {
  metadata: 'adr_example.metadata.json', metadataKey: ADR_HASH,
});
write('adr_example.gltf', gltfText(adrExampleDoc), {
  metadata: 'adr_example.metadata.json', metadataKey: ADR_HASH,
});
write('adr_example_posed.glb', glb(adrPosedDoc), {
  metadata: 'adr_example.metadata.json', metadataKey: ADR_HASH,
});
write('adr_example.metadata.json', jsonText(adrExampleMetadata));

const avatar = buildAvatarHair();
const avatarBytes = glb(avatar.doc, avatar.bin);
const avatarHash = contentHash(avatarBytes);
write('avatar_hair.glb', avatarBytes, {
  metadata: 'avatar_hair.metadata.json', metadataKey: avatarHash,
});
write('avatar_hair.metadata.json', jsonText({ version: 1, models: { [avatarHash]: avatarHairEntries } }));

write('two_parents.gltf', gltfText(twoParentsDoc));
write('cycle.gltf', gltfText(cycleDoc));

// Manifest last (it describes the others, not itself).
const sortedManifest = Object.fromEntries(Object.keys(manifest).sort().map((k) => [k, manifest[k]]));
writeFileSync(join(outDir, 'manifest.json'), jsonText({
  comment: 'Written by scripts/make_fixtures.mjs. contentHash: the CIDv1 Decentraland computes for ' +
    'the file (@dcl/hashing hashV1). metadataKey: the models key to load the file with.',
  files: sortedManifest,
}));

// Cross-check the hashes with Decentraland's own implementation when it is installed (it is a
// devDependency; the fixtures do not need it).
let verified = 'not checked (@dcl/hashing not installed)';
try {
  const hashing = (await import('@dcl/hashing')).default;
  const { readFileSync } = await import('node:fs');
  for (const name of Object.keys(manifest)) {
    const expected = await hashing.hashV1(new Uint8Array(readFileSync(join(outDir, name))));
    check(expected === manifest[name].contentHash, `${name}: ${expected} != ${manifest[name].contentHash}`);
  }
  verified = 'match @dcl/hashing hashV1';
} catch (e) {
  if (e.message.startsWith('fixture check failed')) throw e;
}

for (const name of written) {
  const m = manifest[name];
  console.log(`${name.padEnd(28)} ${String(m.bytes).padStart(6)} B  ${m.contentHash}`);
}
console.log(`content hashes: ${verified}`);
console.log(`avatar_hair: ${avatar.nodes.length} skeleton nodes, metadata key ${avatarHash}`);
