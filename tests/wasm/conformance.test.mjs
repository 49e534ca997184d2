// The conformance pack (conformance/): run.mjs passes every case, ADR and VRM, on this build, fails
// (naming the case, frame and node) when an expectation is off, a VRM case tells UniVRM's limit
// import rules from three-vrm's, the three-vrm runner gives the result conformance/README.md
// publishes, and the pack is what its generators write.
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import { cpSync, mkdtempSync, readFileSync, readdirSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { after, before, test } from 'node:test';

import { glbOfDoc, gltfOf } from '../../scripts/lib/fixtures/glb.mjs';
import { root } from './helpers.mjs';

const pack = join(root, 'conformance');
const runner = join(pack, 'run.mjs');
const caseFiles = readdirSync(join(pack, 'cases')).filter((f) => f.endsWith('.json')).sort();
const vrmPack = join(pack, 'vrm');
const vrmFiles = readdirSync(join(vrmPack, 'cases')).filter((f) => f.endsWith('.json')).sort();

function runNode(...args) {
  const result = spawnSync(process.execPath, args, { encoding: 'utf8', maxBuffer: 1 << 26 });
  return { code: result.status, stdout: result.stdout, stderr: result.stderr };
}

let scratch;
before(() => { scratch = mkdtempSync(join(tmpdir(), 'springbones-conformance-')); });
after(() => rmSync(scratch, { recursive: true, force: true }));

test('the pack has at least 12 cases, each with expected rotations for every frame', () => {
  assert.ok(caseFiles.length >= 12, `${caseFiles.length} cases`);
  for (const f of caseFiles) {
    const c = JSON.parse(readFileSync(join(pack, 'cases', f), 'utf8'));
    assert.ok(c.frames.length > 0, f);
    for (const frame of c.frames) assert.equal(frame.rotations.length, c.nodes.length, f);
  }
});

test('the VRM part has at least 12 cases of VRMC_springBone 1.0, each loading the file\'s own spring bones', () => {
  assert.ok(vrmFiles.length >= 12, `${vrmFiles.length} cases`);
  for (const f of vrmFiles) {
    const c = JSON.parse(readFileSync(join(vrmPack, 'cases', f), 'utf8'));
    assert.deepEqual(c.load, { vrm: true }, f);
    assert.ok(c.requires.includes('vrm'), f);
    const gltf = gltfOf(readFileSync(join(vrmPack, 'cases', c.glb)));
    assert.equal(gltf.extensions.VRMC_springBone.specVersion, '1.0', f);
    for (const frame of c.frames) assert.equal(frame.rotations.length, c.nodes.length, f);
  }
});

test('node conformance/run.mjs passes every case, ADR and VRM', () => {
  const { code, stdout, stderr } = runNode(runner);
  const total = caseFiles.length + vrmFiles.length;
  assert.equal(code, 0, stdout + stderr);
  assert.match(stdout, new RegExp(`^${total} of ${total} cases pass`, 'm'));
  assert.doesNotMatch(stdout, /MISS/);
});

test('a runtime that reads a limit with two shapes as its first shape (three-vrm\'s pull request) misses that case', () => {
  const copy = join(scratch, 'two-shapes');
  cpSync(vrmPack, copy, { recursive: true });
  const name = vrmFiles.find((f) => f.includes('limit-two-shapes'));
  const c = JSON.parse(readFileSync(join(copy, 'cases', name), 'utf8'));
  const model = join(copy, 'cases', c.glb);
  const gltf = gltfOf(readFileSync(model));
  // The file as such a runtime sees it: the cone alone.
  delete gltf.extensions.VRMC_springBone.springs[0].joints[0].extensions.VRMC_springBone_limit.limit.hinge;
  const glb = glbOfDoc(gltf);
  writeFileSync(model, glb);
  const { code, stdout } = runNode(runner, '--cases', join(copy, 'cases'), 'limit-two-shapes');
  assert.equal(code, 1, stdout);
  assert.match(stdout, /^MISS {2}\S*limit-two-shapes\.json: \d+ miss/m);
});

test('three-vrm 3.5.5 passes the VRM cases without limits once its bone length is measured at the current pose', () => {
  const threeRunner = join(pack, 'run_three_vrm.mjs');
  const withoutLimits = vrmFiles.filter((f) => !JSON.parse(readFileSync(join(vrmPack, 'cases', f), 'utf8')).requires.includes('vrm-limits'));
  const exact = runNode(threeRunner, '--exact-length');
  assert.equal(exact.code, 0, exact.stdout + exact.stderr);
  assert.match(exact.stdout, new RegExp(`^${withoutLimits.length} of ${withoutLimits.length} cases pass`, 'm'));
  // As published, its bone length from the previous frame misses every one (conformance/README.md).
  const stock = runNode(threeRunner);
  assert.equal(stock.code, 1, stock.stdout);
  assert.match(stock.stdout, new RegExp(`^0 of ${withoutLimits.length} cases pass`, 'm'));
});

test('the runner fails, naming the case, frame and node, when one expected rotation is off', () => {
  const copy = join(scratch, 'mutated');
  cpSync(join(pack, 'cases'), join(copy, 'cases'), { recursive: true });
  cpSync(join(pack, 'glb'), join(copy, 'glb'), { recursive: true });
  const file = join(copy, 'cases', '06-clamp-stiffness.json');
  const c = JSON.parse(readFileSync(file, 'utf8'));
  const joint = c.nodes.indexOf('SpringBone_hair_left');
  // Turn the expected rotation of frame 30 by 3e-4 rad about X: ten times the tolerance.
  assert.equal(c.tolerance, 3e-5);
  const [x, y, z, w] = c.frames[30].rotations[joint];
  const s = Math.sin(1.5e-4);
  const k = Math.cos(1.5e-4);
  c.frames[30].rotations[joint] = [k * x + s * w, k * y + s * z, k * z - s * y, k * w - s * x];
  writeFileSync(file, JSON.stringify(c));

  const { code, stdout } = runNode(runner, '--cases', join(copy, 'cases'));
  assert.equal(code, 1, stdout);
  assert.match(stdout, /^MISS {2}06-clamp-stiffness\.json: 1 miss$/m);
  assert.match(stdout, /frame 30, SpringBone_hair_left: off by (2\.9\d|3\.0\d)e-4 rad \(tolerance 0\.00003\)/);
  assert.match(stdout, new RegExp(`^${caseFiles.length - 1} of ${caseFiles.length} cases pass`, 'm'));
});

test('the VRM part is what scripts/generate/make_conformance_vrm.mjs writes, byte for byte', () => {
  const out = join(scratch, 'regenerated-vrm');
  const { code, stderr } = runNode(join(root, 'scripts', 'generate', 'make_conformance_vrm.mjs'), '--out', out);
  assert.equal(code, 0, stderr);
  for (const folder of ['cases', 'models']) {
    const files = readdirSync(join(vrmPack, folder)).sort();
    assert.deepEqual(readdirSync(join(out, folder)).sort(), files, folder);
    for (const f of files) {
      assert.ok(readFileSync(join(out, folder, f)).equals(readFileSync(join(vrmPack, folder, f))), `vrm/${folder}/${f} differs`);
    }
  }
});

test('the pack is what scripts/generate/make_conformance.mjs writes, byte for byte', () => {
  const out = join(scratch, 'regenerated');
  const { code, stderr } = runNode(join(root, 'scripts', 'generate', 'make_conformance.mjs'), '--out', out);
  assert.equal(code, 0, stderr);
  for (const folder of ['cases', 'glb']) {
    const files = readdirSync(join(pack, folder)).sort();
    assert.deepEqual(readdirSync(join(out, folder)).sort(), files, folder);
    for (const f of files) {
      assert.ok(readFileSync(join(out, folder, f)).equals(readFileSync(join(pack, folder, f))), `${folder}/${f} differs`);
    }
  }
});
