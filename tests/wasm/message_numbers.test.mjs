// The runtime module writes no number in decimal: its messages carry placeholders that
// web/message_numbers.js writes, and its typed values carry floats and doubles that
// web/typed_output.js turns into the numbers the JSON text of before gave. Held here against what
// C++'s printf writes: libc's printf through printf(1) (the same conversions on the same exact
// binary values; it reads a hex float exactly), and the creator-tools module, which keeps
// snprintf, for the messages themselves.
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { test } from 'node:test';

import { createSpringBones } from '../../web/springbones.js';
import { formatNumber, messageText } from '../../web/message_numbers.js';
import { instantiateModule } from '../../web/module_loader.js';
import { decodeTyped, doubleNumber, floatNumber } from '../../web/typed_output.js';
import { kTypedTags } from '../../web/typed_encoding.js';
import { withBytes, withRoomForStrings } from '../../web/wasm_memory.js';
import { springRig } from './helpers.mjs';

const bits = new DataView(new ArrayBuffer(8));

/** x as C's hex float literal, which printf(1) reads exactly. */
function hexFloat(x) {
  if (Number.isNaN(x)) return 'nan';
  if (!Number.isFinite(x)) return x > 0 ? 'inf' : '-inf';
  bits.setFloat64(0, x);
  const word = bits.getBigUint64(0);
  const sign = word >> 63n ? '-' : '';
  const biased = Number((word >> 52n) & 0x7ffn);
  const mantissa = (word & 0xfffffffffffffn).toString(16).padStart(13, '0');
  return biased === 0 ? `${sign}0x0.${mantissa}p-1022` : `${sign}0x1.${mantissa}p${biased - 1023}`;
}

/** printf(1)'s text of each value in `format` (one conversion). */
function printf(format, values) {
  const out = [];
  for (let i = 0; i < values.length; i += 500) {
    const chunk = values.slice(i, i + 500);
    out.push(...execFileSync('printf', [`${format}\\n`, ...chunk.map(hexFloat)], { encoding: 'utf8' }).split('\n').slice(0, chunk.length));
  }
  return out;
}

// A seeded generator (xorshift32), so that a failure names values that come back.
function generator(seed) {
  let s = seed >>> 0 || 1;
  return () => {
    s ^= s << 13;
    s >>>= 0;
    s ^= s >>> 17;
    s ^= s << 5;
    s >>>= 0;
    return s;
  };
}

/** Random doubles (any bits), random floats, and the edges: zeros, subnormals, extremes, ties. */
function sampleValues() {
  const next = generator(20261129);
  const values = [0, -0, 1, -1, 0.1, 0.5, 2.5, 1e-7, 1e15, 1e16, 1e21, 1e22, 1e23, 123456789, 1e38, -1e38,
    3.4028234663852886e38, 1.1754943508222875e-38, 1.401298464324817e-45, 5e-324, 2.2250738585072014e-308,
    1.7976931348623157e308, 2097152.25, 1234565, 1234575, 12345665, 0.000123456, 999999.5, 9999995, 0.15, 0.25,
    562949953421312.5, 4503599627370495.5, 1e-5, 1e-4, 9.9999995e-5, 65504.5, 16777217];
  for (let i = 0; i < 400; ++i) {
    bits.setUint32(0, next());
    bits.setUint32(4, next());
    const x = bits.getFloat64(0);
    if (Number.isFinite(x)) values.push(x);
    bits.setUint32(0, next());
    const f = bits.getFloat32(0);
    if (Number.isFinite(f)) values.push(f);
    values.push(Math.fround((next() / 2 ** 32) * 10 ** ((next() % 20) - 10)));
    values.push((next() % 2000000) / 8 - 125000);  // exact binary fractions: printf's ties
  }
  return values;
}

test('numbers are written as printf writes them: %.6g, %.7g, %.15g and %f, ties to even', () => {
  const values = [...sampleValues(), NaN, Infinity, -Infinity];
  for (const [format, conversion, precision] of [['%.6g', 'g', 6], ['%.7g', 'g', 7], ['%.15g', 'g', 15], ['%f', 'f', 6]]) {
    const expected = printf(format, values);
    values.forEach((x, i) => assert.equal(formatNumber(x, conversion, precision), expected[i], `${format} of ${hexFloat(x)}`));
  }
  // 't': %f without trailing zeros, as C++ trims it (src/common/message_number.cpp).
  const fixed = printf('%f', values);
  values.forEach((x, i) => {
    const trimmed = fixed[i].replace(/0+$/, '').replace(/\.$/, '');
    assert.equal(formatNumber(x, 't', 6), trimmed, `%f trimmed of ${hexFloat(x)}`);
  });
});

// The float rule of the JSON text before (src/common/json_text.cpp, appendShortest): the first of
// %.1g ... %.9g whose text its own reader, exact for a decimal exponent within +-22, read back as
// the same float; 9 digits when none did. Its reader, ported.
function readsBackAs(text, f) {
  const match = /^(-?)(\d+)(?:\.(\d*))?(?:e([-+]\d+))?$/.exec(text);
  const digits = match[2] + (match[3] ?? '');
  const exponent = Number(match[4] ?? 0) - (match[3] ?? '').length;
  if (exponent < -22 || exponent > 22) return false;
  return Math.fround(Number(`${match[1]}${digits}e${exponent}`)) === f;
}

test('floats come out as the shortest text C++ wrote for them, doubles as their %.15g', () => {
  const floats = [...new Set(sampleValues().map(Math.fround))].filter(Number.isFinite);
  const texts = [];
  for (let d = 1; d <= 9; ++d) texts.push(printf(`%.${d}g`, floats));
  floats.forEach((f, i) => {
    let expected;
    if (Number.isInteger(f) && Math.abs(f) < 1e15) {
      expected = Number(String(f));
    } else {
      let d = 0;
      while (d < 8 && !readsBackAs(texts[d][i], f)) ++d;
      expected = JSON.parse(texts[d][i]);
    }
    assert.ok(Object.is(floatNumber(f), expected), `float ${hexFloat(f)}: ${floatNumber(f)} against ${expected}`);
  });
  const doubles = sampleValues();
  const fifteen = printf('%.15g', doubles);
  doubles.forEach((x, i) => {
    const expected = Number.isInteger(x) && Math.abs(x) < 1e15 ? Number(String(x)) : JSON.parse(fifteen[i]);
    assert.ok(Object.is(doubleNumber(x), expected), `double ${hexFloat(x)}: ${doubleNumber(x)} against ${expected}`);
  });
});

// The C++ writer (TypedWriter) and this decoder: each tag once, through the runtime module.
test('the typed values of the runtime decode: every tag, the float one and non-finite numbers included', async () => {
  const sb = await createSpringBones();
  const { glb, springBones, hash } = springRig({ chains: 1, joints: 2 });
  const rig = sb.loadRig(glb, springBones, { contentHash: hash, colliders: [{ node: 'Avatar_Head', radius: 0.1, inside: true }, { node: 'Avatar_Head', radius: 0.2 }] });
  const seen = new Set();
  const walk = (v) => {
    if (v === null) seen.add('null');
    else if (v === true || v === false) seen.add(String(v));
    else if (typeof v === 'number') seen.add('number');
    else if (typeof v === 'string') seen.add('string');
    else if (Array.isArray(v)) {
      seen.add('array');
      v.forEach(walk);
    } else {
      seen.add('object');
      Object.values(v).forEach(walk);
    }
  };
  walk({ joints: rig.joints, colliders: rig.colliders, chains: rig.chains, drivers: rig.drivers });
  assert.deepEqual([...seen].sort(), ['array', 'false', 'null', 'number', 'object', 'string', 'true']);
  assert.equal(rig.joints[0].params.drag, 0.4);  // a float: 0.4f, not 0.4000000059604645
  assert.equal(rig.colliders[0].radius, 0.1);
  // The tags by hand: a float, non-finite doubles and floats, a message with a number in it.
  const f32 = new DataView(new ArrayBuffer(4));
  const bytes = [kTypedTags.array, 6, 0, 0, 0];
  for (const [tag, value] of [[kTypedTags.float, 0.3], [kTypedTags.float, -Infinity], [kTypedTags.number, NaN],
    [kTypedTags.number, Infinity], [kTypedTags.number, 0.1 + 0.2]]) {
    bytes.push(tag);
    if (tag === kTypedTags.float) {
      f32.setFloat32(0, value, true);
      bytes.push(...new Uint8Array(f32.buffer));
    } else {
      bits.setFloat64(0, value, true);
      bytes.push(...new Uint8Array(bits.buffer));
    }
  }
  bits.setFloat64(0, 2.5);
  const placeholder = [0xff, 0x67, 0x30, 0x37, ...new TextEncoder().encode(bits.getBigUint64(0).toString(16).padStart(16, '0'))];
  const message = [...new TextEncoder().encode('using '), ...placeholder];
  bytes.push(kTypedTags.string, message.length, 0, 0, 0, ...message);
  const decoded = decodeTyped(new Uint8Array(bytes));
  assert.deepEqual(decoded, [0.3, -Infinity, NaN, Infinity, 0.3, 'using 2.5']);
  assert.equal(messageText(new Uint8Array(message)), 'using 2.5');
});

// The same warnings from the runtime (placeholders written here) and from the creator tools
// (snprintf), for values that put every kind of number into them: quoted doubles, %f defaults and
// bounds, and quotes cut at 60 bytes with numbers inside.
test("the runtime's messages read as the creator tools' (snprintf) write them", async () => {
  const sb = await createSpringBones();
  const tools = await instantiateModule('test', {}, {
    importGlue: () => import('../../web/dist/springbones_creator_tools.js'),
    glueFile: 'web/dist/springbones_creator_tools.js',
    defaultUrl: new URL('../../web/dist/springbones_creator_tools.wasm', import.meta.url),
  });
  const next = generator(38);
  const random = () => (next() / 2 ** 32 - 0.5) * 10 ** ((next() % 12) - 3);
  const { glb, springBones, hash } = springRig({ chains: 60, joints: 1 });
  const bones = springBones.models[hash];
  Object.values(bones).forEach((entry, i) => {
    const kind = i % 6;
    if (kind === 0) entry.stiffness = 4 + Math.abs(random()) + 0.001;
    else if (kind === 1) entry.drag = -Math.abs(random()) - 1e-9;
    else if (kind === 2) entry.gravityDir = [random() * 1e3, 11.000000000000002, random()];
    else if (kind === 3) entry.gravityPower = [random(), 'é'.repeat(next() % 40), random(), 1.5e300];
    else if (kind === 4) entry.stiffness = { ['ü'.repeat(next() % 30)]: random(), b: [random(), random()] };
    else entry.gravityPower = 1e300 * random();
  });
  const text = JSON.stringify(springBones);
  const result = withBytes(tools, glb, (ptr, size) =>
    withRoomForStrings(tools, [text, hash], () => tools.detectSpringBones(ptr, size, text, hash)));
  const native = JSON.parse(result).warnings;
  assert.ok(native.length >= 60, `${native.length} warnings`);
  const runtime = sb.loadRig(glb, springBones, { contentHash: hash }).warnings;
  const mine = runtime.filter((w) => native.some((n) => n.path === w.path && n.code === w.code));
  assert.deepEqual(mine.map((w) => ({ ...w })), native);
  assert.ok(native.some((w) => w.message.includes('...')), 'a quote is cut');
  assert.ok(native.some((w) => /\d\.\d+e[-+]\d\d/.test(w.message)), 'a number in exponent notation');
});

test('the hitRadius warning writes floats with %.7g, as native code does', async () => {
  const sb = await createSpringBones();
  const { glb, springBones, hash } = springRig({ chains: 1, joints: 1 });
  // Beyond kMaxHitRadius (1e6): each is a warning; 1e39 is beyond float's range, infinite as a float.
  const radii = [1234567.891, 1e30, 12345678.9, 3.0000001e20, 1e39];
  const [max] = printf('%.7g', [1e6]);
  const expected = printf('%.7g', radii.map(Math.fround));
  radii.forEach((r, i) => {
    const warning = sb.loadRig(glb, springBones, { contentHash: hash, hitRadius: r }).warnings.find((w) => w.code === 'hit-radius-out-of-range');
    assert.equal(warning?.message, `hitRadius ${expected[i]} is outside [0, ${max}] world units; using ${max}`);
  });
  assert.equal(expected[4], 'inf');
});

// What the JSON text showed for bytes that are not UTF-8 (a name cut at 64 bytes inside a
// character), the typed strings show too: one U+FFFD for each byte, not one for the sequence.
test('a string cut inside a character shows U+FFFD for each of its bytes', async () => {
  const sb = await createSpringBones();
  const { glb, springBones, hash } = springRig({ chains: 1, joints: 1 });
  const node = `xx${'€'.repeat(30)}`;  // 2 + 90 bytes: the cut at 64 keeps 2 of the 21st euro's 3
  const rig = sb.loadRig(glb, springBones, { contentHash: hash, colliders: [{ node, radius: 0.1 }] });
  const warning = rig.warnings.find((w) => w.code === 'collider-node-not-found');
  assert.ok(warning?.message.startsWith(`collider node 'xx${'€'.repeat(20)}\uFFFD\uFFFD...' is neither`), warning?.message);
});
