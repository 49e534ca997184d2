// bin/springbones-cli.mjs (the package's `springbones` bin): output of inspect and simulate, metadata file shapes, exit codes.
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import { copyFileSync, mkdtempSync, rmSync, truncateSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { after, before, describe, test } from 'node:test';

import { splitMetadata } from '../../bin/springbones-cli.mjs';
import { contentHashOf, fixture, fixturesDir, metadataKeyOf, root } from './helpers.mjs';

const cli = join(root, 'bin', 'springbones-cli.mjs');
const hairGlb = join(fixturesDir, 'avatar_hair.glb');
const hairMetadata = join(fixturesDir, 'avatar_hair.metadata.json');

function run(...args) {
  const result = spawnSync(process.execPath, [cli, ...args], { encoding: 'utf8', maxBuffer: 1 << 26 });
  return { code: result.status, stdout: result.stdout, stderr: result.stderr };
}

let scratch;
before(() => {
  scratch = mkdtempSync(join(tmpdir(), 'springbones-cli-'));
});
after(() => rmSync(scratch, { recursive: true, force: true }));

describe('inspect', () => {
  test('prints the chains with their parameters, the drivers and the warnings', () => {
    const { code, stdout, stderr } = run('inspect', hairGlb, '--metadata', hairMetadata);
    assert.equal(code, 0, stderr);
    assert.match(stdout, /models key: bafk\S+ \(computed from the GLB\)/);
    assert.match(stdout, /chains \(\d+\):/);
    assert.match(stdout, /SpringBone_hair_left: 4 joints, under Avatar_Head/);
    assert.match(stdout, /SpringBone_hair_left -> SpringBone_hair_left_1 {2}stiffness 1\.5, gravityPower 0\.5, gravityDir \[0, -1, 0\], drag 0\.4/);
    assert.match(stdout, /drivers \(2\): Avatar_Head, Avatar_Hips/);
    assert.match(stdout, /center-not-found at \/models\/\S+\/SpringBone_ribbon\/center: /);
  });

  test('--json prints the rig as JSON', () => {
    const { code, stdout } = run('inspect', hairGlb, '--metadata', hairMetadata, '--json');
    assert.equal(code, 0);
    const data = JSON.parse(stdout);
    assert.equal(data.contentHash, contentHashOf('avatar_hair.glb'));
    assert.ok(data.joints.length > 10);
    assert.deepEqual(data.drivers.map((d) => d.name), ['Avatar_Head', 'Avatar_Hips']);
  });

  test('without metadata: no chains, no warnings, and a hint to pass --metadata', () => {
    const { code, stdout, stderr } = run('inspect', hairGlb);
    assert.equal(code, 0);
    assert.match(stdout, /chains \(0\):/);
    assert.match(stdout, /warnings \(0\):/);
    assert.match(stderr, /note: no springBones metadata given: pass --metadata/);
    assert.doesNotMatch(run('inspect', hairGlb, '--metadata', hairMetadata).stderr, /note:/);
  });

  test('--hash selects the models entry', () => {
    const adr = join(fixturesDir, 'adr_example_posed.glb');
    const metadata = join(fixturesDir, 'adr_example.metadata.json');
    assert.match(run('inspect', adr, '--metadata', metadata).stdout, /model-not-found/);
    const { stdout } = run('inspect', adr, '--metadata', metadata, '--hash', metadataKeyOf('adr_example_posed.glb'));
    assert.match(stdout, /chains \(2\):/);
    assert.match(stdout, /given with --hash/);
  });

  test('reads springBones out of an entity file, and --body-shape picks the representation\'s hash', () => {
    const springBones = JSON.parse(fixture('avatar_hair.metadata.json'));
    const hash = Object.keys(springBones.models)[0];
    const entity = {
      type: 'wearable',
      content: [{ file: 'hair.glb', hash }],
      metadata: { data: { representations: [{ bodyShapes: ['urn:decentraland:off-chain:base-avatars:BaseFemale'], mainFile: 'hair.glb' }], springBones } },
    };
    const path = join(scratch, 'entity.json');
    writeFileSync(path, JSON.stringify(entity));
    const computed = run('inspect', hairGlb, '--metadata', path);
    assert.equal(computed.code, 0, computed.stderr);
    assert.match(computed.stdout, /SpringBone_hair_left: 4 joints/);
    const viaEntity = run('inspect', hairGlb, '--metadata', path, '--body-shape', 'BaseFemale');
    assert.equal(viaEntity.code, 0, viaEntity.stderr);
    assert.match(viaEntity.stdout, /main file of BaseFemale in the entity/);
    const wrongShape = run('inspect', hairGlb, '--metadata', path, '--body-shape', 'BaseMale');
    assert.equal(wrongShape.code, 1);
    assert.match(wrongShape.stderr, /invalid-argument: .*BaseMale/);
  });
});

describe('simulate', () => {
  test('prints one JSON line per frame with 4 floats per joint; --drive sway moves the chains', () => {
    const joints = JSON.parse(run('inspect', hairGlb, '--metadata', hairMetadata, '--json').stdout).joints.length;
    const { code, stdout, stderr } = run('simulate', hairGlb, '--metadata', hairMetadata, '--frames', '30', '--fps', '30', '--drive', 'sway');
    assert.equal(code, 0, stderr);
    const lines = stdout.trim().split('\n').map((line) => JSON.parse(line));
    assert.equal(lines.length, 30);
    assert.deepEqual(lines.map((l) => l.frame), Array.from({ length: 30 }, (_, i) => i + 1));
    assert.equal(lines[29].t, 1);
    for (const l of lines) assert.equal(l.rotations.length, 4 * joints);
    assert.notDeepEqual(lines[29].rotations, lines[0].rotations);
  });

  test('without --drive the drivers stay at rest; the output is the same on every run', () => {
    const a = run('simulate', hairGlb, '--metadata', hairMetadata, '--frames', '5');
    const b = run('simulate', hairGlb, '--metadata', hairMetadata, '--frames', '5');
    assert.equal(a.code, 0);
    assert.equal(a.stdout, b.stdout);
    assert.equal(a.stdout.trim().split('\n').length, 5);
  });
});

describe('.vrm avatars', () => {
  const vrm0 = join(fixturesDir, 'vrm0_springs.vrm');
  const vrm1 = join(fixturesDir, 'vrm10_springs.vrm');

  test('inspect reads the VRM\'s own springs and lists its colliders; virtual tails are named so', () => {
    const { code, stdout, stderr } = run('inspect', vrm0);
    assert.equal(code, 0, stderr);
    assert.match(stdout, /springs: VRM, vrm0/);
    assert.match(stdout, /-> \(virtual tail\)/);
    assert.match(stdout, /colliders \(\d+\):\n {2}sphere on J_Head: offset \[/);
    const json = JSON.parse(run('inspect', vrm1, '--json').stdout);
    assert.equal(json.format, 'vrmc-springbone');
    assert.ok(json.colliders.some((c) => c.shape === 'capsule'));
  });

  test('simulate needs no metadata for a .vrm; metadata options are usage errors', () => {
    const { code, stdout, stderr } = run('simulate', vrm1, '--frames', '3', '--drive', 'sway');
    assert.equal(code, 0, stderr);
    const lines = stdout.trim().split('\n').map((l) => JSON.parse(l));
    assert.equal(lines.length, 3);
    assert.ok(lines[2].rotations.every(Number.isFinite));
    for (const option of ['--metadata', '--hash', '--body-shape']) {
      const usage = run('simulate', vrm1, option, 'x');
      assert.equal(usage.code, 2, option);
      assert.match(usage.stderr, /does not apply to a VRM avatar: vrm10_springs\.vrm carries its own spring bones \(VRMC_springBone\)/);
    }
  });

  // What a file is comes from its content: a VRM keeps its springs under any name, and a wearable
  // named .vrm is still a wearable.
  for (const [fixtureName, name, format, extension] of [
    ['vrm0_springs.vrm', 'avatar.glb', 'vrm0', 'VRM 0.x secondaryAnimation'],
    ['vrm10_springs.vrm', 'avatar.gltf', 'vrmc-springbone', 'VRMC_springBone'],
    ['vrm10_springs.vrm', 'avatar.glb', 'vrmc-springbone', 'VRMC_springBone'],
    ['vrm0_springs.vrm', 'avatar.gltf', 'vrm0', 'VRM 0.x secondaryAnimation'],
  ]) {
    test(`${fixtureName} renamed ${name} is read as a VRM avatar`, () => {
      const original = join(fixturesDir, fixtureName);
      const renamed = join(scratch, `${format}_${name}`);
      copyFileSync(original, renamed);
      const expected = JSON.parse(run('inspect', original, '--json').stdout);
      assert.ok(expected.joints.length > 0);
      const { code, stdout, stderr } = run('inspect', renamed, '--json');
      assert.equal(code, 0, stderr);
      assert.equal(stderr, '');
      const data = JSON.parse(stdout);
      assert.equal(data.format, format);
      assert.deepEqual(data.joints, expected.joints);
      assert.match(run('inspect', renamed).stdout, new RegExp(`springs: VRM, ${format}`));
      const simulated = run('simulate', renamed, '--frames', '3', '--drive', 'sway');
      assert.equal(simulated.code, 0, simulated.stderr);
      assert.equal(simulated.stdout, run('simulate', original, '--frames', '3', '--drive', 'sway').stdout);
      const usage = run('inspect', renamed, '--metadata', hairMetadata);
      assert.equal(usage.code, 2);
      assert.ok(usage.stderr.includes(`--metadata does not apply to a VRM avatar: ${format}_${name} carries its own spring bones (${extension})`), usage.stderr);
    });
  }

  test('a .vrm without VRM spring bones is read as a wearable, with a note saying so', () => {
    const renamed = join(scratch, 'hair.vrm');
    copyFileSync(hairGlb, renamed);
    const withMetadata = run('inspect', renamed, '--metadata', hairMetadata);
    assert.equal(withMetadata.code, 0, withMetadata.stderr);
    assert.equal(withMetadata.stdout.replace('hair.vrm', 'avatar_hair.glb'), run('inspect', hairGlb, '--metadata', hairMetadata).stdout);
    assert.match(withMetadata.stderr, /note: hair\.vrm has no VRM spring bones \(neither VRMC_springBone nor VRM 0\.x secondaryAnimation\): read as a wearable\n/);
    assert.doesNotMatch(withMetadata.stderr, /pass --metadata/);
    const bare = run('inspect', renamed);
    assert.equal(bare.code, 0);
    assert.match(bare.stdout, /chains \(0\):/);
    assert.match(bare.stderr, /read as a wearable\n.*no springBones metadata given: pass --metadata/);
    const simulated = run('simulate', renamed, '--frames', '2');
    assert.equal(simulated.code, 2);
    assert.match(simulated.stderr, /read as a wearable; no springBones metadata given: pass --metadata/);
  });
});

describe('simulate --integrator', () => {
  test('xpbd runs another integrator than the default; a bad name is a usage error', () => {
    const args = ['simulate', hairGlb, '--metadata', hairMetadata, '--frames', '10', '--drive', 'sway'];
    const vrm = run(...args);
    const xpbd = run(...args, '--integrator', 'xpbd');
    assert.equal(xpbd.code, 0, xpbd.stderr);
    assert.equal(run(...args, '--integrator', 'vrm').stdout, vrm.stdout);
    assert.notEqual(xpbd.stdout, vrm.stdout);
    assert.equal(xpbd.stdout.trim().split('\n').length, 10);
    assert.equal(run(...args, '--integrator', 'pbd').code, 2);
  });
});

describe('hash', () => {
  test('prints the content hash @dcl/hashing gives each fixture', () => {
    for (const name of ['avatar_hair.glb', 'adr_example.gltf', 'adr_example_posed.glb']) {
      const { code, stdout, stderr } = run('hash', join(fixturesDir, name));
      assert.equal(code, 0, stderr);
      assert.equal(stdout, `${contentHashOf(name)}\n`);
    }
    const empty = join(scratch, 'empty.bin');
    writeFileSync(empty, '');
    assert.equal(run('hash', empty).stdout, 'bafkreihdwdcefgh4dqkjv67uzcmw7ojee6xedzdetojuzjevtenxquvyku\n');
  });

  test('exit codes: 1 for a missing file, 2 without exactly one file', () => {
    const missing = run('hash', join(scratch, 'missing.bin'));
    assert.equal(missing.code, 1);
    assert.match(missing.stderr, /cannot read .*missing\.bin: ENOENT/);
    assert.equal(run('hash').code, 2);
    assert.equal(run('hash', hairGlb, hairGlb).code, 2);
    assert.equal(run('hash', hairGlb, '--json').code, 2);
  });
});

describe('validate', () => {
  const springBones = JSON.parse(fixture('avatar_hair.metadata.json'));
  const hash = Object.keys(springBones.models)[0];
  // The fixture also exercises the runtime's tolerance of a bone without the naming token, which a
  // catalyst rejects: leave it out here.
  for (const bone of Object.keys(springBones.models[hash])) {
    if (!/springbone/i.test(bone)) delete springBones.models[hash][bone];
  }
  const entityWith = (bones) => ({
    type: 'wearable',
    content: [{ file: 'hair.glb', hash }],
    metadata: { data: { representations: [{ bodyShapes: ['urn:decentraland:off-chain:base-avatars:BaseMale'], mainFile: 'hair.glb', contents: ['hair.glb'] }], springBones: bones } },
  });
  const write = (name, value) => {
    const path = join(scratch, name);
    writeFileSync(path, typeof value === 'string' ? value : JSON.stringify(value));
    return path;
  };

  test('0 and "valid" for an entity the catalyst accepts (also a Builder item, and no springBones)', () => {
    for (const [name, entity] of [
      ['valid.json', entityWith(springBones)],
      ['no_bones.json', entityWith(null)],
      ['item.json', { contents: { 'hair.glb': hash }, data: { representations: [{ bodyShapes: ['BaseMale'], mainFile: 'hair.glb' }], springBones } }],
    ]) {
      const { code, stdout, stderr } = run('validate', write(name, entity));
      assert.equal(code, 0, stderr + stdout);
      assert.match(stdout, /: valid\n$/);
    }
  });

  test('1 with every error listed with its JSON path', () => {
    const bad = structuredClone(springBones);
    bad.models[hash].SpringBone_hair_left.drag = 1.5;
    bad.models[hash].SpringBone_hair_left.stiffness = -1;
    const path = write('invalid.json', entityWith(bad));
    const { code, stdout } = run('validate', path);
    assert.equal(code, 1);
    assert.match(stdout, /: 2 errors\n/);
    // Each path once: the line starts with it, and the message after it does not repeat it.
    assert.ok(stdout.includes(`  /models/${hash}/SpringBone_hair_left/drag: must be <= 1\n`), stdout);
    assert.equal(stdout.split(`/models/${hash}/SpringBone_hair_left/drag`).length, 2, stdout);
    assert.ok(stdout.includes(`/models/${hash}/SpringBone_hair_left/stiffness: `));
    const stale = structuredClone(springBones);
    stale.models.QmStale = { Hair_001: springBones.models[hash].SpringBone_hair_left };
    const json = run('validate', write('stale.json', entityWith(stale)), '--json');
    assert.equal(json.code, 1);
    const report = JSON.parse(json.stdout);
    assert.equal(report.valid, false);
    assert.deepEqual(report.errors.map((e) => e.path), ['/models/QmStale', '/models/QmStale/Hair_001']);
  });

  test('exit codes: 1 for unreadable input, 2 for usage errors', () => {
    for (const [args, message] of [
      [['validate', join(scratch, 'missing.json')], /cannot read/],
      [['validate', write('broken.json', '{"content": [')], /not JSON/],
      [['validate', write('bones_only.json', springBones)], /not an entity or item/],
      [['validate', write('array.json', '[]')], /not an entity or item/],
    ]) {
      const { code, stderr } = run(...args);
      assert.equal(code, 1, `${args.join(' ')}: ${stderr}`);
      assert.match(stderr, message);
    }
    assert.equal(run('validate').code, 2);
    assert.equal(run('validate', 'a.json', 'b.json').code, 2);
    assert.equal(run('validate', 'a.json', '--metadata', 'x').code, 2);
  });
});

describe('exit codes', () => {
  const usage = (...args) => {
    const { code, stderr } = run(...args);
    assert.equal(code, 2, `${args.join(' ')}: ${stderr}`);
    assert.match(stderr, /usage: springbones <command>/);
  };
  test('2 for usage errors, with the usage text', () => {
    usage();
    usage('frobnicate');
    usage('inspect');
    usage('inspect', hairGlb, 'extra.glb');
    usage('inspect', hairGlb, '--bogus');
    usage('simulate', hairGlb);  // a wearable without springBones metadata has nothing to simulate
    assert.match(run('simulate', hairGlb).stderr, /springbones: no springBones metadata given: pass --metadata/);
    usage('simulate', hairGlb, '--metadata', hairMetadata, '--frames', '-1');
    usage('simulate', hairGlb, '--metadata', hairMetadata, '--frames', '2.5');
    usage('simulate', hairGlb, '--metadata', hairMetadata, '--fps', '0');
    usage('simulate', hairGlb, '--metadata', hairMetadata, '--fps', 'fast');
    usage('simulate', hairGlb, '--metadata', hairMetadata, '--fps', '5e-324');  // 1/F is Infinity
    assert.match(run('simulate', hairGlb, '--metadata', hairMetadata, '--fps', '5e-324').stderr,
                 /springbones: --fps 5e-324 gives a frame time of Infinity s\n/);
    usage('simulate', hairGlb, '--metadata', hairMetadata, '--drive', 'spin');
    usage('simulate', hairGlb, '--metadata', hairMetadata, '--step-hz', '5000');
    usage('simulate', hairGlb, '--metadata', hairMetadata, '--max-substeps', '0');
    usage('inspect', hairGlb, '--hash', 'h', '--body-shape', 'BaseMale');
    usage('inspect', hairGlb, '--metadata', hairMetadata, '--body-shape', 'BaseMale');
  });

  test('a typo gets our words: the option, the nearest known one and the command\'s synopsis', () => {
    const typo = run('validate', 'a.json', '--jsn');
    assert.equal(typo.code, 2);
    assert.match(typo.stderr, /^springbones: unknown option '--jsn' for validate \(did you mean --json\?\); validate takes: validate <entity\.json> \[--json\]\n/);
    assert.match(typo.stderr, /usage: springbones <command>/);
    assert.doesNotMatch(typo.stderr, /To specify a positional argument/);  // parseArgs' own advice
    const missing = run('simulate', hairGlb, '--metadata');
    assert.equal(missing.code, 2);
    assert.match(missing.stderr, /^springbones: --metadata needs a value; simulate takes: simulate <glb>/);
    const flagValue = run('inspect', hairGlb, '--json=yes');
    assert.equal(flagValue.code, 2);
    assert.match(flagValue.stderr, /^springbones: --json takes no value; inspect takes: inspect <glb>/);
  });

  test('0 and the usage on stdout for help', () => {
    const { code, stdout } = run('help');
    assert.equal(code, 0);
    assert.match(stdout, /inspect <glb>/);
    assert.match(stdout, /simulate <glb>/);
    assert.match(stdout, /validate <entity\.json>/);
    assert.match(stdout, /hash <file>/);
  });

  test('1 for inputs that cannot be loaded, with the error code', () => {
    const notJson = join(scratch, 'not.json');
    writeFileSync(notJson, '{"version": 1, ');
    const png = join(scratch, 'image.png');
    writeFileSync(png, Buffer.from([0x89, 0x50, 0x4e, 0x47, 13, 10, 26, 10, 0, 0, 0, 13]));
    const badModels = join(scratch, 'bad_models.json');
    writeFileSync(badModels, '{"version": 1, "models": []}');
    for (const [args, message] of [
      [['inspect', join(scratch, 'missing.glb')], /cannot read .*missing\.glb: ENOENT/],
      [['inspect', hairGlb, '--metadata', join(scratch, 'missing.json')], /cannot read/],
      [['inspect', join(fixturesDir, 'cycle.gltf')], /hierarchy-cycle/],
      [['inspect', png], /glb-bad-magic/],
      [['inspect', hairMetadata], /gltf-invalid/],
      [['inspect', hairGlb, '--metadata', notJson], /not JSON/],
      [['simulate', hairGlb, '--metadata', badModels], /metadata-invalid: .*\(at \/models\)/],
    ]) {
      const { code, stderr } = run(...args);
      assert.equal(code, 1, `${args.join(' ')}: ${stderr}`);
      assert.match(stderr, message);
    }
  });
});

describe('input files are bounded and must be what they say', () => {
  test('a device or a folder is refused before it is read, by every command and --metadata', () => {
    for (const args of [['hash', '/dev/zero'], ['inspect', '/dev/zero'], ['validate', '/dev/zero'],
      ['simulate', '/dev/zero', '--metadata', hairMetadata], ['inspect', hairGlb, '--metadata', '/dev/zero'],
      ['hash', scratch]]) {
      const { code, stderr } = run(...args);
      assert.equal(code, 1, `${args.join(' ')}: ${stderr}`);
      assert.match(stderr, /cannot read \S+: not a regular file\n/, args.join(' '));
    }
  });

  test('a JSON file past 16 MiB is refused by its size, before it is read', () => {
    const big = join(scratch, 'big.json');
    writeFileSync(big, '');
    truncateSync(big, (16 << 20) + 1);  // sparse: no 16 MiB written
    const { code, stderr } = run('validate', big);
    assert.equal(code, 1);
    assert.match(stderr, /16777217 bytes, more than the limit of 16777216/);
  });

  test('a JSON file that is not UTF-8 is refused, naming the offset, not read with U+FFFD', () => {
    const springBones = fixture('avatar_hair.metadata.json');
    const at = springBones.indexOf('SpringBone_hair_left');
    const bad = Buffer.concat([springBones.subarray(0, at), Buffer.from([0xff]), springBones.subarray(at)]);
    const path = join(scratch, 'latin1.json');
    writeFileSync(path, bad);
    for (const args of [['inspect', hairGlb, '--metadata', path], ['validate', path]]) {
      const { code, stderr } = run(...args);
      assert.equal(code, 1, args.join(' '));
      assert.match(stderr, new RegExp(`latin1\\.json: not UTF-8 \\(an invalid byte at offset ${at}\\)`));
    }
    // An overlong encoding and a surrogate are not UTF-8 either.
    for (const bytes of [[0xc0, 0xaf], [0xed, 0xa0, 0x80]]) {
      writeFileSync(path, Buffer.from([0x7b, 0x22, ...bytes, 0x22, 0x3a, 0x31, 0x7d]));
      assert.match(run('validate', path).stderr, /not UTF-8 \(an invalid byte at offset 2\)/);
    }
  });
});

test('splitMetadata: springBones itself, an entity, a wearable metadata, a Builder item', () => {
  const springBones = { version: 1, models: {} };
  assert.deepEqual(splitMetadata(springBones), { springBones, entity: undefined });
  const entity = { content: [], metadata: { data: { springBones } } };
  assert.deepEqual(splitMetadata(entity), { springBones, entity });
  const wearable = { id: 'urn:x', data: { representations: [], springBones } };
  assert.deepEqual(splitMetadata(wearable), { springBones, entity: wearable });
  const withoutBones = { metadata: { data: { representations: [] } } };
  assert.deepEqual(splitMetadata(withoutBones), { springBones: null, entity: withoutBones });
  assert.deepEqual(splitMetadata(null), { springBones: null, entity: undefined });
});
