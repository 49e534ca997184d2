// What the three.js adapter and its loader plugin take from three.js beyond its documented API,
// checked against the installed `three` so that a release that changes one fails here, loudly,
// rather than leaving bones unmoved. Run by tests/package/ with every `three` version that
// package.json's peerDependencies range claims (its lowest and its highest).
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { Matrix4, Object3D, Quaternion, REVISION, Vector3 } from 'three';
import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';
import * as SkeletonUtils from 'three/examples/jsm/utils/SkeletonUtils.js';

// tests/package/ names the revision it installed, so that a resolution mix-up cannot pass unseen.
test(`three r${REVISION} is the version under test`, () => {
  const expected = process.env.SPRINGBONES_THREE_REVISION;
  assert.ok(expected, 'tests/package/ sets SPRINGBONES_THREE_REVISION');
  assert.equal(REVISION, expected);
});

test('a Quaternion keeps its components in the own fields _x, _y, _z, _w that x, y, z, w read', () => {
  // The adapter writes the fields directly (5-10x cheaper than set(), which fires onChange).
  const object = new Object3D();
  const q = object.quaternion;
  for (const field of ['_x', '_y', '_z', '_w']) {
    const own = Object.getOwnPropertyDescriptor(q, field);
    assert.ok(own && 'value' in own && own.writable, `${field} is an own writable data field`);
  }
  const expected = new Quaternion().setFromAxisAngle(new Vector3(1, 2, 3).normalize(), 0.7);
  q._x = expected.x; q._y = expected.y; q._z = expected.z; q._w = expected.w;
  assert.deepEqual(q.toArray(), expected.toArray());
  assert.deepEqual([q.x, q.y, q.z, q.w], expected.toArray());
  // ... and updateMatrix composes the object's matrix from them.
  object.position.set(1, 2, 3);
  object.updateMatrixWorld(true);
  const composed = new Matrix4().compose(new Vector3(1, 2, 3), expected, new Vector3(1, 1, 1));
  assert.deepEqual(object.matrixWorld.elements, composed.elements);
});

test('writing the fields leaves .rotation alone; setFromQuaternion(q, order, false) syncs it without onChange', () => {
  const object = new Object3D();
  const expected = new Quaternion().setFromAxisAngle(new Vector3(0, 0, 1), 0.5);
  const q = object.quaternion;
  q._x = expected.x; q._y = expected.y; q._z = expected.z; q._w = expected.w;
  assert.equal(object.rotation.z, 0, 'no onChange: the Euler is stale, as the adapter documents');
  let quaternionChanged = false;
  q._onChange(() => { quaternionChanged = true; });  // the adapter's syncEulers must not fire it
  object.rotation.setFromQuaternion(q, undefined, false);
  assert.ok(Math.abs(object.rotation.z - 0.5) < 1e-7);
  assert.equal(quaternionChanged, false);
});

test('an Object3D keeps its quaternion and its matrixWorld.elements array for life', () => {
  // The adapter caches both at attach time and touches only them per frame.
  const object = new Object3D();
  const parent = new Object3D();
  parent.add(object);
  const quaternion = object.quaternion;
  const elements = object.matrixWorld.elements;
  assert.throws(() => { 'use strict'; object.quaternion = new Quaternion(); }, TypeError);
  object.copy(new Object3D().translateX(2), false);
  object.lookAt(1, 2, 3);
  parent.position.set(0, 5, 0);
  parent.updateMatrixWorld(true);
  object.applyMatrix4(new Matrix4().makeTranslation(1, 0, 0));
  parent.updateMatrixWorld(true);
  assert.equal(object.quaternion, quaternion);
  assert.equal(object.matrixWorld.elements, elements);
  assert.equal(elements[13], 5, 'the kept array holds the current world matrix');
});

/** A glTF (JSON, no buffers) whose node names three.js sanitizes. */
const gltfJson = JSON.stringify({
  asset: { version: '2.0' },
  scene: 0,
  scenes: [{ nodes: [0] }],
  nodes: [
    { name: 'Armature.001', children: [1, 2] },
    { name: 'hair springbone.L', translation: [0, 1, 0], children: [3] },
    { name: 'hair springbone.R', translation: [0, 1, 0] },
    { name: 'hair springbone.L tip', translation: [0, 1, 0] },
  ],
});

test('GLTFLoader keeps glTF names in userData.name and node indices in parser.associations', async () => {
  const gltf = await new GLTFLoader().parseAsync(gltfJson, '');
  const byIndex = [];
  gltf.scene.traverse((o) => {
    const index = gltf.parser.associations.get(o)?.nodes;
    if (index !== undefined) byIndex[index] = o;
  });
  assert.deepEqual(byIndex.map((o) => o.userData.name),
      ['Armature.001', 'hair springbone.L', 'hair springbone.R', 'hair springbone.L tip']);
  assert.notEqual(byIndex[1].name, 'hair springbone.L', 'object.name is sanitized, so the adapter reads userData.name');
  assert.equal(byIndex[3].parent, byIndex[1]);
});

test('GLTFLoader calls a registered plugin\'s afterRoot with the result and its userData, then resolves', async () => {
  const loader = new GLTFLoader();
  const seen = [];
  loader.register((parser) => ({
    name: 'springbones_internals_probe',
    async afterRoot(result) {
      seen.push(parser.json.nodes.length, result.parser === parser, typeof result.userData);
      await new Promise((resolve) => setTimeout(resolve, 10));
      result.userData.probe = 'written in afterRoot';
    },
  }));
  const gltf = await loader.parseAsync(gltfJson, '');
  assert.deepEqual(seen, [4, true, 'object']);
  assert.equal(gltf.userData.probe, 'written in afterRoot', 'the load waits for afterRoot');
});

test('SkeletonUtils.clone keeps the tree\'s shape and child order (wearableNodes walks both side by side)', async () => {
  const gltf = await new GLTFLoader().parseAsync(gltfJson, '');
  const copy = SkeletonUtils.clone(gltf.scene);
  const shape = (o) => [o.userData.name ?? '', o.children.map(shape)];
  assert.deepEqual(shape(copy), shape(gltf.scene));
  const first = (o) => o.children[0];
  assert.notEqual(first(first(copy)), first(first(gltf.scene)), 'objects are copies');
});
