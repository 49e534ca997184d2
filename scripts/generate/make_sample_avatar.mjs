// Writes the demo's sample assets into web/demo/assets/:
//
//   avatar.glb                   a mannequin with Decentraland's 62-bone armature, a rigidly skinned
//                                body (one ellipsoid or capsule per bone) and two animations, `idle`
//                                and `walk` (in place), generated procedurally below
//   hair_wearable.glb            a hair wearable: cap, ponytail, two side locks and two earrings,
//                                skinned to spring-bone chains under its own copy of Avatar_Head
//   hair_wearable.metadata.json  its data.springBones, keyed by the GLB's content hash
//   hair_wearable.entity.json    a catalyst-style entity for the wearable (content list,
//                                representations for both body shapes, data.springBones)
//   manifest.json                sizes and content hashes of the files above
//
//   node scripts/generate/make_sample_avatar.mjs [--out DIR]
//
// Node 20; uses only packages the repository already installs (@dcl/hashing for the content hash,
// three for a load check). Deterministic: the same bytes on every run (no timestamps, no random
// numbers; every float is rounded to a fixed number of decimals before it is written).
//
// Conventions (those of tests/fixtures/avatar_hair.glb: the armature of
// scripts/lib/fixtures/dcl_armature.mjs): glTF space is +Y up and the avatar faces +Z, so +X is
// the avatar's left; below the hips every joint offset is in centimetres along world axes.
import { mkdirSync, readFileSync, writeFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import hashing from '@dcl/hashing';  // CommonJS: named imports do not resolve, the default does
import { AVATAR_BONES, FINGERS, dclArmature, flatten } from '../lib/fixtures/dcl_armature.mjs';
import { BinaryBuffer } from '../lib/fixtures/glb.mjs';
import {
  add, cross, dot, invert, lerp, near, normalize, position, qaxis, qconj, qmul, qnormalize, qrotate, qs, round,
  scale, sub,
} from '../lib/fixtures/vec.mjs';

const root = join(dirname(fileURLToPath(import.meta.url)), '..', '..');
const outArg = process.argv.indexOf('--out');  // --out DIR: write elsewhere (the tests compare)
const outDir = outArg > 0 && process.argv[outArg + 1] ? process.argv[outArg + 1] : join(root, 'web', 'demo', 'assets');
const DEG = Math.PI / 180;

// Rotations in degrees about the axes, the unit the poses below are written in.
const rotX = (d) => qaxis([1, 0, 0], d * DEG);
const rotY = (d) => qaxis([0, 1, 0], d * DEG);
const rotZ = (d) => qaxis([0, 0, 1], d * DEG);

function check(condition, message) {
  if (!condition) throw new Error(`sample check failed: ${message}`);
}

// ---------------------------------------------------------------------------------------------
// The Decentraland armature of scripts/lib/fixtures/dcl_armature.mjs, with the sample's own hands
// and legs: the meshes below are shaped around these proportions.

const PROPORTIONS = {
  fingers: {  // first joint's offset from the hand, then the three segments (T-pose, palm down, cm)
    Thumb: [[2.5, -1.5, 3], [3, -0.5, 1.5], [2.8, 0, 0.5], [2.4, 0, 0]],
    Index: [[9, 0, 2.4], [4, 0, 0], [2.6, 0, 0], [2, 0, 0]],
    Middle: [[9.4, 0, 0.6], [4.4, 0, 0], [2.9, 0, 0], [2.1, 0, 0]],
    Ring: [[9, 0, -1.3], [4, 0, 0], [2.6, 0, 0], [2, 0, 0]],
    Pinky: [[8.2, 0, -3.1], [3.1, 0, 0], [2, 0, 0], [1.8, 0, 0]],
  },
  leg: 44,
  foot: 42,
};

// ---------------------------------------------------------------------------------------------
// Geometry: a mesh builder writing positions, normals, optional vertex colours and one or two
// joint influences per vertex.

class MeshBuilder {
  constructor() {
    this.positions = [];
    this.normals = [];
    this.colors = [];
    this.joints = [];
    this.weights = [];
    this.indices = [];
  }

  get vertexCount() { return this.positions.length / 3; }

  vertex(p, n, influences, color) {
    this.positions.push(...p);
    this.normals.push(...normalize(n));
    if (color) this.colors.push(...color, 1);
    const j = [0, 0, 0, 0];
    const w = [0, 0, 0, 0];
    influences.forEach(([joint, weight], k) => { j[k] = joint; w[k] = weight; });
    this.joints.push(...j);
    this.weights.push(...w);
    return this.vertexCount - 1;
  }

  /** A grid of rows x (cols + 1) vertices, closed around (the last column repeats the first). */
  grid(rows, cols, at) {
    const base = this.vertexCount;
    for (let i = 0; i < rows; i++) {
      for (let j = 0; j <= cols; j++) at(i, j % cols === 0 && j > 0 ? 0 : j);
    }
    for (let i = 0; i + 1 < rows; i++) {
      for (let j = 0; j < cols; j++) {
        const a = base + i * (cols + 1) + j;
        const b = a + cols + 1;
        this.indices.push(a, a + 1, b, a + 1, b + 1, b);  // counter-clockwise seen from outside
      }
    }
  }

  /** Ellipsoid with radii along the axes u, v, w (unit vectors), rigidly on one joint. */
  ellipsoid(center, radii, joint, color, { axes = [[1, 0, 0], [0, 1, 0], [0, 0, 1]], rows = 10, cols = 16 } = {}) {
    const [u, v, w] = axes;
    this.grid(rows + 1, cols, (i, j) => {
      const theta = (Math.PI * i) / rows;  // from +v (top) to -v
      const phi = (2 * Math.PI * j) / cols;
      const s = [Math.sin(theta) * Math.cos(phi), Math.cos(theta), Math.sin(theta) * Math.sin(phi)];
      const p = add(center, add(add(scale(u, s[0] * radii[0]), scale(v, s[1] * radii[1])), scale(w, s[2] * radii[2])));
      const n = add(add(scale(u, s[0] / radii[0]), scale(v, s[1] / radii[1])), scale(w, s[2] / radii[2]));
      this.vertex(p, n, [[joint, 1]], color);
    });
  }

  /** Capsule from a to b, radius ra at a and rb at b, rigidly on one joint. */
  capsule(a, b, ra, rb, joint, color, { cols = 12, capRows = 4 } = {}) {
    const axis = normalize(sub(b, a));
    const ref = Math.abs(axis[1]) < 0.9 ? [0, 1, 0] : [1, 0, 0];
    const u = normalize(cross(axis, ref));
    const v = cross(axis, u);
    const rings = [];  // [center, radius, axial normal component]
    for (let i = 0; i <= capRows; i++) {  // hemisphere around a, from the pole to the equator
      const t = (Math.PI / 2) * (i / capRows);
      rings.push([add(a, scale(axis, -ra * Math.cos(t))), ra * Math.sin(t), -Math.cos(t)]);
    }
    for (let i = 0; i <= capRows; i++) {  // hemisphere around b
      const t = (Math.PI / 2) * (i / capRows);
      rings.push([add(b, scale(axis, rb * Math.sin(t))), rb * Math.cos(t), Math.sin(t)]);
    }
    this.grid(rings.length, cols, (i, j) => {
      const [c, r, axial] = rings[i];
      const phi = (2 * Math.PI * j) / cols;
      const radial = add(scale(u, Math.cos(phi)), scale(v, Math.sin(phi)));
      const n = add(scale(radial, Math.sqrt(Math.max(0, 1 - axial * axial))), scale(axis, axial));
      this.vertex(add(c, scale(radial, r)), n, [[joint, 1]], color);
    });
  }

  /** A tube through `rings` ({c, rx, ry, influences}), elliptic cross-section whose rx axis is the
   *  direction `side` made perpendicular to the tube; closed at both ends. */
  tube(rings, side, { cols = 12 } = {}) {
    const frames = rings.map((ring, i) => {
      const prev = rings[Math.max(0, i - 1)].c;
      const next = rings[Math.min(rings.length - 1, i + 1)].c;
      const t = normalize(sub(next, prev));
      const u = normalize(sub(side, scale(t, dot(side, t))));
      return { t, u, v: cross(t, u) };
    });
    // start cap: a fan around the first ring's centre
    const first = rings[0];
    const startCenter = this.vertex(first.c, scale(frames[0].t, -1), first.influences);
    const base = this.vertexCount;
    this.grid(rings.length, cols, (i, j) => {
      const { c, rx, ry, influences } = rings[i];
      const { u, v } = frames[i];
      const phi = (2 * Math.PI * j) / cols;
      const p = add(c, add(scale(u, rx * Math.cos(phi)), scale(v, ry * Math.sin(phi))));
      const n = add(scale(u, Math.cos(phi) / Math.max(rx, 1e-4)), scale(v, Math.sin(phi) / Math.max(ry, 1e-4)));
      this.vertex(p, n, influences);
    });
    for (let j = 0; j < cols; j++) this.indices.push(startCenter, base + j + 1, base + j);
    const last = rings[rings.length - 1];
    const endCenter = this.vertex(last.c, frames[rings.length - 1].t, last.influences);
    const lastRow = base + (rings.length - 1) * (cols + 1);
    for (let j = 0; j < cols; j++) this.indices.push(endCenter, lastRow + j, lastRow + j + 1);
  }

  /** A cap of an ellipsoid: for each azimuth, polar angles from the top down to maxPolar(phi). */
  cap(center, radii, joint, maxPolar, { rows = 10, cols = 24 } = {}) {
    this.grid(rows + 1, cols, (i, j) => {
      const phi = (2 * Math.PI * j) / cols;  // 0 = +X (left), 90° = +Z (front)
      const theta = maxPolar(phi) * (i / rows);
      const s = [Math.sin(theta) * Math.cos(phi), Math.cos(theta), Math.sin(theta) * Math.sin(phi)];
      const p = add(center, [s[0] * radii[0], s[1] * radii[1], s[2] * radii[2]]);
      this.vertex(p, [s[0] / radii[0], s[1] / radii[1], s[2] / radii[2]], [[joint, 1]]);
    });
  }
}

// ---------------------------------------------------------------------------------------------
// glTF / GLB writing

/** A skinned primitive from a MeshBuilder, its attributes rounded so that the file is the same
 *  on every machine. */
function skinnedPrimitive(buffer, mesh, material) {
  const f32 = (values, decimals) => Float32Array.from(values, (v) => round(v, decimals));
  const attributes = {
    POSITION: buffer.accessor(f32(mesh.positions, 6), 'VEC3', { target: 34962, minMax: true }),
    NORMAL: buffer.accessor(f32(mesh.normals, 5), 'VEC3', { target: 34962 }),
  };
  if (mesh.colors.length) attributes.COLOR_0 = buffer.accessor(f32(mesh.colors, 4), 'VEC4', { target: 34962 });
  attributes.JOINTS_0 = buffer.accessor(Uint8Array.from(mesh.joints), 'VEC4', { target: 34962 });
  attributes.WEIGHTS_0 = buffer.accessor(f32(mesh.weights, 5), 'VEC4', { target: 34962 });
  const IndexArray = mesh.vertexCount < 65536 ? Uint16Array : Uint32Array;
  const indices = buffer.accessor(IndexArray.from(mesh.indices), 'SCALAR', { target: 34963 });
  return { attributes, indices, material };
}

/** sRGB colour (0-255) to the linear values glTF colours hold. */
const linear = (r, g, b) => [r, g, b].map((c) => {
  const s = c / 255;
  return round(s <= 0.04045 ? s / 12.92 : ((s + 0.055) / 1.055) ** 2.4, 4);
});

// ---------------------------------------------------------------------------------------------
// (a) The avatar

const SKIN = linear(224, 172, 138);
const SHIRT = linear(64, 112, 170);
const PANTS = linear(52, 56, 76);
const SHOES = linear(40, 32, 28);
const EYES = linear(30, 30, 36);

function buildAvatarBody(sk) {
  const mesh = new MeshBuilder();
  const jointSlot = new Map(AVATAR_BONES.map((name, slot) => [name, slot]));
  const at = (name) => position(sk.world[sk.index.get(name)]);
  const slot = (name) => jointSlot.get(name);
  const offset = (name, d) => add(at(name), d);

  // Torso and head (world metres; below the hips the bone frames are world-aligned).
  mesh.ellipsoid(offset('Avatar_Hips', [0, -0.03, 0]), [0.155, 0.1, 0.105], slot('Avatar_Hips'), PANTS);
  mesh.ellipsoid(offset('Avatar_Spine', [0, 0.06, 0]), [0.14, 0.09, 0.095], slot('Avatar_Spine'), SHIRT);
  mesh.ellipsoid(offset('Avatar_Spine1', [0, 0.06, 0]), [0.15, 0.09, 0.1], slot('Avatar_Spine1'), SHIRT);
  mesh.ellipsoid(offset('Avatar_Spine2', [0, 0.05, -0.005]), [0.17, 0.115, 0.11], slot('Avatar_Spine2'), SHIRT);
  mesh.capsule(offset('Avatar_Neck', [0, -0.02, 0]), at('Avatar_Head'), 0.048, 0.045, slot('Avatar_Neck'), SKIN);
  mesh.ellipsoid(offset('Avatar_Head', [0, 0.09, 0.01]), [0.092, 0.112, 0.102], slot('Avatar_Head'), SKIN);
  // a nose and two eyes, so the facing direction (+Z) reads at a glance
  mesh.ellipsoid(offset('Avatar_Head', [0, 0.075, 0.112]), [0.014, 0.022, 0.018], slot('Avatar_Head'), SKIN, { rows: 6, cols: 10 });
  for (const x of [-0.035, 0.035]) {
    mesh.ellipsoid(offset('Avatar_Head', [x, 0.105, 0.098]), [0.012, 0.012, 0.008], slot('Avatar_Head'), EYES, { rows: 6, cols: 10 });
  }

  for (const side of ['Left', 'Right']) {
    const sx = side === 'Left' ? 1 : -1;
    const b = (n) => `Avatar_${side}${n}`;
    mesh.capsule(at(b('Shoulder')), at(b('Arm')), 0.045, 0.05, slot(b('Shoulder')), SHIRT);
    mesh.capsule(at(b('Arm')), at(b('ForeArm')), 0.048, 0.04, slot(b('Arm')), SHIRT);
    mesh.capsule(at(b('ForeArm')), at(b('Hand')), 0.037, 0.03, slot(b('ForeArm')), SKIN);
    mesh.ellipsoid(offset(b('Hand'), [0.045 * sx, 0, 0]), [0.05, 0.017, 0.042], slot(b('Hand')), SKIN);
    for (const f of FINGERS) {
      const r = f === 'Thumb' ? 0.0105 : f === 'Pinky' ? 0.0075 : 0.0088;
      for (let j = 1; j <= 3; j++) {
        mesh.capsule(at(b(`Hand${f}${j}`)), at(b(`Hand${f}${j + 1}`)), r, r * 0.92, slot(b(`Hand${f}${j}`)), SKIN, { cols: 8, capRows: 2 });
      }
    }
    mesh.capsule(at(b('UpLeg')), at(b('Leg')), 0.075, 0.058, slot(b('UpLeg')), PANTS);
    mesh.capsule(at(b('Leg')), at(b('Foot')), 0.055, 0.042, slot(b('Leg')), PANTS);
    mesh.ellipsoid(offset(b('Foot'), [0, -0.035, 0.045]), [0.05, 0.042, 0.105], slot(b('Foot')), SHOES);
    mesh.ellipsoid(offset(b('ToeBase'), [0, 0.005, 0.025]), [0.045, 0.03, 0.045], slot(b('ToeBase')), SHOES);
  }
  return mesh;
}

// Animation. Each bone's motion is written as a rotation D in the avatar's rest-aligned axes
// (world axes in the T-pose: +X left, +Y up, +Z forward), applied at the bone after its parent's
// motion. Its local rotation is then r = r_rest * W^-1 * D * W, with W the bone's rest world
// rotation, so the same D means the same thing on a leg (flipped frame) as on an arm.

function pose(sk, name, D) {
  const i = sk.index.get(name);
  const rRest = sk.nodes[i].rotation ?? [0, 0, 0, 1];
  const W = sk.worldRotation[i];
  return qnormalize(qmul(rRest, qmul(qconj(W), qmul(D, W))));
}

const smoothMax0 = (x) => (x > 0 ? x * x : 0);

/** The rotations (D, rest-aligned axes) and hip offset (metres) at phase `t` of a clip. */
const CLIPS = {
  // 8 s: two breaths (4 s each) and one slow weight shift from foot to foot.
  idle: {
    duration: 8, fps: 10,
    pose(t) {
      const breath = Math.sin((2 * Math.PI * t) / 4);
      const sway = Math.sin((2 * Math.PI * t) / 8);
      const look = Math.sin((2 * Math.PI * t) / 8 + 1.2);
      const D = {
        Hips: rotZ(1.6 * sway),
        Spine: rotZ(-1.2 * sway),
        Spine1: rotX(-1.0 * breath),
        Spine2: rotX(-1.4 * breath),
        Neck: qs(rotZ(-0.4 * sway), rotX(0.8 * breath)),
        Head: qs(rotY(6 * look), rotX(1.5 + 1.2 * breath)),
      };
      for (const [side, sx] of [['Left', 1], ['Right', -1]]) {
        D[`${side}Shoulder`] = rotZ(sx * 1.5 * (breath + 1));
        D[`${side}Arm`] = qs(rotX(-4 + 2 * sway * sx), rotZ(-sx * 78));
        D[`${side}ForeArm`] = rotY(-sx * 14);
        D[`${side}Hand`] = rotX(-4);
        D[`${side}UpLeg`] = rotZ(-1.6 * sway + sx * 2);
        D[`${side}Leg`] = rotX(2 + (sx * sway > 0 ? 0 : 3 * Math.abs(sway)));
        D[`${side}Foot`] = rotZ(-sx * 2);
      }
      return { D, hips: [0.012 * sway, -0.004 - 0.002 * Math.abs(sway), 0] };
    },
  },
  // 1.1 s: one stride (two steps), in place.
  walk: {
    duration: 1.1, fps: 30,
    pose(t) {
      const phase = (2 * Math.PI * t) / 1.1;
      const s = Math.sin(phase);
      const c = Math.cos(phase);
      const kneeL = 4 + 55 * smoothMax0(Math.cos(phase - 0.35));
      const kneeR = 4 + 55 * smoothMax0(-Math.cos(phase - 0.35));
      const D = {
        Hips: qs(rotY(-7 * s), rotZ(3 * c)),
        Spine: rotX(3),
        Spine1: rotZ(-2 * c),
        Spine2: rotY(11 * s),
        Neck: rotY(-2 * s),
        Head: qs(rotY(-2 * s), rotX(-2)),
        LeftUpLeg: rotX(-26 * s - 4),
        RightUpLeg: rotX(26 * s - 4),
        LeftLeg: rotX(kneeL),
        RightLeg: rotX(kneeR),
        LeftFoot: rotX(-0.45 * (kneeL - 4) + 8 * s),
        RightFoot: rotX(-0.45 * (kneeR - 4) - 8 * s),
      };
      for (const [side, sx] of [['Left', 1], ['Right', -1]]) {
        const swing = 20 * s * sx;  // left arm back while the left leg is forward
        D[`${side}Shoulder`] = rotZ(sx * 1.5);
        D[`${side}Arm`] = qs(rotX(swing - 2), rotZ(-sx * 79));
        D[`${side}ForeArm`] = rotY(-sx * (18 + 14 * Math.max(0, -swing / 20)));
        D[`${side}Hand`] = rotX(-6);
      }
      return { D, hips: [0.012 * s, 0.016 * Math.cos(2 * phase) - 0.012, 0] };
    },
  },
};

/** A relaxed hand, the same in both clips. */
function fingerPose(side) {
  const sx = side === 'Left' ? 1 : -1;
  const out = {};
  const curl = { Thumb: [8, 10, 8], Index: [12, 18, 12], Middle: [15, 22, 14], Ring: [18, 25, 16], Pinky: [22, 28, 18] };
  for (const f of FINGERS) {
    for (let j = 1; j <= 3; j++) {
      out[`${side}Hand${f}${j}`] = f === 'Thumb' ? qs(rotY(-sx * curl[f][j - 1])) : rotZ(-sx * curl[f][j - 1]);
    }
  }
  return out;
}

function buildAnimations(sk, buffer) {
  const animations = [];
  const armatureRotation = sk.nodes[sk.index.get('Armature')].rotation;
  const hipsRest = sk.nodes[sk.index.get('Avatar_Hips')].translation;
  for (const [name, clip] of Object.entries(CLIPS)) {
    const frames = Math.round(clip.duration * clip.fps);
    const times = Float32Array.from({ length: frames + 1 }, (_, i) => round(i / clip.fps, 6));
    const timeAccessor = buffer.accessor(times, 'SCALAR', { minMax: true });
    const staticTimes = buffer.accessor(Float32Array.from([0, round(clip.duration, 6)]), 'SCALAR', { minMax: true });
    const poses = Array.from(times, (t, i) => clip.pose(i === frames ? 0 : t));  // last key = first: loops
    const channels = [];
    const samplers = [];
    const addChannel = (node, path, input, values, type) => {
      samplers.push({ input, output: buffer.accessor(values, type), interpolation: 'LINEAR' });
      channels.push({ sampler: samplers.length - 1, target: { node: sk.index.get(node), path } });
    };
    // every bone both clips move, so switching clips never leaves a bone in the other clip's pose
    const animated = Object.keys(poses[0].D);
    for (const bone of animated) {
      const values = new Float32Array(poses.length * 4);
      poses.forEach((p, i) => {
        let q = pose(sk, `Avatar_${bone}`, p.D[bone]);
        // keep consecutive keys in the same hemisphere (no long way round when interpolating)
        if (i > 0 && q[0] * values[i * 4 - 4] + q[1] * values[i * 4 - 3] + q[2] * values[i * 4 - 2] + q[3] * values[i * 4 - 1] < 0) {
          q = q.map((v) => -v);
        }
        q.forEach((v, k) => { values[i * 4 + k] = round(v, 7); });
      });
      addChannel(`Avatar_${bone}`, 'rotation', timeAccessor, values, 'VEC4');
    }
    for (const side of ['Left', 'Right']) {
      for (const [bone, D] of Object.entries(fingerPose(side))) {
        const q = pose(sk, `Avatar_${bone}`, D).map((v) => round(v, 7));
        addChannel(`Avatar_${bone}`, 'rotation', staticTimes, Float32Array.from([...q, ...q]), 'VEC4');
      }
    }
    const hips = new Float32Array(poses.length * 3);
    poses.forEach((p, i) => {
      // world offset (m) into the Armature's frame (cm, turned +90° about X)
      const local = add(hipsRest, qrotate(qconj(armatureRotation), scale(p.hips, 100)));
      local.forEach((v, k) => { hips[i * 3 + k] = round(v, 5); });
    });
    addChannel('Avatar_Hips', 'translation', timeAccessor, hips, 'VEC3');
    animations.push({ name, channels, samplers });
  }
  return animations;
}

function buildAvatar() {
  const sk = flatten([dclArmature({ proportions: PROPORTIONS })]);
  for (const bone of AVATAR_BONES) check(sk.index.has(bone), `missing ${bone}`);
  check(AVATAR_BONES.length === 62 && new Set(AVATAR_BONES).size === 62, '62 unique avatar bones');
  const at = (name) => position(sk.world[sk.index.get(name)]);
  check(near(at('Avatar_Hips'), [0, 1, 0]), 'hips 1 m up');
  check(near(at('Avatar_Head'), [0, 1.6, 0]), 'head 1.6 m up');
  check(near(at('Avatar_LeftHand'), [0.67, 1.45, -0.01]), 'left hand on +X (T-pose)');
  check(near(at('Avatar_LeftToeBase'), [0.09, 0.02, 0.12]), 'toes in front of the ankle (+Z)');

  const buffer = new BinaryBuffer();
  const body = buildAvatarBody(sk);
  const jointNodes = AVATAR_BONES.map((n) => sk.index.get(n));
  const inverseBind = Float32Array.from(jointNodes.flatMap((i) => invert(sk.world[i]).map((v) => round(v, 6))));
  const primitive = skinnedPrimitive(buffer, body, 0);
  const ibm = buffer.accessor(inverseBind, 'MAT4');
  const animations = buildAnimations(sk, buffer);
  const meshNode = sk.nodes.length;
  const doc = {
    asset: { version: '2.0', generator: 'springbones scripts/generate/make_sample_avatar.mjs' },
    scene: 0,
    scenes: [{ name: 'avatar', nodes: [...sk.roots, meshNode] }],
    nodes: [...sk.nodes, { name: 'Body', mesh: 0, skin: 0 }],
    meshes: [{ name: 'Body', primitives: [primitive] }],
    materials: [{
      name: 'Mannequin',
      pbrMetallicRoughness: { baseColorFactor: [1, 1, 1, 1], metallicFactor: 0, roughnessFactor: 0.75 },
    }],
    skins: [{ name: 'Armature', joints: jointNodes, inverseBindMatrices: ibm, skeleton: sk.index.get('Armature') }],
    animations,
  };
  return { bytes: buffer.glb(doc), vertices: body.vertexCount, nodes: doc.nodes.length };
}

// ---------------------------------------------------------------------------------------------
// (b) The hair wearable. Spring-bone offsets are in centimetres in Avatar_Head's frame, which is
// world-aligned in the rest pose (head at 1.6 m; the avatar's skull is an ellipsoid centred 9 cm
// above it, radii 9.2 x 11.2 x 10.2 cm).

/** A linear chain: the root at `t`, each following node an offset from the previous one. */
function chain(names, t, offsets) {
  let tree = null;
  for (let i = names.length - 1; i >= 0; i--) {
    tree = { name: names[i], t: i === 0 ? t : offsets[i - 1], children: tree ? [tree] : undefined };
  }
  return tree;
}

const PONYTAIL = ['SpringBone_ponytail', 'SpringBone_ponytail_1', 'SpringBone_ponytail_2',
  'SpringBone_ponytail_3', 'SpringBone_ponytail_4', 'SpringBone_ponytail_tip'];
const lock = (s) => [`hair_springbone_${s}`, `hair_springbone_${s}_1`, `hair_springbone_${s}_2`, `hair_springbone_${s}_tip`];
const earring = (s) => [`springbone_earring_${s}`, `springbone_earring_${s}_1`, `springbone_earring_${s}_tip`];

const hairChains = [
  chain(PONYTAIL, [0, 17, -9], [[0, -3, -5], [0, -7, -3], [0, -7, -1.5], [0, -7, -0.5], [0, -6, 0]]),
  chain(lock('l'), [8.2, 14, 6.5], [[1.3, -6, 0.4], [0.6, -6, 0], [0.1, -5, 0]]),
  chain(lock('r'), [-8.2, 14, 6.5], [[-1.3, -6, 0.4], [-0.6, -6, 0], [-0.1, -5, 0]]),
  chain(earring('l'), [9.3, 4.5, 1.5], [[0, -1.6, 0], [0, -3.2, 0]]),
  chain(earring('r'), [-9.3, 4.5, 1.5], [[0, -1.6, 0], [0, -3.2, 0]]),
];

const HAIR_COLOR = [...linear(92, 52, 28), 1];
const GOLD = [...linear(255, 200, 90), 1];

function buildWearable() {
  const sk = flatten([dclArmature({ proportions: PROPORTIONS, full: false, extraChildren: { Avatar_Head: hairChains } })]);
  const at = (name) => position(sk.world[sk.index.get(name)]);
  check(near(at('Avatar_Head'), [0, 1.6, 0]), 'wearable head matches the avatar');
  check(near(at('SpringBone_ponytail_tip'), [0, 1.6 + (17 - 3 - 7 - 7 - 7 - 6) / 100, -0.19]), 'ponytail tip');

  // Skin joints: every node below Armature (a Blender export lists the whole armature).
  const jointNodes = sk.nodes.map((_, i) => i).filter((i) => sk.nodes[i].name !== 'Armature');
  const slot = new Map(jointNodes.map((node, s) => [sk.nodes[node].name, s]));
  const head = slot.get('Avatar_Head');

  // Hair: a cap over the skull (low at the back, above the brow at the front), the ponytail and
  // the side locks. Tubes blend the two bones meeting at each inner node, so they bend smoothly.
  const hair = new MeshBuilder();
  const headPos = at('Avatar_Head');
  hair.cap(add(headPos, [0, 0.093, 0.002]), [0.101, 0.12, 0.112], head, (phi) => {
    const front = Math.sin(phi);  // +1 front, -1 back: a fringe above the brow, the nape covered
    return (lerp(132, 60, (front + 1) / 2) + 6 * Math.abs(Math.cos(phi))) * DEG;
  }, { rows: 14, cols: 32 });
  const chainRings = (names, radii, side) => {
    const rings = [];
    const steps = 3;  // rings per segment
    for (let k = 0; k + 1 < names.length; k++) {
      const a = at(names[k]);
      const b = at(names[k + 1]);
      for (let i = 0; i < steps; i++) {
        const t = i / steps;
        const [rx0, ry0] = radii[k];
        const [rx1, ry1] = radii[k + 1];
        // the ring at a node is shared half-and-half with the bone before it
        const influences = i === 0 && k > 0 ? [[slot.get(names[k]), 0.5], [slot.get(names[k - 1]), 0.5]] : [[slot.get(names[k]), 1]];
        rings.push({ c: add(a, scale(sub(b, a), t)), rx: lerp(rx0, rx1, t), ry: lerp(ry0, ry1, t), influences });
      }
    }
    const last = names.length - 1;
    rings.push({ c: at(names[last]), rx: radii[last][0], ry: radii[last][1], influences: [[slot.get(names[last - 1]), 1]] });
    hair.tube(rings, side);
  };
  chainRings(PONYTAIL, [[0.022, 0.022], [0.03, 0.028], [0.03, 0.027], [0.026, 0.023], [0.018, 0.016], [0.004, 0.004]], [1, 0, 0]);
  for (const s of ['l', 'r']) {
    chainRings(lock(s), [[0.006, 0.018], [0.007, 0.02], [0.006, 0.017], [0.002, 0.006]], [1, 0, 0]);
  }
  // a hair tie around the ponytail's root
  hair.capsule(add(at('SpringBone_ponytail'), [0, -0.008, -0.014]), add(at('SpringBone_ponytail'), [0, -0.016, -0.028]),
    0.026, 0.026, slot.get('SpringBone_ponytail'), null, { cols: 14, capRows: 2 });

  // Earrings: a thin link on the first bone, a drop on the second.
  const gold = new MeshBuilder();
  for (const s of ['l', 'r']) {
    const [r0, r1, tip] = earring(s).map(at);
    gold.capsule(r0, r1, 0.0022, 0.0022, slot.get(earring(s)[0]), null, { cols: 8, capRows: 2 });
    const mid = scale(add(r1, tip), 0.5);
    gold.ellipsoid(mid, [0.009, 0.016, 0.009], slot.get(earring(s)[1]), null, { rows: 8, cols: 12 });
  }

  const buffer = new BinaryBuffer();
  const hairPrimitive = skinnedPrimitive(buffer, hair, 0);
  const goldPrimitive = skinnedPrimitive(buffer, gold, 1);
  const ibm = buffer.accessor(Float32Array.from(jointNodes.flatMap((i) => invert(sk.world[i]).map((v) => round(v, 6)))), 'MAT4');
  const hairNode = sk.nodes.length;
  const doc = {
    asset: { version: '2.0', generator: 'springbones scripts/generate/make_sample_avatar.mjs' },
    scene: 0,
    scenes: [{ name: 'hair_wearable', nodes: [...sk.roots, hairNode, hairNode + 1] }],
    nodes: [...sk.nodes, { name: 'Hair', mesh: 0, skin: 0 }, { name: 'Earrings', mesh: 1, skin: 0 }],
    meshes: [{ name: 'Hair', primitives: [hairPrimitive] }, { name: 'Earrings', primitives: [goldPrimitive] }],
    materials: [
      { name: 'Hair', doubleSided: true, pbrMetallicRoughness: { baseColorFactor: HAIR_COLOR, metallicFactor: 0, roughnessFactor: 0.6 } },
      { name: 'Gold', pbrMetallicRoughness: { baseColorFactor: GOLD, metallicFactor: 0.8, roughnessFactor: 0.3 } },
    ],
    skins: [{ name: 'Armature', joints: jointNodes, inverseBindMatrices: ibm, skeleton: sk.index.get('Armature') }],
  };
  const springNodes = sk.nodes.filter((n) => /springbone/i.test(n.name)).map((n) => n.name);
  return { bytes: buffer.glb(doc), springNodes, nodes: doc.nodes.length, vertices: hair.vertexCount + gold.vertexCount };
}

// data.springBones entries. The ponytail has a softer member override near its end; the earrings
// use Avatar_Hips as their center (the ADR's example), so turning the whole avatar does not swing
// them but the walk's hip twist does.
const down = [0, -1, 0];
const HAIR_ENTRIES = {
  SpringBone_ponytail: { stiffness: 1.2, gravityPower: 0.4, gravityDir: down, drag: 0.3, isRoot: true },
  SpringBone_ponytail_3: { stiffness: 0.7, gravityPower: 0.5, gravityDir: down, drag: 0.25, isRoot: false },
  hair_springbone_l: { stiffness: 1.6, gravityPower: 0.3, gravityDir: down, drag: 0.4, isRoot: true },
  hair_springbone_r: { stiffness: 1.6, gravityPower: 0.3, gravityDir: down, drag: 0.4, isRoot: true },
  springbone_earring_l: { stiffness: 0.5, gravityPower: 1, gravityDir: down, drag: 0.2, center: 'Avatar_Hips', isRoot: true },
  springbone_earring_r: { stiffness: 0.5, gravityPower: 1, gravityDir: down, drag: 0.2, center: 'Avatar_Hips', isRoot: true },
};

// ---------------------------------------------------------------------------------------------
// Write everything

mkdirSync(outDir, { recursive: true });
const jsonText = (value) => Buffer.from(JSON.stringify(value, null, 2) + '\n', 'utf8');
const manifest = {};
async function write(name, bytes, info = {}) {
  writeFileSync(join(outDir, name), bytes);
  manifest[name] = { bytes: bytes.length, contentHash: await hashing.hashV1(new Uint8Array(bytes)), ...info };
  return manifest[name].contentHash;
}

const avatar = buildAvatar();
await write('avatar.glb', avatar.bytes, { animations: Object.keys(CLIPS) });

const wearable = buildWearable();
const wearableHash = await write('hair_wearable.glb', wearable.bytes, {
  metadata: 'hair_wearable.metadata.json', springBoneNodes: wearable.springNodes,
});
const springBones = { version: 1, models: { [wearableHash]: HAIR_ENTRIES } };
for (const bone of Object.keys(HAIR_ENTRIES)) check(wearable.springNodes.includes(bone), `${bone} is a node of the wearable`);
await write('hair_wearable.metadata.json', jsonText(springBones));

const BODY_SHAPES = ['urn:decentraland:off-chain:base-avatars:BaseMale', 'urn:decentraland:off-chain:base-avatars:BaseFemale'];
const entity = {
  version: 'v3',
  type: 'wearable',
  pointers: ['urn:decentraland:off-chain:springbones-demo:hair_wearable'],
  timestamp: 1767225600000,  // fixed (2026-01-01): deterministic output
  content: [{ file: 'hair_wearable.glb', hash: wearableHash }],
  metadata: {
    id: 'urn:decentraland:off-chain:springbones-demo:hair_wearable',
    name: 'Ponytail with side locks and earrings (springbones sample)',
    description: 'Generated by scripts/generate/make_sample_avatar.mjs',
    i18n: [{ code: 'en', text: 'Ponytail with side locks and earrings' }],
    data: {
      replaces: [],
      hides: [],
      tags: ['hair', 'springbones'],
      category: 'hair',
      representations: [{
        bodyShapes: BODY_SHAPES,
        mainFile: 'hair_wearable.glb',
        contents: ['hair_wearable.glb'],
        overrideHides: [],
        overrideReplaces: [],
      }],
      springBones,
    },
  },
};
await write('hair_wearable.entity.json', jsonText(entity));

writeFileSync(join(outDir, 'manifest.json'), jsonText({
  comment: 'Written by scripts/generate/make_sample_avatar.mjs. contentHash: @dcl/hashing hashV1 of the file.',
  files: manifest,
}));

// Load check: three.js's GLTFLoader parses both GLBs (no DOM needed: no textures).
let loadCheck = 'skipped (three not installed)';
try {
  const { GLTFLoader } = await import('three/examples/jsm/loaders/GLTFLoader.js');
  const loader = new GLTFLoader();
  for (const name of ['avatar.glb', 'hair_wearable.glb']) {
    const bytes = readFileSync(join(outDir, name));
    const buffer = bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength);
    const gltf = await loader.parseAsync(buffer, '');
    let skinned = 0;
    gltf.scene.traverse((o) => { if (o.isSkinnedMesh) skinned++; });
    check(skinned > 0, `${name}: a skinned mesh`);
    if (name === 'avatar.glb') {
      check(gltf.animations.map((a) => a.name).join() === 'idle,walk', 'avatar clips idle, walk');
      for (const bone of AVATAR_BONES) check(gltf.scene.getObjectByName(bone), `avatar: ${bone} in three.js`);
    } else {
      for (const bone of wearable.springNodes) check(gltf.scene.getObjectByName(bone), `wearable: ${bone} in three.js`);
    }
  }
  loadCheck = 'both GLBs parse in three.js GLTFLoader';
} catch (e) {
  if (e.message.startsWith('sample check failed') || !/Cannot find (module|package)/.test(e.message)) throw e;
}

for (const [name, m] of Object.entries(manifest)) {
  console.log(`${name.padEnd(28)} ${String(m.bytes).padStart(7)} B  ${m.contentHash}`);
}
console.log(`avatar: ${avatar.nodes} nodes, ${avatar.vertices} vertices; wearable: ${wearable.nodes} nodes, ` +
  `${wearable.vertices} vertices, ${wearable.springNodes.length} springbone nodes`);
console.log(`load check: ${loadCheck}`);
