// Messages a person can act on (issue 37's table, found by trying the library as a new user): each
// names what was given, what was expected and where the right thing is. The module-load errors
// are in module_load_errors.test.mjs, step(16) in long_frame.test.mjs.
import assert from 'node:assert/strict';
import { before, test } from 'node:test';

import { createSpringBones, SpringBonesError } from '../../web/springbones.js';
import { springRig } from './helpers.mjs';

const kBaseMale = 'urn:decentraland:off-chain:base-avatars:BaseMale';
const kBaseFemale = 'urn:decentraland:off-chain:base-avatars:BaseFemale';

let sb;
before(async () => {
  sb = await createSpringBones();
});

// A catalyst entity wearing the test rig's GLB for both body shapes, its springBones where the
// catalyst keeps it (metadata.data.springBones).
function entityOf({ hash, springBones }) {
  return {
    version: 'v3', type: 'wearable', pointers: ['urn:test'], timestamp: 0,
    content: [{ file: 'hair.glb', hash }],
    metadata: { id: 'urn:test', data: { springBones, representations: [
      { bodyShapes: [kBaseMale, kBaseFemale], mainFile: 'hair.glb', contents: ['hair.glb'] },
    ] } },
  };
}

test('an entity passed as springBones says it is an entity and where its springBones is', () => {
  const rig = springRig();
  const entity = entityOf(rig);
  const loaded = sb.loadRig(rig.doc, entity, { contentHash: rig.hash });
  assert.equal(loaded.joints.length, 0);
  const [warning] = loaded.warnings;
  assert.equal(warning.code, 'unsupported-version', 'the code a catalyst entity always earned');
  assert.match(warning.message, /springBones is a wearable entity \(it has metadata\.data\)/);
  assert.match(warning.message, /pass entity\.metadata\.data\.springBones as springBones \(it has one\)/);
  assert.doesNotMatch(warning.message, /"v3"/, 'not the entity\'s version read as springBones.version');
  // Following the advice loads the chains.
  assert.equal(sb.loadRig(rig.doc, entity.metadata.data.springBones, { entity, bodyShape: kBaseMale }).joints.length, 3);

  // A Builder item keeps it at data.springBones; one without any says so.
  const item = { contents: { 'hair.glb': rig.hash }, data: { representations: entity.metadata.data.representations } };
  const [itemWarning] = sb.loadRig(rig.doc, item, { contentHash: rig.hash }).warnings;
  assert.match(itemWarning.message, /a Builder item \(it has data\.representations\).*item\.data\.springBones.*this one has none/);
  // Anything else with a wrong version keeps the plain message.
  const [plain] = sb.loadRig(rig.doc, { version: 2, models: {} }, { contentHash: rig.hash }).warnings;
  assert.match(plain.message, /springBones\.version is 2, not 1/);
});

test("bodyShape 'basemale' is refused with the entity's body shapes, and the one it differs from by case", () => {
  const rig = springRig();
  const entity = entityOf(rig);
  const error = (() => {
    try {
      sb.loadRig(rig.doc, rig.springBones, { entity, bodyShape: 'basemale' });
    } catch (e) {
      return e;
    }
    return null;
  })();
  assert.ok(error instanceof SpringBonesError, String(error));
  assert.equal(error.code, 'invalid-argument');
  assert.equal(error.path, '/metadata/data/representations');
  assert.ok(error.message.includes(`its body shapes are '${kBaseMale}', '${kBaseFemale}'`), error.message);
  assert.match(error.message, /did you mean 'BaseMale'\?/);
  // Matching stays by URN suffix with the catalyst's case: the suggestion works.
  assert.equal(sb.loadRig(rig.doc, rig.springBones, { entity, bodyShape: 'BaseMale' }).joints.length, 3);
  // A body shape that is nothing like one lists them without a guess.
  assert.throws(() => sb.loadRig(rig.doc, rig.springBones, { entity, bodyShape: 'Robot' }),
                (e) => e.message.includes(`body shape 'Robot'; its body shapes are '${kBaseMale}'`) && !/did you mean/.test(e.message));
});

test('the list of body shapes is bounded', () => {
  const rig = springRig();
  const entity = entityOf(rig);
  entity.metadata.data.representations[0].bodyShapes = Array.from({ length: 30 }, (_, i) => `urn:shape:${i}`);
  assert.throws(() => sb.loadRig(rig.doc, rig.springBones, { entity, bodyShape: 'BaseMale' }),
                (e) => /'urn:shape:7' and 22 more/.test(e.message) && !e.message.includes('urn:shape:8'));
});

test("a collider on 'Head', a node the rig does not have, warns with the nodes that exist", () => {
  const rig = springRig({ chains: 2 });
  const loaded = sb.loadRig(rig.doc, rig.springBones, { contentHash: rig.hash, colliders: [{ node: 'Head', radius: 0.1 }] });
  const warnings = loaded.warnings.filter((w) => w.code === 'collider-node-not-found');
  assert.equal(warnings.length, 1, JSON.stringify(loaded.warnings));
  assert.match(warnings[0].message, /collider node 'Head' is neither a node of this GLB nor a Decentraland avatar bone/);
  assert.match(warnings[0].message, /nodes a collider can be on are 'Avatar_Head'$/, 'spring bones are not offered');
  // It still becomes a driver the page may supply, as before.
  assert.ok(loaded.drivers.some((d) => d.name === 'Head' && d.node === -1));
  // An avatar bone the GLB lacks is what the option is for: no warning.
  const chest = sb.loadRig(rig.doc, rig.springBones, { contentHash: rig.hash, colliders: [{ node: 'Avatar_Chest', radius: 0.1 }] });
  assert.deepEqual(chest.warnings, []);
});

test('the nodes listed for a missing collider node are bounded', () => {
  const rig = springRig();
  for (let i = 0; i < 25; i++) {
    rig.doc.nodes.push({ name: `Prop_${i}_${'x'.repeat(100)}` });
    rig.doc.nodes[0].children.push(rig.doc.nodes.length - 1);
  }
  const loaded = sb.loadRig(rig.doc, rig.springBones, { contentHash: rig.hash, colliders: [{ node: 'Head', radius: 0.1 }] });
  const [warning] = loaded.warnings.filter((w) => w.code === 'collider-node-not-found');
  assert.match(warning.message, /and 16 more$/, 'Avatar_Head and 9 props listed, 16 props left');
  assert.ok(warning.message.length < 1200, `${warning.message.length} characters`);
  assert.match(warning.message, /'Prop_0_x{57}\.\.\.'/, 'a long name quoted to 64 bytes');
});
