// Property-based test of the typed encoder's JavaScript side (web/typed_value.js) over random
// object graphs: Proxies, holes, arrays that grow while they are read, cycles, toJSON, boxed
// primitives, BigInt, huge strings and keys. For every graph, the encoder either writes exactly
// what JSON.stringify would (numbers compared by their bits, which JSON would round through text),
// or refuses with a TypeError, a RangeError or a 'limit-exceeded' SpringBonesError; and its work is
// bounded by the graph as it was built: every Proxy trap is counted, and their number stays within
// a small multiple of the graph's size, however much the graph grows while it is read. Seeded, so
// a failure names the case that reproduces it.
import assert from 'node:assert/strict';
import { test } from 'node:test';

import { SpringBonesError } from '../../web/errors.js';
import { kTypedLimits } from '../../web/typed_encoding.js';
import { encodeTyped } from '../../web/typed_value.js';
import { decodeTyped } from './typed_decode.mjs';

function mulberry32(seed) {
  return () => {
    seed = (seed + 0x6d2b79f5) | 0;
    let t = Math.imul(seed ^ (seed >>> 15), 1 | seed);
    t = (t + Math.imul(t ^ (t >>> 7), 61 | t)) ^ t;
    return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
  };
}

// One random graph: its root, how many things it was built with, the trap counter its Proxies
// share, and whether anything in it changes while it is read (then only the bounds are checked).
function randomGraph(random) {
  const counter = { traps: 0 };
  let size = 0;
  let mutates = false;
  const pick = (list) => list[Math.floor(random() * list.length)];
  const numbers = [0, -0, 1, -1.5, 1e308, 5e-324, Math.PI, NaN, Infinity, -Infinity, 2 ** 53];
  const strings = () => pick(['', 'a', 'SpringBone_hair', 'é', '\u{1f600}', 'x'.repeat(1 + Math.floor(random() * 64)),
    '\ud800', 'a\udc00b', 'y'.repeat(kTypedLimits.maxStringBytes + 1), 'é'.repeat(kTypedLimits.maxStringBytes / 2 + 1)]);
  const counted = (target, grow) => new Proxy(target, {
    get(t, key, receiver) {
      ++counter.traps;
      if (grow && t.length < 2 ** 20 && (key === 'length' || /^\d+$/.test(String(key)))) t.push(0);
      return Reflect.get(t, key, receiver);
    },
    has(t, key) {
      ++counter.traps;
      return Reflect.has(t, key);
    },
    ownKeys(t) {
      ++counter.traps;
      if (grow && !Array.isArray(t)) t[`grown${Object.keys(t).length}`] = 1;  // listed once: the new key is not read
      return Reflect.ownKeys(t);
    },
    getOwnPropertyDescriptor(t, key) {
      ++counter.traps;
      return Reflect.getOwnPropertyDescriptor(t, key);
    },
  });
  const ancestors = [];
  const value = (depth) => {
    ++size;
    const r = random();
    if (depth > 5 || r < 0.3) {
      return pick([() => null, () => random() < 0.5, () => pick(numbers), strings, () => (random() < 0.02 ? 10n : 1),
        () => (random() < 0.02 ? undefined : 2), () => (random() < 0.02 ? () => 1 : 3), () => new Number(pick(numbers)),
        () => new String(strings())])();
    }
    if (r < 0.35 && ancestors.length > 0 && random() < 0.2) return pick(ancestors);  // a cycle
    if (r < 0.38) return { toJSON: () => ({ via: 'toJSON' }) };
    if (r < 0.4) return new Float32Array(2);
    const isArray = random() < 0.5;
    const container = isArray ? [] : {};
    const proxied = random() < 0.4;
    const grows = proxied && random() < 0.4;
    mutates ||= grows;
    const wrapped = proxied ? counted(container, grows) : container;
    ancestors.push(wrapped);
    const count = Math.floor(random() * 6);
    for (let i = 0; i < count; ++i) {
      const child = value(depth + 1);
      if (isArray) {
        if (random() < 0.05) container.length += 1;  // a hole
        else container.push(child);
      } else {
        const key = random() < 0.05 ? strings() : `k${i}`;
        if (child !== undefined || random() < 0.5) container[key] = child;
      }
    }
    if (isArray && random() < 0.03) container.length = 2 ** 32 - 1;  // sparse beyond every bound
    ancestors.pop();
    return wrapped;
  };
  const root = value(0);
  return { root, counter, size: () => size, mutates };
}

// Numbers as their bits, so that -0, NaN and the infinities compare as the encoder keeps them.
// (A replacer sees a boxed number before JSON.stringify unwraps it.)
const byBits = (v) => JSON.parse(JSON.stringify(v, (_k, x) => {
  const n = x instanceof Number ? x.valueOf() : x;
  return typeof n === 'number' ? { bits: bitsOf(n) } : x;
}));
const bitsOf = (x) => Array.from(new Uint8Array(new Float64Array([x]).buffer)).join('.');
const sorted = (v) => (Array.isArray(v) ? v.map(sorted) : v && typeof v === 'object'
  ? Object.fromEntries(Object.keys(v).sort().map((k) => [k, sorted(v[k])])) : v);

test('random object graphs: what JSON.stringify writes, or a documented refusal, in bounded work', () => {
  const random = mulberry32(39);
  const outcomes = { written: 0, type: 0, range: 0, limit: 0 };
  for (let n = 0; n < 600; ++n) {
    const graph = randomGraph(random);
    const before = graph.counter.traps;
    let bytes;
    try {
      bytes = encodeTyped('test', graph.root);
    } catch (error) {
      if (error instanceof SpringBonesError) {
        assert.equal(error.code, 'limit-exceeded', `case ${n}: ${error.message}`);
        ++outcomes.limit;
      } else if (error instanceof RangeError) {
        assert.match(error.message, /lone surrogate/, `case ${n}`);
        ++outcomes.range;
      } else {
        assert.ok(error instanceof TypeError, `case ${n}: ${error}`);
        ++outcomes.type;
      }
      assert.ok(error.message.length < 1000, `case ${n}: a message of ${error.message.length} characters`);
    }
    const traps = graph.counter.traps - before;
    // Per thing built, a Proxy sees at most a length or key listing, a has, a get and a toJSON
    // lookup of its own, and its parent's get: 8 is a generous multiple; growth adds nothing.
    assert.ok(traps <= 8 * graph.size() + 8, `case ${n}: ${traps} traps for a graph of ${graph.size()}`);
    if (bytes === undefined) continue;
    ++outcomes.written;
    if (graph.mutates) continue;  // JSON.stringify now would see what the reads added
    const expected = sorted(byBits(graph.root));
    assert.deepEqual(byBits(decodeTyped(bytes)), expected, `case ${n}`);
  }
  // Every outcome was reached, so each branch above was exercised.
  for (const [outcome, count] of Object.entries(outcomes)) assert.ok(count > 10, `${outcome}: ${count} cases`);
});
