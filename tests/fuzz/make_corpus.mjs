// Writes the seed corpora of the fuzz targets (tests/fuzz/corpus/<target>/) from tests/fixtures.
// Deterministic: running it again gives the same files. Usage: node tests/fuzz/make_corpus.mjs
//   glb_metadata/  fixture GLB/glTF + "\n@@springBones@@\n" + metadata text, GLBs without their
//                  BIN chunk (the loader never reads it), and a few broken containers
//   metadata/      the fixture metadata plus one input per distinct outcome of the validator's
//                  differential cases (tests/fixtures/validation_cases.json), at most 48
//   simulation/    pseudo-random byte programs (the target builds everything from bytes)
//   vrm/           the VRM fixtures (0.x, 1.0, 1.0 with extended colliders), both extensions in one file, glTF text
//   typed/         typed input (web/typed_value.js) of the fixtures' glTF documents, metadata, the
//                  sample's entity and rig options, a few malformed encodings, and inputs at and
//                  past the bounds of src/common/typed_encoding.json
import { mkdirSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { glbOfJson, jsonChunkOf } from '../../scripts/lib/fixtures/glb.mjs';
import { kTypedLimits, kTypedTags } from '../../web/typed_encoding.js';
import { encodeGltf, encodeTyped } from '../../web/typed_value.js';

const here = dirname(fileURLToPath(import.meta.url));
const fixtures = join(here, '..', 'fixtures');
const corpus = join(here, 'corpus');
const separator = Buffer.from('\n@@springBones@@\n');

function reset(target) {
  const dir = join(corpus, target);
  rmSync(dir, { recursive: true, force: true });
  mkdirSync(dir, { recursive: true });
  return dir;
}

// A GLB holding only the JSON chunk of `glb`, with the same JSON.
const withoutBin = (glb) => glbOfJson(jsonChunkOf(glb));

const fixture = (name) => readFileSync(join(fixtures, name));
const compact = (name) => Buffer.from(JSON.stringify(JSON.parse(fixture(name).toString())));

// --- glb_metadata
{
  const dir = reset('glb_metadata');
  const adrMeta = compact('adr_example.metadata.json');
  const hairMeta = compact('avatar_hair.metadata.json');
  const seeds = {
    adr_example_glb: [fixture('adr_example.glb'), adrMeta],
    adr_example_gltf: [fixture('adr_example.gltf'), adrMeta],
    adr_example_posed_glb: [fixture('adr_example_posed.glb'), adrMeta],
    avatar_hair_glb: [withoutBin(fixture('avatar_hair.glb')), hairMeta],
    cycle_gltf: [fixture('cycle.gltf'), adrMeta],
    two_parents_gltf: [fixture('two_parents.gltf'), adrMeta],
    adr_example_no_metadata: [fixture('adr_example.glb'), null],
    matrix_node_glb: [
      glbOfJson(JSON.stringify({
        asset: { version: '2.0' },
        nodes: [
          { name: 'Avatar_Hips', children: [1], matrix: [0, 2, 0, 0, -3, 0, 0, 0, 0, 0, 4, 0, 1, 2, 3, 1] },
          { name: 'springbone_a', children: [2], scale: [1, 1, 1], rotation: [0, 0, 0.7071068, 0.7071068] },
          { name: 'springbone_a_tip', translation: [0, 0.1, 0] },
        ],
      })),
      Buffer.from(JSON.stringify({
        version: 1,
        models: { h: { springbone_a: { stiffness: 1, gravityPower: 1, gravityDir: [0, -1, 0], drag: 0.4, isRoot: true, center: 'Avatar_Hips' } } },
      })),
    ],
    truncated_header: [fixture('adr_example.glb').subarray(0, 16), null],
    // What JSON.parse and a byte-level JSON library read differently (docs/input.md, "Bytes are
    // read as the page reads them"): the reader's own grammar, UTF-8 decoding and number rules.
    page_unread_members: [glbOfJson('{"asset":{"version":"2.0"},"nodes":[{"name":"a","rotation":[-0,0,0,1]}],' +
      '"accessors":[{"max":[1e400]}],"meshes":[{"name":"\\ud800"}]}'), null],
    page_ill_formed_utf8: [glbOfJson(Buffer.concat([Buffer.from('{"asset":{"version":"2.0"},"nodes":[{"name":"'),
      Buffer.from([0xff, 0xe2, 0x82, 0xed, 0xa0, 0x80]), Buffer.from('"}]}')])), null],
    page_nul_padding: [glbOfJson(Buffer.concat([Buffer.from('{"asset":{"version":"2.0"},"nodes":[]}'), Buffer.from([0, 0x67])])), null],
  };
  for (const [name, [glb, meta]] of Object.entries(seeds)) {
    writeFileSync(join(dir, name), meta ? Buffer.concat([glb, separator, meta]) : glb);
  }
}

// --- vrm
{
  const dir = reset('vrm');
  for (const name of ['vrm0_springs.vrm', 'vrm10_springs.vrm', 'vrm10_extended_colliders.vrm']) {
    const vrm = fixture(name);
    writeFileSync(join(dir, name.replace('.vrm', '')), vrm.length > 20 + vrm.readUInt32LE(12) ? withoutBin(vrm) : vrm);
  }
  // Both extensions in one document, and the 1.0 one alone as glTF text.
  const gltf = (name) => JSON.parse(fixture(name).subarray(20, 20 + fixture(name).readUInt32LE(12)).toString());
  const v0 = gltf('vrm0_springs.vrm');
  const v1 = gltf('vrm10_springs.vrm');
  writeFileSync(join(dir, 'both_extensions'), glbOfJson(JSON.stringify({ ...v1, extensions: { ...v0.extensions, ...v1.extensions } })));
  writeFileSync(join(dir, 'vrm10_text'), JSON.stringify(v1));
}

// --- metadata
{
  const dir = reset('metadata');
  writeFileSync(join(dir, 'adr_example'), fixture('adr_example.metadata.json'));
  writeFileSync(join(dir, 'avatar_hair'), fixture('avatar_hair.metadata.json'));
  const cases = JSON.parse(fixture('validation_cases.json').toString());
  const seen = new Set();
  let written = 0;
  for (const c of cases) {
    const key = c.valid ? 'valid' : c.errors.map((e) => String(e).replace(/\/models\/[^/ ]*/, '/models/*')).join('|');
    if (seen.has(key) || written >= 48 || c.input === undefined) continue;
    seen.add(key);
    writeFileSync(join(dir, `case_${String(written).padStart(2, '0')}`), JSON.stringify(c.input));
    written += 1;
  }
}

// --- simulation
{
  const dir = reset('simulation');
  let state = 0x2545f491;
  const next = () => {
    state = (Math.imul(state, 1103515245) + 12345) >>> 0;
    return state >>> 16;
  };
  for (let i = 0; i < 16; i += 1) {
    const bytes = Buffer.alloc(64 << (i % 6));
    for (let k = 0; k < bytes.length; k += 1) bytes[k] = next() & 0xff;
    writeFileSync(join(dir, `random_${String(i).padStart(2, '0')}`), bytes);
  }
}

// --- entity: the sample's entity, recorded validation cases as entities and as Builder items,
// and the shapes the validator must refuse
{
  const dir = reset('entity');
  const sample = readFileSync(join(here, '..', '..', 'web', 'demo', 'assets', 'hair_wearable.entity.json'));
  writeFileSync(join(dir, 'sample_entity'), Buffer.from(JSON.stringify(JSON.parse(sample.toString()))));
  const cases = JSON.parse(fixture('validation_cases.json').toString());
  const picked = cases.filter((c, i) => i % 40 === 0 && c.input !== undefined).slice(0, 24);
  picked.forEach((c, i) => {
    const n = String(i).padStart(2, '0');
    const data = { representations: c.representations, springBones: c.input };
    writeFileSync(join(dir, `case_${n}_entity`), JSON.stringify({ content: c.content, metadata: { data } }));
    writeFileSync(join(dir, `case_${n}_item`), JSON.stringify({ contents: c.contents, data }));
  });
  const refused = ['{}', '[]', '{"metadata":{}}', '{"metadata":{"data":null}}', '{"data":{"springBones":null}}',
    '{"contents":[],"data":{"representations":[{"mainFile":"a.glb","bodyShapes":["BaseMale"]}]}}',
    '{"content":{"a.glb":"Qm"},"metadata":{"data":{"representations":[{"mainFile":"a.glb","bodyShapes":["BaseMale"]}]}}}'];
  refused.forEach((text, i) => writeFileSync(join(dir, `shape_${String(i).padStart(2, '0')}`), text));
}

// --- typed: what a page's parse becomes, for every typed entry point
{
  const dir = reset('typed');
  const gltfOf = (name) => (name.endsWith('.gltf') ? JSON.parse(fixture(name).toString()) : JSON.parse(jsonChunkOf(fixture(name)).toString()));
  for (const name of ['adr_example.glb', 'avatar_hair.glb', 'two_parents.gltf', 'cycle.gltf']) {
    writeFileSync(join(dir, `gltf_${name.replace('.', '_')}`), encodeGltf('corpus', gltfOf(name), false));
  }
  for (const name of ['vrm0_springs.vrm', 'vrm10_springs.vrm', 'vrm10_extended_colliders.vrm']) {
    writeFileSync(join(dir, `vrm_${name.replace('.', '_')}`), encodeGltf('corpus', gltfOf(name), true));
  }
  for (const name of ['adr_example.metadata.json', 'avatar_hair.metadata.json']) {
    writeFileSync(join(dir, `metadata_${name.replace(/\./g, '_')}`), encodeTyped('corpus', JSON.parse(fixture(name).toString())));
  }
  const sample = readFileSync(join(here, '..', '..', 'web', 'demo', 'assets', 'hair_wearable.entity.json'));
  writeFileSync(join(dir, 'entity_sample'), encodeTyped('corpus', JSON.parse(sample.toString())));
  writeFileSync(join(dir, 'options_colliders'), encodeTyped('corpus',
    { colliders: [{ node: 'Avatar_Head', offset: [0, 9, 0], radius: 9.5 }, { node: 'Avatar_Neck', offset: [0, 0, 0], tail: [0, 5, 0], radius: 4 }], hitRadius: 0.01 }));
  writeFileSync(join(dir, 'options_preset'), encodeTyped('corpus', { preset: 'dcl-body' }));
  const malformed = [[7], [5, 255, 255, 255, 255], [6, 1, 0, 0, 0, 9, 0, 0, 0], [3, 0, 0], [4, 3, 0, 0, 0, 0xff, 0xfe, 0x80], [0, 0]];
  malformed.forEach((bytes, i) => writeFileSync(join(dir, `malformed_${String(i).padStart(2, '0')}`), Buffer.from(bytes)));
  // The bounds of typed_encoding.json, reached: written by hand, as the encoder refuses them.
  const u32 = (v) => Buffer.from(new Uint32Array([v]).buffer);
  const sized = (text) => Buffer.concat([u32(Buffer.byteLength(text)), Buffer.from(text)]);
  const { tags, limits } = { tags: kTypedTags, limits: kTypedLimits };
  const gltfNamed = (name) => Buffer.concat([Buffer.from([tags.object]), u32(2), sized('asset'), Buffer.from([tags.object]), u32(1),
    sized('version'), Buffer.from([tags.string]), sized('2.0'), sized('nodes'), Buffer.from([tags.array]), u32(1),
    Buffer.from([tags.object]), u32(1), sized('name'), Buffer.from([tags.string]), sized(name)]);
  writeFileSync(join(dir, 'bound_string_at_limit'), gltfNamed('n'.repeat(limits.maxStringBytes)));
  writeFileSync(join(dir, 'bound_string_past_limit'), gltfNamed('n'.repeat(limits.maxStringBytes + 1)));
  writeFileSync(join(dir, 'bound_key_past_limit'), Buffer.concat([Buffer.from([tags.object]), u32(1),
    sized('k'.repeat(limits.maxStringBytes + 1)), Buffer.from([tags.null])]));
  writeFileSync(join(dir, 'bound_container_past_limit'), Buffer.concat([Buffer.from([tags.object]), u32(1), sized('nodes'),
    Buffer.from([tags.array]), u32(limits.maxContainerSize + 1)]));
}
