// The conformance pack (conformance/): run.mjs passes every case on this build, fails (naming the
// case, frame and node) when an expectation is off, and the pack is what its generator writes.
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import { cpSync, mkdtempSync, readFileSync, readdirSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { after, before, test } from 'node:test';

import { root } from './helpers.mjs';

const pack = join(root, 'conformance');
const runner = join(pack, 'run.mjs');
const caseFiles = readdirSync(join(pack, 'cases')).filter((f) => f.endsWith('.json')).sort();

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

test('node conformance/run.mjs passes every case', () => {
  const { code, stdout, stderr } = runNode(runner);
  assert.equal(code, 0, stdout + stderr);
  assert.match(stdout, new RegExp(`^${caseFiles.length} of ${caseFiles.length} cases pass`, 'm'));
  assert.doesNotMatch(stdout, /MISS/);
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

test('the pack is what scripts/make_conformance.mjs writes, byte for byte', () => {
  const out = join(scratch, 'regenerated');
  const { code, stderr } = runNode(join(root, 'scripts', 'make_conformance.mjs'), '--out', out);
  assert.equal(code, 0, stderr);
  for (const folder of ['cases', 'glb']) {
    const files = readdirSync(join(pack, folder)).sort();
    assert.deepEqual(readdirSync(join(out, folder)).sort(), files, folder);
    for (const f of files) {
      assert.ok(readFileSync(join(out, folder, f)).equals(readFileSync(join(pack, folder, f))), `${folder}/${f} differs`);
    }
  }
});
