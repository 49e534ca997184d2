// Writes the ADR-316 conformance pack: conformance/glb/*.glb and conformance/cases/*.json
// (conformance/README.md describes the format; conformance/run.mjs replays it on springbones).
//
//   node scripts/generate/make_conformance.mjs [--out <dir>]
//
// --out writes the pack elsewhere (default: conformance/), e.g. to compare it with the one checked in.
//
// Needs the npm devDependencies (@dcl/hashing for the content hashes). Deterministic: running it
// again rewrites the same bytes.
//
// Every expected rotation comes from scripts/lib/adr_reference.mjs, a second implementation of
// docs/semantics.md's rules that shares no code with springbones, or is a node's exact rest
// rotation read from the GLB. On top of that, cases whose answer follows from a symmetry are
// checked against it here (a chain whose center moves rigidly with it, a chain carried across a
// jump, a disabled rig), so the reference itself is tested before its numbers are written.
import { mkdirSync, rmSync, writeFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import hashing from '@dcl/hashing';  // CommonJS: named imports do not resolve, the default does
import { dclArmature, flatten } from '../lib/fixtures/dcl_armature.mjs';
import { glbOfDoc } from '../lib/fixtures/glb.mjs';
import { sig, still, swayMotion, walk } from '../lib/fixtures/motions.mjs';
import { mmul, qaxis, round, trsMatrix } from '../lib/fixtures/vec.mjs';
import { ReferenceInstance, buildRig, modelEntry, modelKey, poseWorld } from '../lib/adr_reference.mjs';

const root = join(dirname(fileURLToPath(import.meta.url)), '..', '..');
const outFlag = process.argv.indexOf('--out');
const outDir = outFlag >= 0 ? process.argv[outFlag + 1] : join(root, 'conformance');
if (!outDir) throw new Error('--out needs a folder');

const FORMAT = 'springbones-conformance/1';
// Radians, per node and frame (conformance/README.md, "Tolerance"): springbones computes in 32-bit
// floats, whose positions 1.6 m up are 1.2e-7 m apart, 2.4e-6 rad on a 5 cm bone, and a spring
// carries such errors over a few steps; its largest difference from the reference on the pack is
// 9.4e-6 rad, a third of this.
const TOLERANCE = 3e-5;
const FPS = 60;

function check(condition, message) {
  if (!condition) throw new Error(`conformance check failed: ${message}`);
}

// ---------------------------------------------------------------------------------------------
// The GLBs: the armature a wearable carries (Armature to Avatar_Head, Decentraland's 0.01 scale
// and turned frames), with chains under Avatar_Head. Offsets are in the head's space, centimetres,
// +Y up, +Z forward, +X the avatar's left.

// A linear chain: `name` at `t`, then one node per segment (an offset from the previous node),
// named `${name}_1`, `_2`, ... and the last `${name}_tip`.
function strand(name, t, segments) {
  let tree;
  for (let i = segments.length; i >= 1; i--) {
    tree = { name: i === segments.length ? `${name}_tip` : `${name}_${i}`, t: segments[i - 1], children: tree && [tree] };
  }
  return { name, t, children: [tree] };
}

function strandsTrees(segment) {
  const s = segment;
  return [
    strand('SpringBone_hair_left', [7, 8, -2], [[s, 0, 0], [s, 0, 0], [s, 0, 0]]),  // out to the left, level
    strand('hair_springbone_r', [-7, 8, -2], [[-s, -1, 0], [-s, -1, 0]]),            // out to the right
    strand('ponytail_SPRINGBONE', [0, 6, -9], [[0, 0, -7], [0, -2, -6], [0, -4, -5]]), // back, curving down
    strand('springbone_earring_r', [-8, -2, 0], [[0, -4, 0]]),                          // hanging straight down
    strand('SpringBoneCollider', [0, 12, 0], [[0, 0, 8]]),                              // a candidate name
    strand('springbone_bow', [0, 10, 6], [[0, 0, s], [0, 0, s]]),                      // forward, level
    strand('skirt_1', [5, -5, 5], [[0, 0, 6]]),                                         // no token
    strand('Spring_Bone_cape', [-5, -5, -5], [[0, 0, -6]]),                             // no token either
  ];
}

// A root whose first child continues the chain and whose second starts a branch; the first
// branch runs on through a node without the token.
const branchTrees = [{
  name: 'SpringBone_tail', t: [0, 0, -10], children: [
    {
      name: 'SpringBone_tail_a1', t: [0, 0, -6], children: [{
        name: 'SpringBone_tail_a2', t: [0, 0, -6], children: [{
          name: 'tail_bead', t: [0, -2, -5], children: [{ name: 'tail_bead_tip', t: [0, -3, -3] }],
        }],
      }],
    },
    { name: 'SpringBone_tail_b1', t: [4, 0, -4], children: [{ name: 'SpringBone_tail_b1_tip', t: [5, 0, -3] }] },
  ],
}];

function makeGlb(file, trees) {
  const flat = flatten([dclArmature({ full: false, extraChildren: { Avatar_Head: trees } })]);
  const doc = { asset: { version: '2.0', generator: 'springbones scripts/generate/make_conformance.mjs' }, scene: 0, scenes: [{ nodes: [0] }], nodes: flat.nodes };
  return { file, nodes: flat.nodes, parent: flat.parent, bytes: glbOfDoc(doc) };
}

const glbs = {
  strands: makeGlb('strands.glb', strandsTrees(6)),
  strandsFemale: makeGlb('strands_female.glb', strandsTrees(5)),
  branch: makeGlb('branch.glb', branchTrees),
};
for (const g of Object.values(glbs)) g.hash = await hashing.hashV1(g.bytes);
check(new Set(Object.values(glbs).map((g) => g.hash)).size === 3, 'the GLBs have different hashes');

// ---------------------------------------------------------------------------------------------
// Driver motion: the world matrix of the scene root (Armature) per frame, M(t) x its rest matrix.
// Every other avatar node follows from it through its rest local transform.

const ARMATURE_REST = trsMatrix(glbs.strands.nodes[0]);
const armaturePose = (motion) => ({ Armature: mmul(motion, ARMATURE_REST).map(sig) });

// At most 3.3 m/s and 0.05 rad per step at the head, well below the jump thresholds.
const sway = swayMotion({ yaw: 0.4, roll: 0.25 });

// Frames of `dt` seconds each under `motion` (a function of the time at the end of the frame).
function framesOf(motion, dts, extra = () => ({})) {
  let t = 0;
  return dts.map((dt, k) => {
    t += dt;
    return { dt, pose: armaturePose(motion(t, k)), ...extra(k) };
  });
}
const steady = (n, dt = 1 / FPS) => new Array(n).fill(dt);

// ---------------------------------------------------------------------------------------------
// Expected rotations.

const NON_FINITE = { NaN, Infinity, '-Infinity': -Infinity };
// The springBones a runtime is handed: {"$nonFinite": "NaN"} markers become the IEEE values.
function decodeNonFinite(value) {
  if (Array.isArray(value)) return value.map(decodeNonFinite);
  if (value !== null && typeof value === 'object') {
    const keys = Object.keys(value);
    if (keys.length === 1 && keys[0] === '$nonFinite') return NON_FINITE[value.$nonFinite];
    return Object.fromEntries(keys.map((k) => [k, decodeNonFinite(value[k])]));
  }
  return value;
}
const nf = (name) => ({ $nonFinite: name });

// The simulated and resting nodes a case lists: every node of the GLB under Avatar_Head that has
// children (each could be a joint under some reading of the rules).
const listedNodes = (glb) => glb.nodes.map((n, i) => ({ n, i }))
  .filter(({ n, i }) => n.children?.length && !n.name.startsWith('Avatar_') && n.name !== 'Armature' && glb.parent[i] >= 0)
  .map(({ n }) => n.name);

// Runs the reference over the frames: per frame, the steps it ran and every listed node's local
// rotation (its rest rotation when it is no joint). Also returns the jumps carried.
function simulate(glb, springBones, load, instance, frames, nodes) {
  const bones = modelEntry(decodeNonFinite(springBones), modelKey(load, glb.hash));
  const rig = buildRig(glb.nodes, bones);
  const sim = new ReferenceInstance(rig, instance);
  const jointOf = new Map(rig.joints.map((j, i) => [j.name, i]));
  const restOf = (name) => glb.nodes[rig.byName.get(name)].rotation ?? [0, 0, 0, 1];
  const out = frames.map((f) => {
    const world = poseWorld(glb.nodes, glb.parent, f.pose);
    const rotations = sim.frame(f.dt, new Map(rig.drivers.map((d) => [d, world[d]])), f.jump === true);
    return {
      steps: sim.lastSteps,
      rotations: nodes.map((name) => (jointOf.has(name) ? rotations[jointOf.get(name)] : restOf(name))),
    };
  });
  return { frames: out, jumps: sim.jumps, joints: rig.joints.map((j) => j.name) };
}

// The angle between two unit quaternions' rotations. With b on a's side, |a - b| = 2 sin(phi / 2)
// and |a + b| = 2 cos(phi / 2), phi being the angle between them as 4-vectors and 2 phi the
// rotation's: 4 atan2(|a - b|, |a + b|), accurate for small angles where acos of the dot is not.
function angle(a, b) {
  const s = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3] < 0 ? -1 : 1;
  const d = Math.hypot(...a.map((v, i) => v - s * b[i]));
  const p = Math.hypot(...a.map((v, i) => v + s * b[i]));
  return 4 * Math.atan2(d, p);
}
// The largest angle between two runs' rotations of the named nodes.
function largestDifference(a, b, nodes, which) {
  let worst = 0;
  a.frames.forEach((f, k) => which.forEach((name) => {
    const i = nodes.indexOf(name);
    worst = Math.max(worst, angle(f.rotations[i], b.frames[k].rotations[i]));
  }));
  return worst;
}
const restRotation = (glb, name) => glb.nodes.find((n) => n.name === name).rotation ?? [0, 0, 0, 1];
// Whether every listed node stays at its rest rotation (up to the reference's rounding).
const isRest = (run, nodes, glb) => run.frames.every((f) => f.rotations.every((q, i) => angle(q, restRotation(glb, nodes[i])) < 1e-9));
const moves = (run, nodes, name, glb) => {
  const i = nodes.indexOf(name);
  const rest = glb.nodes.find((n) => n.name === name).rotation ?? [0, 0, 0, 1];
  return run.frames.some((f) => angle(f.rotations[i], rest) > 0.01);
};

// Frame boundaries must not be a rounding away from a step: each frame's accumulated time is a
// multiple of the step (within rounding) or clearly between two.
function checkStepBoundaries(name, frames, stepHz = 60, maxSubsteps = 4) {
  const h = 1 / stepHz;
  let acc = 0;
  for (const [k, f] of frames.entries()) {
    acc += f.dt;
    const q = acc / h;
    const frac = Math.abs(q - Math.round(q));
    check(frac < 1e-9 || frac > 1e-3, `${name}: frame ${k} ends ${frac} steps from a step boundary`);
    const crossed = Math.floor((acc + h * 1e-6) / h);
    acc = crossed > maxSubsteps ? 0 : Math.max(0, acc - crossed * h);
  }
}

// ---------------------------------------------------------------------------------------------
// The cases.

const H = glbs.strands.hash;
const SWAY = framesOf(sway, steady(60));
const STILL = framesOf(still, steady(60));
const WALK = framesOf(walk, steady(60));
const entry = (p) => ({ stiffness: 1, gravityPower: 1, gravityDir: [0, -1, 0], drag: 0.4, isRoot: true, ...p });
const single = (bones, hash = H) => ({ version: 1, models: { [hash]: bones } });

const BASE_MALE = 'urn:decentraland:off-chain:base-avatars:BaseMale';
const BASE_FEMALE = 'urn:decentraland:off-chain:base-avatars:BaseFemale';
const STALE = 'bafkreiaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa';  // a hash no file here has
const entity = {
  type: 'wearable',
  content: [
    { file: 'male/hair.glb', hash: glbs.strands.hash },
    { file: 'female/hair.glb', hash: glbs.strandsFemale.hash },
    { file: 'thumbnail.png', hash: glbs.branch.hash },  // another file's hash: never a models key
  ],
  metadata: {
    data: {
      representations: [
        { bodyShapes: [BASE_MALE], mainFile: 'male/hair.glb', contents: ['male/hair.glb'] },
        { bodyShapes: [BASE_FEMALE], mainFile: 'female/hair.glb', contents: ['female/hair.glb'] },
      ],
    },
  },
};
const maleBones = {
  SpringBone_hair_left: entry({ stiffness: 0.3, gravityPower: 1.5, drag: 0.3 }),
  ponytail_SPRINGBONE: entry({ stiffness: 0.3, gravityPower: 1.5, drag: 0.3 }),
};
const femaleBones = {
  SpringBone_hair_left: entry({ stiffness: 3, gravityPower: 0.2, drag: 0.8 }),
  springbone_bow: entry({ stiffness: 0.5, gravityPower: 1, drag: 0.5 }),
};
const bothShapes = { version: 1, models: { [glbs.strands.hash]: maleBones, [glbs.strandsFemale.hash]: femaleBones } };

const cases = [
  {
    name: 'discovery-case-insensitive',
    title: 'A node is a candidate when its name contains "springbone" in any case, anywhere',
    rules: 'SpringBone_hair_left, hair_springbone_r, ponytail_SPRINGBONE and springbone_earring_r are roots and move. ' +
      'skirt_1 and Spring_Bone_cape have entries with isRoot true, but their names lack the token: they stay at rest.',
    glb: glbs.strands, motion: SWAY,
    springBones: single({
      SpringBone_hair_left: entry({}), hair_springbone_r: entry({}), ponytail_SPRINGBONE: entry({}),
      springbone_earring_r: entry({}), skirt_1: entry({}), Spring_Bone_cape: entry({}),
    }),
    warnings: ['bone-not-spring'],
    verify: (run, nodes, g) => {
      for (const n of ['SpringBone_hair_left', 'hair_springbone_r', 'ponytail_SPRINGBONE', 'springbone_earring_r']) check(moves(run, nodes, n, g), `${n} moves`);
      for (const n of ['skirt_1', 'Spring_Bone_cape']) check(!moves(run, nodes, n, g), `${n} rests`);
    },
  },
  {
    name: 'is-root-required',
    title: 'Only a candidate whose entry has isRoot: true starts a chain',
    rules: 'SpringBone_hair_left (isRoot true) moves. hair_springbone_r (isRoot false), ponytail_SPRINGBONE (no isRoot), ' +
      'springbone_earring_r (isRoot null), SpringBoneCollider (isRoot "true", a string) and springbone_bow (no entry) stay at rest.',
    glb: glbs.strands, motion: SWAY,
    springBones: single({
      SpringBone_hair_left: entry({}),
      hair_springbone_r: entry({ isRoot: false }),
      ponytail_SPRINGBONE: (({ isRoot, ...rest }) => rest)(entry({})),
      springbone_earring_r: entry({ isRoot: null }),
      SpringBoneCollider: entry({ isRoot: 'true' }),
    }),
    warnings: ['is-root-not-boolean'],
    verify: (run, nodes, g) => {
      check(moves(run, nodes, 'SpringBone_hair_left', g), 'the root moves');
      for (const n of nodes.filter((x) => !x.startsWith('SpringBone_hair_left'))) check(!moves(run, nodes, n, g), `${n} rests`);
    },
  },
  {
    name: 'branch',
    title: 'A chain with a branch: the first child is the tail, the second starts a branch that is simulated too',
    rules: 'SpringBone_tail aims at its first child SpringBone_tail_a1; SpringBone_tail_b1, its second child, is a joint of the same ' +
      'chain. tail_bead has no token but is a descendant of the root, so it moves with the chain.',
    glb: glbs.branch, motion: SWAY,
    springBones: single({ SpringBone_tail: entry({ stiffness: 0.8 }) }, glbs.branch.hash),
    warnings: [],
    verify: (run, nodes, g) => { for (const n of nodes) check(moves(run, nodes, n, g), `${n} moves`); },
  },
  {
    name: 'member-inheritance',
    title: 'Members take their own entry, else their parent joint\'s parameters and center; missing fields take the defaults',
    rules: 'SpringBone_tail_a1 has its own entry and keeps the root\'s center (its entry has no center key). ' +
      'SpringBone_tail_a2\'s entry gives only stiffness: gravityPower, gravityDir and drag are the defaults (0, [0,-1,0], 0.5), ' +
      'not the parent\'s. tail_bead (no token, no entry) inherits SpringBone_tail_a2\'s values. SpringBone_tail_b1 is marked isRoot ' +
      'inside the chain: it is a member with its own parameters and center null (world space). The tip\'s entry is ignored.',
    glb: glbs.branch, motion: SWAY,
    springBones: single({
      SpringBone_tail: entry({ stiffness: 0.5, gravityPower: 1, drag: 0.4, center: 'Avatar_Hips' }),
      SpringBone_tail_a1: { stiffness: 2, gravityPower: 0.2, gravityDir: [1, -1, 0], drag: 0.8, isRoot: false },
      SpringBone_tail_a2: { stiffness: 1 },
      SpringBone_tail_b1: entry({ stiffness: 0.1, gravityPower: 1.5, drag: 0.2, center: null }),
      SpringBone_tail_b1_tip: entry({ stiffness: 4, gravityPower: 2 }),
    }, glbs.branch.hash),
    warnings: ['nested-root', 'param-missing', 'tip-entry-ignored'],
  },
  {
    name: 'defaults',
    title: 'Missing parameters take the defaults: stiffness 2, gravityPower 0, gravityDir [0,-1,0], drag 0.5',
    rules: 'SpringBone_hair_left has only isRoot; ponytail_SPRINGBONE adds gravityPower 1; springbone_bow adds stiffness 0.5 and gravityPower 0.5.',
    glb: glbs.strands, motion: SWAY,
    springBones: single({
      SpringBone_hair_left: { isRoot: true },
      ponytail_SPRINGBONE: { isRoot: true, gravityPower: 1 },
      springbone_bow: { isRoot: true, stiffness: 0.5, gravityPower: 0.5 },
    }),
    warnings: ['param-missing'],
  },
  {
    name: 'clamp-stiffness',
    title: 'stiffness outside [0, 4] is clamped to the nearest bound',
    rules: 'SpringBone_hair_left: 9 runs as 4. ponytail_SPRINGBONE: -2 runs as 0. springbone_bow: 4, on the bound, as given.',
    glb: glbs.strands, motion: SWAY,
    springBones: single({
      SpringBone_hair_left: entry({ stiffness: 9 }), ponytail_SPRINGBONE: entry({ stiffness: -2 }), springbone_bow: entry({ stiffness: 4 }),
    }),
    warnings: ['param-out-of-range'],
  },
  {
    name: 'clamp-gravity-power',
    title: 'gravityPower outside [0, 2] is clamped to the nearest bound',
    rules: 'SpringBone_hair_left: 7 runs as 2. ponytail_SPRINGBONE: -1 runs as 0. springbone_bow: 2, on the bound, as given.',
    glb: glbs.strands, motion: SWAY,
    springBones: single({
      SpringBone_hair_left: entry({ gravityPower: 7 }), ponytail_SPRINGBONE: entry({ gravityPower: -1 }), springbone_bow: entry({ gravityPower: 2 }),
    }),
    warnings: ['param-out-of-range'],
  },
  {
    name: 'clamp-drag',
    title: 'drag outside [0, 1] is clamped to the nearest bound',
    rules: 'SpringBone_hair_left: 3 runs as 1 (no inertia). ponytail_SPRINGBONE: -1 runs as 0 (no damping). springbone_bow: 1, on the bound, as given.',
    glb: glbs.strands, motion: SWAY,
    springBones: single({
      SpringBone_hair_left: entry({ drag: 3 }), ponytail_SPRINGBONE: entry({ drag: -1 }), springbone_bow: entry({ drag: 1 }),
    }),
    warnings: ['param-out-of-range'],
  },
  {
    name: 'gravity-dir',
    title: 'gravityDir is a world direction, normalized; a zero or unreadable vector is [0,-1,0]',
    rules: 'SpringBone_hair_left [0,-5,0] pulls like [0,-1,0]. ponytail_SPRINGBONE [3,0,4] pulls toward [0.6,0,0.8]. ' +
      'hair_springbone_r [0,20,0] has a component beyond the validator\'s 10 but is only normalized: up. ' +
      'springbone_bow [0,0,0] and springbone_earring_r [1,1,"x"] fall back to [0,-1,0]. The avatar stands still.',
    glb: glbs.strands, motion: STILL,
    springBones: single({
      SpringBone_hair_left: entry({ gravityDir: [0, -5, 0], stiffness: 0.5 }),
      ponytail_SPRINGBONE: entry({ gravityDir: [3, 0, 4], stiffness: 0.5 }),
      hair_springbone_r: entry({ gravityDir: [0, 20, 0], stiffness: 0.5 }),
      springbone_bow: entry({ gravityDir: [0, 0, 0], stiffness: 0.5 }),
      springbone_earring_r: entry({ gravityDir: [1, 1, 'x'], stiffness: 0 }),
    }),
    warnings: ['gravity-dir-zero', 'param-not-vector', 'param-out-of-range'],
  },
  {
    name: 'non-finite-and-non-numeric',
    title: 'A parameter that is not a finite number takes the default; it is never clamped',
    rules: 'SpringBone_hair_left stiffness NaN runs as 2. ponytail_SPRINGBONE gravityPower +Infinity runs as 0 (the default, not the bound 2). ' +
      'springbone_bow drag -Infinity runs as 0.5. hair_springbone_r gravityDir [0, NaN, 1] is [0,-1,0]. springbone_earring_r ' +
      'stiffness "1" (a string), gravityPower null and drag true run as 2, 0 and 0.5. {"$nonFinite": ...} marks the IEEE values.',
    glb: glbs.strands, motion: SWAY,
    springBones: single({
      SpringBone_hair_left: entry({ stiffness: nf('NaN') }),
      ponytail_SPRINGBONE: entry({ gravityPower: nf('Infinity') }),
      springbone_bow: entry({ drag: nf('-Infinity') }),
      hair_springbone_r: entry({ gravityDir: [0, nf('NaN'), 1] }),
      springbone_earring_r: entry({ stiffness: '1', gravityPower: null, drag: true }),
    }),
    // springbones' JavaScript API hands the object over as typed input, NaN and the infinities
    // as numbers: the core names them (param-not-finite), and the string, null and boolean as not
    // numbers.
    warnings: ['param-not-finite', 'param-not-number', 'param-not-vector'],
  },
  {
    name: 'center',
    title: 'With a center, inertia is kept in the center node\'s space',
    rules: 'Every chain has center Avatar_Hips or Avatar_Spine2, and the avatar walks, bobs and turns: in the center\'s space nothing ' +
      'moves, so every joint turns exactly as it does when the avatar stands still (gravity is vertical, and the turn is about the vertical).',
    glb: glbs.strands, motion: WALK,
    springBones: single({
      SpringBone_hair_left: entry({ center: 'Avatar_Hips' }),
      ponytail_SPRINGBONE: entry({ center: 'Avatar_Hips' }),
      springbone_bow: entry({ center: 'Avatar_Spine2', stiffness: 0.3 }),
    }),
    warnings: [],
    verify: (run, nodes, g, c) => {
      const standing = simulate(g, c.springBones, c.load, c.instance, STILL, nodes);
      const d = largestDifference(run, standing, nodes, nodes);
      check(d < 2e-6, `center: walking differs from standing by ${d} rad`);
      check(moves(run, nodes, 'ponytail_SPRINGBONE', g), 'the ponytail moves');
    },
  },
  {
    name: 'center-fallback',
    title: 'A center that is no node, or is a spring bone, falls back to world space; null is world space',
    rules: 'SpringBone_hair_left names Avatar_Tail (no such node), ponytail_SPRINGBONE names SpringBoneCollider (a candidate), ' +
      'springbone_bow names springbone_earring_r_tip (inside a chain), hair_springbone_r has center null: all four run in world space ' +
      'and lag behind the walking avatar. springbone_earring_r\'s center Avatar_Hips resolves.',
    glb: glbs.strands, motion: WALK,
    springBones: single({
      SpringBone_hair_left: entry({ center: 'Avatar_Tail' }),
      ponytail_SPRINGBONE: entry({ center: 'SpringBoneCollider' }),
      springbone_bow: entry({ center: 'springbone_earring_r_tip' }),
      hair_springbone_r: entry({ center: null }),
      springbone_earring_r: entry({ center: 'Avatar_Hips' }),
    }),
    warnings: ['center-is-spring-bone', 'center-not-found'],
    verify: (run, nodes, g, c) => {
      const bones = structuredClone(c.springBones);
      for (const e of Object.values(bones.models[H])) delete e.center;
      const world = simulate(g, bones, c.load, c.instance, WALK, nodes);
      const fallen = nodes.filter((n) => !n.startsWith('springbone_earring_r'));
      const d = largestDifference(run, world, nodes, fallen);
      check(d === 0, `center-fallback: fallen-back chains differ from world space by ${d}`);
      check(largestDifference(run, world, nodes, ['springbone_earring_r']) > 1e-3, 'the resolved center changes the earring');
    },
  },
  {
    name: 'models-key-from-entity-male',
    title: 'The models key is the content hash of the main file of the body shape\'s representation',
    rules: 'The entity\'s BaseMale representation has main file male/hair.glb, this GLB: its hash selects maleBones. ' +
      'The other key (the female GLB\'s) is not used.',
    glb: glbs.strands, motion: SWAY,
    load: { entity, bodyShape: BASE_MALE },
    springBones: bothShapes,
    warnings: [],
    verify: (run, nodes, g) => check(!moves(run, nodes, 'springbone_bow', g) && moves(run, nodes, 'ponytail_SPRINGBONE', g), 'male parameters'),
  },
  {
    name: 'models-key-from-entity-female',
    title: 'The same springBones, loaded for the other body shape (named by the URN\'s last segment)',
    rules: 'BaseFemale wears female/hair.glb, another GLB: its hash selects femaleBones.',
    glb: glbs.strandsFemale, motion: SWAY,
    load: { entity, bodyShape: 'BaseFemale' },
    springBones: bothShapes,
    warnings: [],
    verify: (run, nodes, g) => check(moves(run, nodes, 'springbone_bow', g) && !moves(run, nodes, 'ponytail_SPRINGBONE', g), 'female parameters'),
  },
  {
    name: 'models-key-from-glb-bytes',
    title: 'Without an entity, the models key is the GLB\'s own content hash (CIDv1, as the catalyst computes it)',
    rules: 'The entry under this GLB\'s hash applies; the one under another hash does not.',
    glb: glbs.strands, motion: SWAY, load: {},
    springBones: { version: 1, models: { [glbs.branch.hash]: femaleBones, [H]: maleBones } },
    warnings: [],
    requires: ['content-hash'],
  },
  {
    name: 'stale-hash',
    title: 'No entry under the current main file\'s hash: no spring bones, even if another entry exists',
    rules: 'models has one entry, under a hash no representation uses (left from an earlier upload). Nothing moves.',
    glb: glbs.strands, motion: SWAY,
    load: { entity, bodyShape: BASE_MALE },
    springBones: { version: 1, models: { [STALE]: maleBones } },
    warnings: ['model-not-found'],
  },
  {
    name: 'version-2',
    title: 'version must be exactly 1: otherwise no spring bones',
    rules: 'version 2 with a valid entry: nothing moves.',
    glb: glbs.strands, motion: SWAY,
    springBones: { version: 2, models: { [H]: maleBones } },
    warnings: ['unsupported-version'],
  },
  {
    name: 'version-string',
    title: 'version "1" is a string, not the number 1: no spring bones',
    rules: 'version "1" with a valid entry: nothing moves.',
    glb: glbs.strands, motion: SWAY,
    springBones: { version: '1', models: { [H]: maleBones } },
    warnings: ['unsupported-version'],
  },
  {
    name: 'still-at-rest',
    title: 'Without gravity, a chain under a still avatar stays exactly at rest',
    rules: 'Every candidate is a root with stiffness and drag but gravityPower 0; the avatar stands still for 90 frames.',
    glb: glbs.strands, motion: STILL,
    springBones: single(Object.fromEntries(['SpringBone_hair_left', 'hair_springbone_r', 'ponytail_SPRINGBONE', 'springbone_earring_r',
      'SpringBoneCollider', 'springbone_bow'].map((n) => [n, entry({ gravityPower: 0, stiffness: 1.5 })]))),
    warnings: [],
    source: 'rest',
  },
  {
    name: 'fixed-steps-frame-rates',
    title: 'Fixed 60 Hz steps whatever the frame rate, the drivers interpolated across a frame\'s steps',
    rules: 'Frames of 1/30 s (2 steps), 1/144 s (0 or 1 step), 1/60 s and 0.025 s (1 or 2 steps, the remainder carried) under the sway.',
    glb: glbs.strands, motion: framesOf(sway, [...steady(10, 1 / 30), ...steady(36, 1 / 144), ...steady(10), ...steady(12, 0.025)]),
    springBones: single({ SpringBone_hair_left: entry({}), ponytail_SPRINGBONE: entry({ drag: 0.2 }) }),
    instance: { stepHz: 60, maxSubsteps: 4 },
    warnings: [],
    requires: ['fixed-steps'],
  },
  {
    name: 'substep-cap-hitch',
    title: 'A frame longer than maxSubsteps steps runs that many and drops the rest of its time',
    rules: 'A 0.5 s hitch at frame 20 (30 steps of time) runs 4 steps, the drivers interpolated in quarters of the frame, and the ' +
      'accumulator starts again from 0; a 0.1 s frame at frame 40 runs 4 of its 6 steps.',
    glb: glbs.strands,
    motion: framesOf(sway, [...steady(20), 0.5, ...steady(19), 0.1, ...steady(19)]),
    springBones: single({ SpringBone_hair_left: entry({}), ponytail_SPRINGBONE: entry({ drag: 0.2 }) }),
    instance: { stepHz: 60, maxSubsteps: 4 },
    warnings: [],
    requires: ['fixed-steps'],
    verify: (run) => check(run.frames[20].steps === 4 && run.frames[40].steps === 4, 'capped at 4 steps'),
  },
  {
    name: 'jump-teleport',
    title: 'A driver moving farther than jumpDistance per step is a jump: the chains are carried across it',
    rules: 'The avatar stands still while its chains fall under gravity, then at frame 30 is moved 1.8 m and turned half a turn about ' +
      'the vertical in one frame. The chains keep their shape and motion relative to the avatar: every frame turns exactly as when ' +
      'the avatar never moved.',
    glb: glbs.strands,
    motion: framesOf((t, k) => (k < 30 ? still() : trsMatrix({ translation: [1.5, 0, 1], rotation: qaxis([0, 1, 0], Math.PI) })), steady(60)),
    springBones: single({ SpringBone_hair_left: entry({ stiffness: 0.5 }), ponytail_SPRINGBONE: entry({ stiffness: 0.3 }), springbone_bow: entry({}) }),
    instance: { jumpDistance: 0.5, jumpAngle: 0.5 },
    warnings: [],
    jumps: 1,
    requires: ['jumps'],
    verify: (run, nodes, g, c) => {
      const standing = simulate(g, c.springBones, c.load, c.instance, framesOf(still, steady(60)), nodes);
      const d = largestDifference(run, standing, nodes, nodes);
      check(d < 2e-6, `jump-teleport: differs from standing by ${d}`);
    },
  },
  {
    name: 'jump-explicit',
    title: 'A jump asked for by the caller (jump()) is carried like a detected one',
    rules: 'At frame 30 the avatar moves 0.2 m and turns 0.3 rad about the vertical, below both thresholds, and the frame says ' +
      '"jump": true: every frame turns exactly as when the avatar never moved.',
    glb: glbs.strands,
    motion: framesOf((t, k) => (k < 30 ? still() : trsMatrix({ translation: [0.2, 0, 0], rotation: qaxis([0, 1, 0], 0.3) })), steady(60),
      (k) => (k === 30 ? { jump: true } : {})),
    springBones: single({ SpringBone_hair_left: entry({ stiffness: 0.5 }), ponytail_SPRINGBONE: entry({ stiffness: 0.3 }), springbone_bow: entry({}) }),
    instance: { jumpDistance: 0.5, jumpAngle: 0.5 },
    warnings: [],
    jumps: 1,
    requires: ['jumps'],
    verify: (run, nodes, g, c) => {
      const standing = simulate(g, c.springBones, c.load, c.instance, framesOf(still, steady(60)), nodes);
      const d = largestDifference(run, standing, nodes, nodes);
      check(d < 2e-6, `jump-explicit: differs from standing by ${d}`);
      const noJump = simulate(g, c.springBones, c.load, c.instance, c.motion.map(({ jump, ...f }) => f), nodes);
      check(largestDifference(run, noJump, nodes, nodes) > 1e-3, 'without jump() the chains swing');
    },
  },
];

// ---------------------------------------------------------------------------------------------
// Writing.

// One case as JSON text: the header indented, one frame per line.
function caseText(c) {
  const { frames, ...head } = c;
  const text = JSON.stringify(head, null, 2);
  const lines = frames.map((f) => `    ${JSON.stringify(f)}`).join(',\n');
  return `${text.slice(0, -2)},\n  "frames": [\n${lines}\n  ]\n}\n`;
}

rmSync(join(outDir, 'cases'), { recursive: true, force: true });
rmSync(join(outDir, 'glb'), { recursive: true, force: true });
mkdirSync(join(outDir, 'cases'), { recursive: true });
mkdirSync(join(outDir, 'glb'), { recursive: true });
for (const g of Object.values(glbs)) writeFileSync(join(outDir, 'glb', g.file), g.bytes);

const summary = [];
cases.forEach((spec, index) => {
  const load = spec.load ?? { contentHash: spec.glb.hash };
  const instance = { integrator: 'vrm', stepHz: 60, maxSubsteps: 4, jumpDistance: 0.5, jumpAngle: 0.5, ...spec.instance };
  const nodes = listedNodes(spec.glb);
  checkStepBoundaries(spec.name, spec.motion, instance.stepHz, instance.maxSubsteps);
  const run = simulate(spec.glb, spec.springBones, load, instance, spec.motion, nodes);
  const source = spec.source ?? (isRest(run, nodes, spec.glb) ? 'rest' : 'reference');
  if (source === 'rest') {
    // The expectation is then the GLB's own rest rotations, exactly; the reference agrees.
    check(isRest(run, nodes, spec.glb), `${spec.name}: the reference keeps every node at rest`);
    for (const f of run.frames) f.rotations = nodes.map((n) => restRotation(spec.glb, n));
  } else check(nodes.some((n) => moves(run, nodes, n, spec.glb)), `${spec.name}: something moves`);
  spec.verify?.(run, nodes, spec.glb, { ...spec, load, instance });
  const c = {
    format: FORMAT,
    name: spec.name,
    title: spec.title,
    rules: spec.rules,
    requires: spec.requires ?? [],
    glb: `../glb/${spec.glb.file}`,
    load,
    springBones: spec.springBones,
    instance,
    source,
    tolerance: TOLERANCE,
    nodes,
    springbones: { joints: [...run.joints].sort(), warnings: [...spec.warnings].sort(), jumps: spec.jumps ?? 0 },
    frames: spec.motion.map((f, k) => ({
      dt: f.dt,
      ...(f.jump ? { jump: true } : {}),
      pose: f.pose,
      steps: run.frames[k].steps,
      rotations: run.frames[k].rotations.map((q) => q.map((v) => round(v, 9))),
    })),
  };
  const file = `${String(index + 1).padStart(2, '0')}-${spec.name}.json`;
  writeFileSync(join(outDir, 'cases', file), caseText(c));
  summary.push(`${file}: ${source}, ${c.frames.length} frames, ${run.joints.length} joints`);
});
console.log(summary.join('\n'));
