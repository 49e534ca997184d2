// Writes three small VRM spring-bone test models into tests/fixtures/:
//
//   vrm10_springs.vrm  VRMC_springBone 1.0: two springs (back hair in world space, a skirt panel
//                      with its center on the hips), sphere and capsule colliders in three groups,
//                      per-joint parameters that change along each spring, rotated rest poses, one
//                      joint with a non-unit gravityDir.
//   vrm0_springs.vrm   VRM 0.x extensions.VRM.secondaryAnimation: two bone groups (hair with two
//                      roots, one of them branching and with leaves that get virtual tails; a tail
//                      with its center on the hips), two collider groups of spheres whose offsets
//                      have non-zero z (VRM 0.x stores them in Unity's axes).
//   vrm10_extended_colliders.vrm  VRMC_springBone 1.0 with VRMC_springBone_extended_collider: a
//                      plane, an inside sphere and an inside capsule (each with the base shape
//                      the extension asks for), and an extension of an unknown version whose base
//                      sphere applies.
//
//   node scripts/generate/make_vrm_fixtures.mjs
//
// Node 20, no npm packages. Deterministic (literal numbers only, no trigonometry). The files are
// GLB with a JSON chunk only: a node hierarchy and the spring-bone extension, no meshes, no
// VRMC_vrm / humanoid data, so they are test models, not complete avatars. Every node is made up
// here; nothing is copied from a third-party model. scripts/generate/make_vrm_trajectories.mjs runs them in
// @pixiv/three-vrm-springbone 3.5.5 and tests/native/vrm_loader_test.cpp loads them.
//
// Values are chosen where springbones and three-vrm 3.5.5 agree by design (docs/semantics.md,
// "VRM avatars"): every parameter written out (three-vrm's dragForce default is 0.4,
// ours the spec's 0.5), collider nodes at scale 1 (three-vrm does not scale radii), VRM 0.x
// gravityDir with z = 0 (three-vrm does not convert its axes, we negate z as for offsets), no
// skipped nodes between VRMC_springBone joints (three-vrm reads a grandchild's own translation).
import { mkdirSync, writeFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { glbOfDoc } from '../lib/fixtures/glb.mjs';

const outDir = join(dirname(fileURLToPath(import.meta.url)), '..', '..', 'tests', 'fixtures');

// Nodes are given as [name, parentName, translation, rotation?]; indices follow list order.
function buildNodes(list) {
  const index = new Map(list.map(([name], i) => [name, i]));
  const nodes = list.map(([name, , translation, rotation]) => {
    const node = { name };
    if (translation) node.translation = translation;
    if (rotation) node.rotation = rotation;
    return node;
  });
  list.forEach(([name, parent]) => {
    if (parent === null) return;
    const p = nodes[index.get(parent)];
    (p.children ??= []).push(index.get(name));
  });
  const roots = list.map(([, parent], i) => (parent === null ? i : -1)).filter((i) => i >= 0);
  return { nodes, index, roots };
}

// The glTF document of one model: one scene over `roots`, the extensions at the top level.
function vrmDoc(nodes, roots, extensionsUsed, extensions) {
  return {
    asset: { version: '2.0', generator: 'springbones scripts/generate/make_vrm_fixtures.mjs' },
    extensionsUsed,
    extensions,
    scene: 0,
    scenes: [{ nodes: roots }],
    nodes,
  };
}

// Shared body: +Y up, the avatar faces +Z (VRM 1.0 convention), metres.
const body = [
  ['Root', null, null],
  ['J_Hips', 'Root', [0, 0.95, 0]],
  ['J_Spine', 'J_Hips', [0, 0.1, 0]],
  ['J_Chest', 'J_Spine', [0, 0.15, 0]],
  ['J_Neck', 'J_Chest', [0, 0.2, 0]],
  ['J_Head', 'J_Neck', [0, 0.08, 0]],
  ['J_UpperLeg_L', 'J_Hips', [0.09, -0.05, 0]],
  ['J_UpperLeg_R', 'J_Hips', [-0.09, -0.05, 0]],
];

// ---------------------------------------------------------------------------------------------
// VRM 1.0

function vrm10() {
  const { nodes, index, roots } = buildNodes([
    ...body,
    // Back hair: root tilted back 30 degrees about X (quaternion of 30 deg: sin 15, cos 15).
    ['Hair_Back_1', 'J_Head', [0, 0.1, -0.11], [0.25881904510252074, 0, 0, 0.9659258262890683]],
    ['Hair_Back_2', 'Hair_Back_1', [0, -0.07, -0.01]],
    ['Hair_Back_3', 'Hair_Back_2', [0, -0.07, 0], [0, 0, 0.0998334166468281, 0.9950041652780258]],
    ['Hair_Back_4', 'Hair_Back_3', [0, -0.06, 0]],
    ['Hair_Back_End', 'Hair_Back_4', [0, -0.05, 0]],
    // A skirt panel in front of the left leg.
    ['Skirt_L_1', 'J_Hips', [0.07, -0.03, 0.11]],
    ['Skirt_L_2', 'Skirt_L_1', [0, -0.1, 0.015]],
    ['Skirt_L_3', 'Skirt_L_2', [0, -0.1, 0], [0.0499791692706783, 0, 0, 0.9987502603949663]],
    ['Skirt_L_End', 'Skirt_L_3', [0, -0.1, 0]],
  ]);
  const n = (name) => index.get(name);
  const joint = (name, p) => ({ node: n(name), ...p });
  const ext = {
    specVersion: '1.0',
    colliders: [
      { node: n('J_Head'), shape: { sphere: { offset: [0, 0.07, -0.01], radius: 0.115 } } },
      { node: n('J_UpperLeg_L'), shape: { capsule: { offset: [0, 0, 0], radius: 0.07, tail: [0, -0.4, 0.02] } } },
      { node: n('J_UpperLeg_R'), shape: { capsule: { offset: [0, 0, 0], radius: 0.07, tail: [0, -0.4, 0.02] } } },
      { node: n('J_Chest'), shape: { sphere: { offset: [0, 0.05, -0.03], radius: 0.12 } } },
    ],
    colliderGroups: [
      { name: 'head', colliders: [0] },
      { name: 'legs', colliders: [1, 2] },
      { name: 'chest', colliders: [3] },
    ],
    springs: [
      {
        name: 'hair_back',
        joints: [
          joint('Hair_Back_1', { hitRadius: 0.02, stiffness: 1.2, gravityPower: 0.4, gravityDir: [0, -1, 0], dragForce: 0.35 }),
          joint('Hair_Back_2', { hitRadius: 0.02, stiffness: 0.9, gravityPower: 0.5, gravityDir: [0, -1, 0], dragForce: 0.3 }),
          joint('Hair_Back_3', { hitRadius: 0.015, stiffness: 0.7, gravityPower: 0.5, gravityDir: [0, -1, 0], dragForce: 0.3 }),
          joint('Hair_Back_4', { hitRadius: 0.01, stiffness: 0.5, gravityPower: 0.3, gravityDir: [0, -1.5, 0.5], dragForce: 0.25 }),
          joint('Hair_Back_End', { hitRadius: 0.01, stiffness: 9, gravityPower: 9, gravityDir: [1, 0, 0], dragForce: 0.9 }),  // tail only: unused
        ],
        colliderGroups: [0, 2],
      },
      {
        name: 'skirt_left',
        joints: [
          joint('Skirt_L_1', { hitRadius: 0.02, stiffness: 0.8, gravityPower: 0.6, gravityDir: [0, -0.8944271909999159, -0.4472135954999579], dragForce: 0.2 }),
          joint('Skirt_L_2', { hitRadius: 0.02, stiffness: 0.6, gravityPower: 0.6, gravityDir: [0, -0.8944271909999159, -0.4472135954999579], dragForce: 0.2 }),
          joint('Skirt_L_3', { hitRadius: 0.02, stiffness: 0.4, gravityPower: 0.6, gravityDir: [0, -0.8944271909999159, -0.4472135954999579], dragForce: 0.15 }),
          joint('Skirt_L_End', {}),
        ],
        colliderGroups: [1],
        center: n('J_Hips'),
      },
    ],
  };
  return vrmDoc(nodes, roots, ['VRMC_springBone'], { VRMC_springBone: ext });
}

// ---------------------------------------------------------------------------------------------
// VRM 1.0 with VRMC_springBone_extended_collider

// A back-hair strand kept behind a plane on the head, an ear pendant kept inside a sphere on the
// head, a tail kept inside a capsule on the hips, and one extended collider of an unknown
// specVersion whose base sphere (on the chest) applies instead. Each extended collider carries
// the base shape the extension asks writers for: a radius-0 sphere far away for the inside
// shapes, a huge sphere on the far side for the plane.
function vrm10Extended() {
  const { nodes, index, roots } = buildNodes([
    ...body,
    ['Hair_Back_1', 'J_Head', [0, 0.1, -0.11], [0.25881904510252074, 0, 0, 0.9659258262890683]],
    ['Hair_Back_2', 'Hair_Back_1', [0, -0.07, -0.01]],
    ['Hair_Back_3', 'Hair_Back_2', [0, -0.07, 0]],
    ['Hair_Back_End', 'Hair_Back_3', [0, -0.06, 0]],
    ['Ear_L_1', 'J_Head', [0.08, 0, 0]],
    ['Ear_L_2', 'Ear_L_1', [0, -0.04, 0]],
    ['Ear_L_End', 'Ear_L_2', [0, -0.04, 0]],
    ['Tail_1', 'J_Hips', [0, -0.02, -0.12]],
    ['Tail_2', 'Tail_1', [0, -0.1, -0.05]],
    ['Tail_3', 'Tail_2', [0, -0.1, -0.03]],
    ['Tail_End', 'Tail_3', [0, -0.1, 0]],
  ]);
  const n = (name) => index.get(name);
  const joint = (name, p) => ({ node: n(name), ...p });
  const extended = (shape) => ({ VRMC_springBone_extended_collider: { specVersion: '1.0', shape } });
  const farAway = { sphere: { offset: [0, -10000, 0], radius: 0 } };
  const ext = {
    specVersion: '1.0',
    colliders: [
      // The back of the head: tails stay on the -Z side of z = -0.1 (head space).
      { node: n('J_Head'), shape: { sphere: { offset: [0, 0, 9999.9], radius: 10000 } },
        extensions: extended({ plane: { offset: [0, 0, -0.1], normal: [0, 0, -1] } }) },
      { node: n('J_Head'), shape: farAway, extensions: extended({ sphere: { offset: [0.08, -0.05, 0], radius: 0.045, inside: true } }) },
      { node: n('J_Hips'), shape: farAway,
        extensions: extended({ capsule: { offset: [0, -0.02, -0.12], tail: [0, -0.35, -0.22], radius: 0.05, inside: true } }) },
      // A version no reader knows: its base shape, a chest sphere, is the collider.
      { node: n('J_Chest'), shape: { sphere: { offset: [0, 0.1, -0.12], radius: 0.08 } },
        extensions: { VRMC_springBone_extended_collider: { specVersion: '9.0', shape: { plane: { normal: [0, 1, 0] } } } } },
    ],
    colliderGroups: [
      { name: 'head_back', colliders: [0, 3] },
      { name: 'ear', colliders: [1] },
      { name: 'tail', colliders: [2] },
    ],
    springs: [
      {
        name: 'hair_back',
        joints: [
          joint('Hair_Back_1', { hitRadius: 0.02, stiffness: 1.0, gravityPower: 0.4, gravityDir: [0, -1, 0], dragForce: 0.3 }),
          joint('Hair_Back_2', { hitRadius: 0.02, stiffness: 0.8, gravityPower: 0.5, gravityDir: [0, -1, 0], dragForce: 0.3 }),
          joint('Hair_Back_3', { hitRadius: 0.015, stiffness: 0.6, gravityPower: 0.5, gravityDir: [0, -1, 0], dragForce: 0.25 }),
          joint('Hair_Back_End', {}),
        ],
        colliderGroups: [0],
      },
      {
        name: 'ear_pendant',
        joints: [
          joint('Ear_L_1', { hitRadius: 0.01, stiffness: 0.5, gravityPower: 0.5, gravityDir: [0, -1, 0], dragForce: 0.3 }),
          joint('Ear_L_2', { hitRadius: 0.01, stiffness: 0.4, gravityPower: 0.5, gravityDir: [0, -1, 0], dragForce: 0.3 }),
          joint('Ear_L_End', {}),
        ],
        colliderGroups: [1],
      },
      {
        name: 'tail',
        joints: [
          joint('Tail_1', { hitRadius: 0.015, stiffness: 0.7, gravityPower: 0.5, gravityDir: [0, -1, 0], dragForce: 0.2 }),
          joint('Tail_2', { hitRadius: 0.015, stiffness: 0.6, gravityPower: 0.5, gravityDir: [0, -1, 0], dragForce: 0.2 }),
          joint('Tail_3', { hitRadius: 0.015, stiffness: 0.5, gravityPower: 0.5, gravityDir: [0, -1, 0], dragForce: 0.2 }),
          joint('Tail_End', {}),
        ],
        colliderGroups: [2],
      },
    ],
  };
  return vrmDoc(nodes, roots, ['VRMC_springBone', 'VRMC_springBone_extended_collider'], { VRMC_springBone: ext });
}

// ---------------------------------------------------------------------------------------------
// VRM 0.x

function vrm0() {
  const { nodes, index, roots } = buildNodes([
    ...body,
    // Hair root with two children: the first is its tail, the second a branch joint.
    ['Hair_1', 'J_Head', [0, 0.11, -0.12], [0, 0.25881904510252074, 0, 0.9659258262890683]],
    ['Hair_1_a', 'Hair_1', [0, -0.08, -0.03]],
    ['Hair_1_a_b', 'Hair_1_a', [0, -0.07, 0]],  // leaf: virtual tail 7 cm along -Y
    ['Hair_1_side', 'Hair_1', [0.04, -0.06, 0], [0, 0, 0.19866933079506122, 0.9800665778412416]],  // rotated leaf
    ['Ear_L', 'J_Head', [0.08, 0.03, 0.0]],  // a root that is a leaf: one joint, virtual tail
    // A tail behind the hips.
    ['Tail_1', 'J_Hips', [0, -0.02, -0.12]],
    ['Tail_2', 'Tail_1', [0, -0.05, -0.1]],
    ['Tail_3', 'Tail_2', [0, -0.06, -0.08]],
  ]);
  const n = (name) => index.get(name);
  const secondaryAnimation = {
    boneGroups: [
      {
        comment: 'hair',
        stiffiness: 1.1,
        gravityPower: 0.3,
        gravityDir: { x: 0, y: -1, z: 0 },
        dragForce: 0.3,
        center: -1,
        hitRadius: 0.015,
        bones: [n('Hair_1'), n('Ear_L')],
        colliderGroups: [0],
      },
      {
        comment: 'tail',
        stiffiness: 0.7,
        gravityPower: 0.5,
        gravityDir: { x: 0.3, y: -1.2, z: 0 },  // not unit: gravity = dir * power in both engines
        dragForce: 0.2,
        center: n('J_Hips'),
        hitRadius: 0.02,
        bones: [n('Tail_1')],
        colliderGroups: [1],
      },
    ],
    colliderGroups: [
      {
        node: n('J_Head'),
        colliders: [
          { offset: { x: 0, y: 0.07, z: 0.01 }, radius: 0.1 },  // z is Unity's: (0, 0.07, -0.01) in glTF
          { offset: { x: 0, y: -0.02, z: 0.06 }, radius: 0.06 },
        ],
      },
      { node: n('J_Hips'), colliders: [{ offset: { x: 0, y: -0.16, z: 0.14 }, radius: 0.09 }] },
    ],
  };
  return vrmDoc(nodes, roots, ['VRM'], { VRM: { specVersion: '0.0', secondaryAnimation } });
}

mkdirSync(outDir, { recursive: true });
for (const [file, doc] of [['vrm10_springs.vrm', vrm10()], ['vrm0_springs.vrm', vrm0()], ['vrm10_extended_colliders.vrm', vrm10Extended()]]) {
  const bytes = glbOfDoc(doc);
  writeFileSync(join(outDir, file), bytes);
  console.log(`wrote tests/fixtures/${file} (${bytes.length} bytes, ${doc.nodes.length} nodes)`);
}
