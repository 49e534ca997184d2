// Writes the VRM part of the conformance pack: conformance/vrm/models/*.vrm and
// conformance/vrm/cases/*.json (conformance/README.md describes the format; conformance/run.mjs
// replays it on springbones, conformance/run_three_vrm.mjs the cases without limits on three-vrm).
//
//   node scripts/generate/make_conformance_vrm.mjs [--out <dir>]
//
// --out writes the part elsewhere (default: conformance/vrm/). Deterministic: running it again
// rewrites the same bytes.
//
// Every expected rotation comes from scripts/lib/vrm_reference.mjs, a second implementation of
// docs/semantics.md's VRM rules in doubles that shares no code with springbones. Where a case's
// answer follows from another run (a center moving rigidly with the chain, a limit that must be
// ignored, a rotation that only differs in length), the reference is checked against it here before
// anything is written, and every case checks that what it is about happened (a collider pushed, a
// limit moved a tail).
import { mkdirSync, rmSync, writeFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { glbOfDoc } from '../lib/fixtures/glb.mjs';
import { sig, still, swayMotion, walk } from '../lib/fixtures/motions.mjs';
import { qaxis, round } from '../lib/fixtures/vec.mjs';
import { poseWorld } from '../lib/adr_reference.mjs';
import { VrmReferenceInstance, buildVrmRig } from '../lib/vrm_reference.mjs';

const root = join(dirname(fileURLToPath(import.meta.url)), '..', '..');
const outFlag = process.argv.indexOf('--out');
const outDir = outFlag >= 0 ? process.argv[outFlag + 1] : join(root, 'conformance', 'vrm');
if (!outDir) throw new Error('--out needs a folder');

const FORMAT = 'springbones-conformance/1';
const TOLERANCE = 3e-5;  // as the ADR cases (conformance/README.md, "Tolerance")
const FPS = 60;

function check(condition, message) {
  if (!condition) throw new Error(`conformance check failed: ${message}`);
}

// ---------------------------------------------------------------------------------------------
// The models: a Root (the scene root the frames move), a Body 1 m above it, and strands hanging
// from the Body, each a spring of three joints and a tail. Metres, glTF axes (+Y up).

const SEGMENT = [0.03, -0.1, 0.02];  // a little off the vertical, so no push is along the bone

/** A strand of `n` segments under Body at `t`: node specs named `${name}_0` .. `${name}_${n}`. */
function strand(name, t, n = 3, segment = SEGMENT) {
  return Array.from({ length: n + 1 }, (_, i) => ({ name: `${name}_${i}`, t: i === 0 ? t : segment }));
}

/**
 * A VRM document: `strands` (arrays from strand()), extra nodes under Body ({name, t}), and the
 * VRMC_springBone extension built by `springBone(index)`, where index maps node names to indices.
 */
function model(strands, extra, springBone) {
  const nodes = [{ name: 'Root', children: [1] }, { name: 'Body', translation: [0, 1, 0], children: [] }];
  const index = new Map([['Root', 0], ['Body', 1]]);
  for (const e of extra) {
    index.set(e.name, nodes.length);
    nodes[1].children.push(nodes.length);
    nodes.push({ name: e.name, translation: e.t, ...(e.rotation ? { rotation: e.rotation } : {}) });
  }
  for (const s of strands) {
    s.forEach((spec, i) => {
      const at = nodes.length;
      index.set(spec.name, at);
      if (i === 0) nodes[1].children.push(at);
      else nodes[at - 1].children = [at];
      nodes.push({ name: spec.name, translation: spec.t });
    });
  }
  for (const n of nodes) if (n.children?.length === 0) delete n.children;
  const extension = springBone((name) => {
    check(index.has(name), `node ${name}`);
    return index.get(name);
  });
  const used = ['VRMC_springBone'];
  const text = JSON.stringify(extension);
  if (text.includes('VRMC_springBone_extended_collider')) used.push('VRMC_springBone_extended_collider');
  if (text.includes('VRMC_springBone_limit')) used.push('VRMC_springBone_limit');
  return {
    asset: { version: '2.0', generator: 'springbones scripts/generate/make_conformance_vrm.mjs' },
    extensionsUsed: used,
    scene: 0, scenes: [{ nodes: [0] }], nodes,
    extensions: { VRMC_springBone: { specVersion: '1.0', ...extension } },
  };
}

const params = (p = {}) => ({ stiffness: 1, gravityPower: 1, gravityDir: [0, -1, 0], dragForce: 0.4, hitRadius: 0.02, ...p });
/** A spring over a strand's nodes: every joint takes `p`, `limits[i]` (if any) goes on joint i. */
function spring(node, name, s, { p = {}, colliderGroups, center, limits = {} } = {}) {
  return {
    name,
    joints: s.map((spec, i) => ({
      node: node(spec.name), ...params(p),
      ...(limits[i] ? { extensions: { VRMC_springBone_limit: limits[i] } } : {}),
    })),
    ...(colliderGroups ? { colliderGroups } : {}),
    ...(center !== undefined ? { center } : {}),
  };
}
const limitExt = (limit, specVersion = '1.0-draft') => ({ specVersion, limit });

// ---------------------------------------------------------------------------------------------
// Driver motion: the Root's world matrix per frame.

const rootPose = (m) => ({ Root: m.map(sig) });
const sway = swayMotion({ yaw: 0.5, roll: 0.3 });
const framesOf = (motion, n = 90) => Array.from({ length: n }, (_, k) => ({ dt: 1 / FPS, pose: rootPose(motion((k + 1) / FPS)) }));
const SWAY = framesOf(sway);
const STILL = framesOf(still);
const WALK = framesOf(walk);

// ---------------------------------------------------------------------------------------------

function nodesOf(doc) {
  const parent = new Array(doc.nodes.length).fill(-1);
  doc.nodes.forEach((n, i) => (n.children ?? []).forEach((c) => { parent[c] = i; }));
  return parent;
}

/** The reference's run of a document: rotations of `listed` per frame, and what it did. */
function simulate(doc, frames, listed) {
  const rig = buildVrmRig(doc);
  const parent = nodesOf(doc);
  const sim = new VrmReferenceInstance(rig, { stepHz: FPS, maxSubsteps: 4 });
  const jointOf = new Map(rig.joints.map((j, i) => [j.name, i]));
  const out = frames.map((f) => {
    const world = poseWorld(doc.nodes, parent, f.pose);
    const rotations = sim.frame(f.dt, new Map(rig.drivers.map((d) => [d, world[d]])));
    return { steps: sim.lastSteps, rotations: listed.map((name) => rotations[jointOf.get(name)]) };
  });
  return { frames: out, pushes: sim.pushes, limited: sim.limited, joints: rig.joints.map((j) => j.name) };
}

function angle(a, b) {
  const s = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3] < 0 ? -1 : 1;
  return 4 * Math.atan2(Math.hypot(...a.map((v, i) => v - s * b[i])), Math.hypot(...a.map((v, i) => v + s * b[i])));
}
const largestDifference = (a, b) => Math.max(...a.frames.flatMap((f, k) => f.rotations.map((q, i) => angle(q, b.frames[k].rotations[i]))));
const moves = (run) => run.frames.some((f) => f.rotations.some((q) => angle(q, [0, 0, 0, 1]) > 0.01));
const withoutLimits = (doc) => {
  const copy = structuredClone(doc);
  for (const s of copy.extensions.VRMC_springBone.springs) for (const j of s.joints) delete j.extensions;
  copy.extensionsUsed = copy.extensionsUsed.filter((e) => e !== 'VRMC_springBone_limit');
  return copy;
};

// ---------------------------------------------------------------------------------------------
// The cases. `limits: true` marks cases three-vrm 3.5.5 cannot run (it reads no limits).

const A = strand('HairA', [0.1, 0.45, 0]);
const B = strand('HairB', [-0.1, 0.45, 0]);
const DOWN = [0, -0.1, 0];  // a strand hanging exactly down: the singular directions
const sphere = (node, offset, radius) => ({ node, shape: { sphere: { offset, radius } } });
const capsule = (node, offset, tail, radius) => ({ node, shape: { capsule: { offset, tail, radius } } });
const extended = (base, shape) => ({ ...base, extensions: { VRMC_springBone_extended_collider: { specVersion: '1.0', shape } } });
const H = Math.SQRT1_2;

const cases = [
  {
    name: 'sphere-and-capsule',
    title: 'Sphere and capsule colliders push the tails out, each push followed by the bone length',
    rules: 'HairA tests a sphere on Body beside its lower joints; HairB a capsule across its path. hitRadius 0.02 m. The avatar sways.',
    doc: model([A, B], [], (n) => ({
      colliders: [sphere(n('Body'), [0.2, 0.2, 0], 0.05), capsule(n('Body'), [-0.18, 0.25, -0.1], [-0.18, 0.25, 0.1], 0.04)],
      colliderGroups: [{ name: 'sphere', colliders: [0] }, { name: 'capsule', colliders: [1] }],
      springs: [spring(n, 'A', A, { colliderGroups: [0] }), spring(n, 'B', B, { colliderGroups: [1] })],
    })),
    motion: SWAY, warnings: [],
    verify: (run) => check(run.pushes > 20, `colliders push (${run.pushes})`),
  },
  {
    name: 'extended-plane',
    title: 'VRMC_springBone_extended_collider: a plane keeps the tails hitRadius above it, on its normal\'s side',
    rules: 'A plane on Body through [0, 0.2, 0] with normal [0.2, 1, 0.1] (made unit), in place of a base sphere; HairA and HairB ' +
      'hang through it at rest and are pushed up onto it.',
    doc: model([A, B], [], (n) => ({
      colliders: [extended(sphere(n('Body'), [0, -5, 0], 0.01), { plane: { offset: [0, 0.2, 0], normal: [0.2, 1, 0.1] } })],
      colliderGroups: [{ colliders: [0] }],
      springs: [spring(n, 'A', A, { colliderGroups: [0] }), spring(n, 'B', B, { colliderGroups: [0] })],
    })),
    motion: SWAY, warnings: [],
    verify: (run) => check(run.pushes > 20, `the plane pushes (${run.pushes})`),
  },
  {
    name: 'extended-inside',
    title: 'VRMC_springBone_extended_collider: inside sphere and inside capsule keep the tails within radius - hitRadius',
    rules: 'HairA lives in an inside sphere (radius 0.22 m) around its root, HairB in an inside capsule (radius 0.17 m) along its ' +
      'upper half: the tails are pulled toward the shapes\' centers whenever they swing out.',
    doc: model([A, B], [], (n) => ({
      colliders: [
        extended(sphere(n('Body'), [0.1, 0.4, 0], 0.3), { sphere: { offset: [0.1, 0.4, 0], radius: 0.22, inside: true } }),
        extended(sphere(n('Body'), [-0.1, 0.4, 0], 0.3), { capsule: { offset: [-0.1, 0.45, 0], tail: [-0.08, 0.3, 0], radius: 0.17, inside: true } }),
      ],
      colliderGroups: [{ colliders: [0] }, { colliders: [1] }],
      springs: [spring(n, 'A', A, { colliderGroups: [0], p: { gravityPower: 2 } }), spring(n, 'B', B, { colliderGroups: [1], p: { gravityPower: 2 } })],
    })),
    motion: SWAY, warnings: [],
    verify: (run) => check(run.pushes > 20, `the inside shapes pull (${run.pushes})`),
  },
  {
    name: 'center',
    title: 'A spring\'s center: inertia is kept in the center node\'s space',
    rules: 'Both springs have center Body while the avatar walks, bobs and turns about the vertical: in the center\'s space nothing ' +
      'moves, so every joint turns exactly as when the avatar stands still.',
    doc: model([A, B], [], (n) => ({
      springs: [spring(n, 'A', A, { center: n('Body') }), spring(n, 'B', B, { center: n('Body'), p: { stiffness: 0.3 } })],
    })),
    motion: WALK, warnings: [],
    verify: (run, c, listed) => {
      const standing = simulate(c.doc, STILL, listed);
      const d = largestDifference(run, standing);
      check(d < 2e-6, `center: walking differs from standing by ${d}`);
      check(moves(run), 'the strands move');
    },
  },
  {
    name: 'collider-in-two-groups',
    title: 'A collider listed by two of a spring\'s collider groups is tested, and pushes, once per group',
    rules: 'Collider 0 (a sphere) is in groups 0 and 1, and spring A lists both: it pushes HairA twice per step. Spring B lists group 1 ' +
      'only, with the same sphere and a capsule.',
    doc: model([A, B], [], (n) => ({
      colliders: [sphere(n('Body'), [0.18, 0.25, 0], 0.06), capsule(n('Body'), [-0.18, 0.25, -0.1], [-0.18, 0.25, 0.1], 0.04)],
      colliderGroups: [{ colliders: [0] }, { colliders: [0, 1] }],
      springs: [spring(n, 'A', A, { colliderGroups: [0, 1] }), spring(n, 'B', B, { colliderGroups: [1] })],
    })),
    motion: SWAY, warnings: ['vrm-collider-repeated'],
    verify: (run, c, listed) => {
      const once = structuredClone(c.doc);
      once.extensions.VRMC_springBone.springs[0].colliderGroups = [1];
      const d = largestDifference(run, simulate(once, SWAY, listed));
      check(d > 1e-3, `the second push moves HairA (${d})`);
    },
  },
  {
    name: 'limit-cone',
    title: 'VRMC_springBone_limit cone, turned by its rotation: the bone stays within angle of the limit\'s +Y',
    rules: 'HairA\'s joints have a cone of 0.25 rad turned 0.4 rad about Z; HairB\'s first joint a cone of 0.1 rad, pulled sideways by a gravityDir ' +
      'of length 1.41 (folded into gravityPower). Directions outside go to the cone\'s boundary at the same azimuth.',
    doc: model([A, B], [], (n) => ({
      springs: [
        spring(n, 'A', A, { limits: { 0: limitExt({ cone: { angle: 0.25, rotation: qaxis([0, 0, 1], 0.4) } }), 1: limitExt({ cone: { angle: 0.25 } }) } }),
        spring(n, 'B', B, { p: { stiffness: 0.2, gravityDir: [1, -1, 0] }, limits: { 0: limitExt({ cone: { angle: 0.1 } }) } }),
      ],
    })),
    motion: SWAY, warnings: ['vrm-gravity-dir-scaled'], limits: true,
    verify: (run) => check(run.limited > 20, `the cone moves tails (${run.limited})`),
  },
  {
    name: 'limit-hinge',
    title: 'VRMC_springBone_limit hinge: the bone stays in the limit\'s YZ plane, within angle of +Y',
    rules: 'HairA\'s joints have a hinge of 0.5 rad turned a quarter turn about Y (the plane is the avatar\'s XY plane); HairB\'s first ' +
      'joint a hinge of 0.2 rad, unturned.',
    doc: model([A, B], [], (n) => ({
      springs: [
        spring(n, 'A', A, { limits: { 0: limitExt({ hinge: { angle: 0.5, rotation: [0, H, 0, H] } }), 1: limitExt({ hinge: { angle: 0.5, rotation: [0, H, 0, H] } }) } }),
        spring(n, 'B', B, { p: { stiffness: 0.3 }, limits: { 0: limitExt({ hinge: { angle: 0.2 } }) } }),
      ],
    })),
    motion: SWAY, warnings: [], limits: true,
    verify: (run) => check(run.limited > 20, `the hinge moves tails (${run.limited})`),
  },
  {
    name: 'limit-spherical',
    title: 'VRMC_springBone_limit spherical: pitch about the limit\'s X and yaw toward X bounded apart',
    rules: 'HairA\'s joints: pitch 0.3, yaw 0.15; HairB\'s first joint: pitch 0.8, yaw 0.05, turned 0.3 rad about Y. Each angle is ' +
      'clamped on its own and the direction rebuilt from the two.',
    doc: model([A, B], [], (n) => ({
      springs: [
        spring(n, 'A', A, { limits: { 0: limitExt({ spherical: { pitch: 0.3, yaw: 0.15 } }), 1: limitExt({ spherical: { pitch: 0.3, yaw: 0.15 } }) } }),
        spring(n, 'B', B, { p: { stiffness: 0.3 }, limits: { 0: limitExt({ spherical: { pitch: 0.8, yaw: 0.05, rotation: qaxis([0, 1, 0], 0.3) } }) } }),
      ],
    })),
    motion: SWAY, warnings: [], limits: true,
    verify: (run) => check(run.limited > 20, `the spherical limit moves tails (${run.limited})`),
  },
  {
    name: 'limit-singular-directions',
    title: 'The singular directions: cone at -Y, hinge at +-X, spherical at +-X',
    rules: 'Three strands hang exactly down under a still avatar with gravity along them. HairA\'s cone (0.4 rad) is turned half a ' +
      'turn about X, so the bone points at its -Y: it goes to the boundary on the +Z side. HairB\'s hinge (0.6 rad) and HairC\'s ' +
      'spherical limit (pitch 0.5, yaw 0.3) are turned a quarter turn about Z, so the bone points at their +X: the hinge takes +Y, the ' +
      'spherical limit pitch 0 and its yaw bound.',
    doc: (() => {
      const a = strand('HairA', [0.1, 0.45, 0], 3, DOWN);
      const b = strand('HairB', [-0.1, 0.45, 0], 3, DOWN);
      const c = strand('HairC', [0, 0.45, -0.1], 3, DOWN);
      const quarterZ = qaxis([0, 0, 1], Math.PI / 2);
      return model([a, b, c], [], (n) => ({
        springs: [
          spring(n, 'A', a, { limits: { 0: limitExt({ cone: { angle: 0.4, rotation: [1, 0, 0, 0] } }) } }),
          spring(n, 'B', b, { limits: { 0: limitExt({ hinge: { angle: 0.6, rotation: quarterZ } }) } }),
          spring(n, 'C', c, { limits: { 0: limitExt({ spherical: { pitch: 0.5, yaw: 0.3, rotation: quarterZ } }) } }),
        ],
      }));
    })(),
    motion: STILL, warnings: [], limits: true,
    verify: (run) => check(run.limited >= 3 && moves(run), `the singular directions are limited (${run.limited})`),
  },
  {
    name: 'limit-spec-versions',
    title: 'specVersion "1.0-draft" and "1.0" are both read (UniVRM #2828: the draft becomes 1.0 when ratified)',
    rules: 'HairA\'s first joint has a cone of 0.2 rad under specVersion "1.0-draft", HairB\'s the same under "1.0": both apply.',
    doc: model([A, B], [], (n) => ({
      springs: [
        spring(n, 'A', A, { limits: { 0: limitExt({ cone: { angle: 0.2 } }, '1.0-draft') } }),
        spring(n, 'B', B, { limits: { 0: limitExt({ cone: { angle: 0.2 } }, '1.0') } }),
      ],
    })),
    motion: SWAY, warnings: [], limits: true,
    verify: (run, c, listed) => {
      check(run.limited > 20, `both limits act (${run.limited})`);
      check(largestDifference(run, simulate(withoutLimits(c.doc), SWAY, listed)) > 1e-2, 'the limits change the motion');
    },
  },
  {
    name: 'limit-unknown-version',
    title: 'A limit under an unknown specVersion, or none, is ignored (UniVRM #2828)',
    rules: 'HairA\'s first joint has a cone of 0.2 rad under specVersion "2.0", HairB\'s under no specVersion: both move as if unlimited.',
    doc: model([A, B], [], (n) => ({
      springs: [
        spring(n, 'A', A, { limits: { 0: limitExt({ cone: { angle: 0.2 } }, '2.0') } }),
        spring(n, 'B', B, { limits: { 0: { limit: { cone: { angle: 0.2 } } } } }),
      ],
    })),
    motion: SWAY, warnings: ['limit-spec-version'], limits: true, ignoredLimits: true,
  },
  {
    name: 'limit-no-shape',
    title: 'A limit extension without a limit, or a limit with none of cone, hinge and spherical, is ignored (UniVRM #2828)',
    rules: 'HairA\'s first joint has VRMC_springBone_limit without "limit"; HairB\'s has "limit": {}: both move as if unlimited.',
    doc: model([A, B], [], (n) => ({
      springs: [
        spring(n, 'A', A, { limits: { 0: { specVersion: '1.0-draft' } } }),
        spring(n, 'B', B, { limits: { 0: limitExt({}) } }),
      ],
    })),
    motion: SWAY, warnings: ['limit-invalid'], limits: true, ignoredLimits: true,
  },
  {
    name: 'limit-two-shapes',
    title: 'A limit with two shapes is ignored, not read as either (UniVRM #2828)',
    rules: 'HairA\'s first joint has a limit with a cone of 0.1 rad and a hinge of 0.1 rad: it moves as if unlimited. (three-vrm\'s ' +
      'pull request #1632 would use the cone.)',
    doc: model([A], [], (n) => ({
      springs: [spring(n, 'A', A, { limits: { 0: limitExt({ cone: { angle: 0.1 }, hinge: { angle: 0.1 } }) } })],
    })),
    motion: SWAY, warnings: ['limit-invalid'], limits: true, ignoredLimits: true,
    verify: (run, c, listed) => {
      const cone = structuredClone(c.doc);
      delete cone.extensions.VRMC_springBone.springs[0].joints[0].extensions.VRMC_springBone_limit.limit.hinge;
      check(largestDifference(run, simulate(cone, SWAY, listed)) > 1e-2, 'reading the cone would differ');
    },
  },
  {
    name: 'limit-on-last-joint',
    title: 'A limit on a spring\'s last joint, which is only a tail, is ignored (UniVRM #2828)',
    rules: 'HairA_3, the last joint of spring A, has a cone of 0.1 rad: nothing changes.',
    doc: model([A], [], (n) => ({
      springs: [spring(n, 'A', A, { limits: { 3: limitExt({ cone: { angle: 0.1 } }) } })],
    })),
    motion: SWAY, warnings: ['limit-on-end-joint'], limits: true, ignoredLimits: true,
  },
  {
    name: 'limit-rotation-length',
    title: 'A limit rotation of any finite length is made unit: [1e20, 0, 0, 1e20] and [1e-25, 0, 0, 1e-25] are half a turn about X',
    rules: 'HairA\'s first joint has a cone of 0.3 rad with rotation [0, 0, 1e20, 1e20] (a quarter turn about Z), HairB\'s a hinge of ' +
      '0.3 rad with [1e-25, 0, 0, 1e-25] (a quarter turn about X): each moves exactly as with the unit quaternion.',
    doc: model([A, B], [], (n) => ({
      springs: [
        spring(n, 'A', A, { limits: { 0: limitExt({ cone: { angle: 0.3, rotation: [0, 0, 1e20, 1e20] } }) } }),
        spring(n, 'B', B, { limits: { 0: limitExt({ hinge: { angle: 0.3, rotation: [1e-25, 0, 0, 1e-25] } }) } }),
      ],
    })),
    motion: SWAY, warnings: ['limit-rotation-invalid'], limits: true,
    verify: (run, c, listed) => {
      const unit = structuredClone(c.doc);
      const [a, b] = unit.extensions.VRMC_springBone.springs;
      a.joints[0].extensions.VRMC_springBone_limit.limit.cone.rotation = [0, 0, H, H];
      b.joints[0].extensions.VRMC_springBone_limit.limit.hinge.rotation = [H, 0, 0, H];
      const d = largestDifference(run, simulate(unit, SWAY, listed));
      check(d < 1e-12, `the long and short rotations move as the unit ones (${d})`);
      check(run.limited > 20, `the limits act (${run.limited})`);
    },
  },
];

// ---------------------------------------------------------------------------------------------
// Writing.

function caseText(c) {
  const { frames, ...head } = c;
  const text = JSON.stringify(head, null, 2);
  const lines = frames.map((f) => `    ${JSON.stringify(f)}`).join(',\n');
  return `${text.slice(0, -2)},\n  "frames": [\n${lines}\n  ]\n}\n`;
}

rmSync(join(outDir, 'cases'), { recursive: true, force: true });
rmSync(join(outDir, 'models'), { recursive: true, force: true });
mkdirSync(join(outDir, 'cases'), { recursive: true });
mkdirSync(join(outDir, 'models'), { recursive: true });

const summary = [];
cases.forEach((spec, index) => {
  const file = `${String(index + 1).padStart(2, '0')}-${spec.name}`;
  const listed = buildVrmRig(spec.doc).joints.map((j) => j.name);
  const run = simulate(spec.doc, spec.motion, listed);
  check(moves(run), `${spec.name}: something moves`);
  if (spec.ignoredLimits) {
    const unlimited = simulate(withoutLimits(spec.doc), spec.motion, listed);
    const d = largestDifference(run, unlimited);
    check(d === 0, `${spec.name}: the ignored limits change the motion by ${d}`);
  }
  spec.verify?.(run, spec, listed);
  writeFileSync(join(outDir, 'models', `${file}.vrm`), glbOfDoc(spec.doc));
  const c = {
    format: FORMAT,
    name: `vrm-${spec.name}`,
    title: spec.title,
    rules: spec.rules,
    requires: ['vrm', ...(spec.limits ? ['vrm-limits'] : [])],
    glb: `../models/${file}.vrm`,
    load: { vrm: true },
    instance: { integrator: 'vrm', stepHz: FPS, maxSubsteps: 4, jumpDistance: 0.5, jumpAngle: 0.5 },
    source: 'reference',
    tolerance: TOLERANCE,
    nodes: listed,
    springbones: { joints: [...run.joints].sort(), warnings: [...spec.warnings].sort(), jumps: 0 },
    frames: spec.motion.map((f, k) => ({
      dt: f.dt,
      pose: f.pose,
      steps: run.frames[k].steps,
      rotations: run.frames[k].rotations.map((q) => q.map((v) => round(v, 9))),
    })),
  };
  writeFileSync(join(outDir, 'cases', `${file}.json`), caseText(c));
  summary.push(`${file}: ${c.frames.length} frames, ${run.joints.length} joints, ${run.pushes} pushes, ${run.limited} limited`);
});
console.log(summary.join('\n'));
