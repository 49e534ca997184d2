// "The name contains springbone" is one rule in JavaScript (web/wearable/spring_bone_name.js) and
// one in the core (isSpringBoneName in src/loading/rig_builder.cpp). The core is the ground truth:
// loadRig starts a chain at every entry with isRoot whose node it takes for a spring bone, so the
// joints it builds over nodes with tricky names say which names it accepts.
import assert from 'node:assert/strict';
import { before, test } from 'node:test';
import { createSpringBones } from '../../web/springbones.js';
import { isSpringBoneName, springBoneNames } from '../../web/wearable/spring_bone_name.js';

let sb;
before(async () => {
  sb = await createSpringBones();
});

const kNames = [
  'SpringBone_hair', 'springbone', 'SPRINGBONE', 'sPrInGbOnE_2', 'hair_springbone_l', 'xspringbonex',
  'spring_bone', 'springbon', 'Spring Bone', 'springbone'.split('').join('\u200b'),
  '\u017Fpringbone',            // long s: Unicode folds it to "s"
  'SPR\u0130NGBONE',            // dotted capital I: toLowerCase gives "i" and a combining dot
  'spr\u0131ngbone',            // dotless i: toUpperCase gives "I"
  '\uFF53\uFF50\uFF52\uFF49\uFF4E\uFF47\uFF42\uFF4F\uFF4E\uFF45',  // full-width letters
  'SPRINGBONE\u00DF', '\u00FCber_springbone', '\u9AEA_springbone', 'springbone\u0301', 'SPRINGBONE_\u{1F487}',
];

test('isSpringBoneName accepts exactly the names the core starts chains at', () => {
  const nodes = [];
  const roots = [];
  for (const name of kNames) {
    roots.push(nodes.length);
    nodes.push({ name, children: [nodes.length + 1], translation: [0, 1, 0] });
    nodes.push({ name: `tip ${nodes.length}`, translation: [0, 0.1, 0] });
  }
  const gltf = { asset: { version: '2.0' }, scene: 0, scenes: [{ nodes: roots }], nodes };
  const entry = Object.fromEntries(kNames.map((name) => [name, { isRoot: true }]));
  const rig = sb.loadRig(gltf, { version: 1, models: { h: entry } }, { contentHash: 'h' });
  const coreAccepts = new Set(rig.chains.map((root) => rig.joints[root].name));
  rig.dispose();
  for (const name of kNames) {
    assert.equal(isSpringBoneName(name), coreAccepts.has(name), `${JSON.stringify(name)}: the core ${coreAccepts.has(name) ? 'accepts' : 'refuses'} it`);
  }
  // The list is not trivial: both answers occur, including for names a Unicode folding would take.
  assert.ok(coreAccepts.size >= 5 && coreAccepts.size <= kNames.length - 5, [...coreAccepts].join(', '));
  assert.equal(coreAccepts.has('\u017Fpringbone'), false);
});

test('anything but a string is no spring-bone name; springBoneNames keeps node order', () => {
  for (const value of [undefined, null, 5, ['springbone'], { toString: () => 'springbone' }]) assert.equal(isSpringBoneName(value), false);
  assert.deepEqual(springBoneNames([{ name: 'b_springbone' }, null, { name: 'Armature' }, { name: 'SpringBone_a' }, {}]), ['b_springbone', 'SpringBone_a']);
  assert.deepEqual(springBoneNames(undefined), []);
});
