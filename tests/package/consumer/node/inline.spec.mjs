// springbones/inline in Node: the runtime module comes from the JavaScript itself, no option and no
// file read; the creator tools still load from the package's .wasm.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import { test } from 'node:test';
import { createSpringBones, SpringBonesError } from 'springbones/inline';
import { SpringBonesError as PackageError } from 'springbones';

const asset = (name) => new URL(`../assets/${name}`, import.meta.url);

test('springbones/inline resolves to the package\'s inline bundle', () => {
  assert.ok(fileURLToPath(import.meta.resolve('springbones/inline')).endsWith('/node_modules/springbones/web/dist/inline.min.js'));
  assert.equal(SpringBonesError, PackageError, 'one error class for both entries');
});

test('loads the sample wearable from the inlined module and steps it', async () => {
  const sb = await createSpringBones();
  const glb = new Uint8Array(readFileSync(asset('hair_wearable.glb')));
  const springBones = JSON.parse(readFileSync(asset('hair_wearable.metadata.json'), 'utf8'));
  const rig = sb.loadRig(glb, springBones);
  assert.equal(rig.joints.length, 15);
  const instance = rig.createInstance();
  const head = rig.drivers.findIndex((d) => d.name === 'Avatar_Head');
  const rest = instance.rotations.slice();
  for (let frame = 0; frame < 30; frame++) {
    instance.driverMatrices[16 * head + 12] += 0.01;
    instance.step(1 / 60);
  }
  assert.ok(instance.rotations.every(Number.isFinite));
  assert.ok(instance.rotations.some((v, i) => Math.abs(v - rest[i]) > 0.01), 'the hair swings');
  assert.throws(() => sb.loadRig(new Uint8Array(8)), (e) => e instanceof SpringBonesError);
  const tools = await sb.creatorTools();
  assert.equal(tools.detectSpringBones(glb).length, 20);
});
