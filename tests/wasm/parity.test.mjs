// Native and WebAssembly builds produce the same rotations for the same inputs (docs/design.md:
// within 1e-6). The native side is tools/dump_rotations.cpp, which scripts/test builds
// (build/native-release) before these tests run; it writes the driver matrices it fed in and the
// rotations it got, frame by frame. Here the same scenario runs through the JS API; the driver
// matrices must agree exactly (the scenario is the same), the rotations within 1e-6.
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { existsSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { after, before, describe, test } from 'node:test';

import { createSpringBones } from '../../web/springbones.js';
import { swayDrivers } from '../../bin/sway.mjs';
import { glbOfDoc } from '../../scripts/lib/fixtures/glb.mjs';
import { fixturesDir, metadataKeyOf, root, springRig } from './helpers.mjs';

const kTolerance = 1e-6;

const dumper = ['native-release', 'native-debug']
  .map((preset) => join(root, 'build', preset, 'tools', 'dump_rotations'))
  .find((path) => existsSync(path));

let sb;
let scratch;
before(async () => {
  assert.ok(dumper, 'build/native-release/tools/dump_rotations is missing: run scripts/build native');
  sb = await createSpringBones();
  scratch = mkdtempSync(join(tmpdir(), 'springbones-parity-'));
});
after(() => {
  if (scratch) rmSync(scratch, { recursive: true, force: true });
});

function runNative({ glbPath, metadataPath, hash, frames, fps, stepHz, maxSubsteps, wind, bodyColliders }) {
  const args = [glbPath, metadataPath ?? '-', hash ?? '-', String(frames), String(fps), '--drive', 'sway'];
  if (wind !== undefined) args.push('--wind', `${wind.strength},${wind.gustFrequency},${wind.seed}`);
  if (bodyColliders) args.push('--body-colliders');
  if (stepHz !== undefined) args.push('--step-hz', String(stepHz));
  if (maxSubsteps !== undefined) args.push('--max-substeps', String(maxSubsteps));
  const text = execFileSync(dumper, args, { encoding: 'utf8', maxBuffer: 1 << 28 });
  return text.trim().split('\n').map((line) => JSON.parse(line));
}

function runWasm({ glb, springBones, hash, frames, fps, stepHz, maxSubsteps, wind, bodyColliders }) {
  const options = {};
  if (stepHz !== undefined) options.stepHz = stepHz;
  if (maxSubsteps !== undefined) options.maxSubsteps = maxSubsteps;
  const rigOptions = hash === undefined ? {} : { contentHash: hash };
  if (bodyColliders) Object.assign(rigOptions, { colliders: 'dcl-body', hitRadius: 0.01 });
  const rig = sb.loadRig(glb, springBones, rigOptions);
  const inst = rig.createInstance(options);
  if (wind !== undefined) inst.setWind({ direction: [1, 0, 0.5], ...wind });
  const rest = Float32Array.from(inst.driverMatrices);
  const out = [];
  for (let k = 1; k <= frames; ++k) {
    swayDrivers(rest, inst.driverMatrices, k / fps);
    inst.step(1 / fps);
    out.push({ drivers: Float32Array.from(inst.driverMatrices), rotations: Float32Array.from(inst.rotations) });
  }
  inst.dispose();
  rig.dispose();
  return out;
}

function compare(native, wasm) {
  assert.equal(native.length, wasm.length);
  let worst = 0;
  for (let k = 0; k < native.length; ++k) {
    const n = native[k];
    const w = wasm[k];
    assert.equal(n.drivers.length, w.drivers.length);
    n.drivers.forEach((v, i) => {
      if (Math.fround(v) !== w.drivers[i]) assert.fail(`frame ${k + 1}: driver float ${i} is ${v} natively, ${w.drivers[i]} in WASM`);
    });
    assert.equal(n.rotations.length, w.rotations.length);
    n.rotations.forEach((v, i) => {
      const d = Math.abs(Math.fround(v) - w.rotations[i]);
      worst = Math.max(worst, d);
      if (!(d <= kTolerance)) assert.fail(`frame ${k + 1}: rotation float ${i} is ${v} natively, ${w.rotations[i]} in WASM`);
    });
  }
  return worst;
}

function fixtureScenario(name, metadata, hash) {
  return {
    native: { glbPath: join(fixturesDir, name), metadataPath: join(fixturesDir, metadata), hash },
    wasm: {
      glb: readFileSync(join(fixturesDir, name)),
      springBones: readFileSync(join(fixturesDir, metadata), 'utf8'),
      hash,
    },
  };
}

function check(scenario, timing) {
  const native = runNative({ ...scenario.native, ...timing });
  const wasm = runWasm({ ...scenario.wasm, ...timing });
  assert.ok(native.at(-1).rotations.some((v, i) => i % 4 !== 3 && v !== 0), 'the scenario moves something');
  return compare(native, wasm);
}

// Frame rates that are not a multiple of stepHz interpolate the driver rotations across substeps.
// The solver does it with a normalized lerp (+, *, / and sqrt only) rather than slerp, whose
// acosf/sinf come from glibc natively and from musl in WebAssembly and differ in the last bit.
describe('native and WASM agree within 1e-6 under the scripted sway', () => {
  const hair = () => fixtureScenario('avatar_hair.glb', 'avatar_hair.metadata.json', undefined);
  test('avatar_hair.glb at 60 fps (one step per frame)', () => {
    check(hair(), { frames: 300, fps: 60 });
  });
  test('avatar_hair.glb at 45 fps (drivers interpolated across substeps)', () => {
    check(hair(), { frames: 300, fps: 45 });
  });
  test('avatar_hair.glb at 144 fps with stepHz 90', () => {
    check(hair(), { frames: 400, fps: 144, stepHz: 90 });
  });
  test('avatar_hair.glb with a gusting wind and the dcl-body colliders (gusts are arithmetic only)', () => {
    check(hair(), { frames: 300, fps: 45, wind: { strength: 1.5, gustFrequency: 2, seed: 12345 }, bodyColliders: true });
  });
  test('avatar_hair.glb at 8 fps, maxSubsteps 2 (surplus time dropped)', () => {
    check(hair(), { frames: 60, fps: 8, maxSubsteps: 2 });
  });
  test('adr_example_posed.glb with the ADR metadata and hash', () => {
    const key = metadataKeyOf('adr_example_posed.glb');
    check(fixtureScenario('adr_example_posed.glb', 'adr_example.metadata.json', key), { frames: 240, fps: 60 });
  });
  test('a rig with non-uniform bone scales (the general matrix path)', () => {
    const rig = springRig({ chains: 2, joints: 4 });
    rig.doc.nodes[2].scale = [1, 2, 0.5];
    const glb = glbOfDoc(rig.doc);
    const glbPath = join(scratch, 'nonuniform.glb');
    const metadataPath = join(scratch, 'nonuniform.json');
    writeFileSync(glbPath, glb);
    writeFileSync(metadataPath, JSON.stringify(rig.springBones));
    check({ native: { glbPath, metadataPath, hash: rig.hash }, wasm: { glb, springBones: rig.springBones, hash: rig.hash } },
          { frames: 240, fps: 60 });
  });
});
