// scripts/bench --scaling: every function that takes untrusted bytes or JSON, fed inputs of one
// shape at N and at 4N bytes. A linear function takes about 4x as long on the larger input; the
// table prints the ratio per function and shape and flags any above 6. The larger size is 1 MiB,
// so the same run shows the time of a 1 MiB input of every shape (target: under 100 ms).
//
// Shapes stress what the code reads and what it skips: many nodes, deep hierarchies, long
// children arrays, long strings, many small objects and deep nesting in extras and extensions,
// skipped containers (meshes, accessors, images, buffers), and for the metadata, the entity and
// the VRM extensions the same in each of their containers. Each input is built to its size from a
// repeated unit, so N and 4N differ only in how many units they hold.
import { performance } from 'node:perf_hooks';
import { createSpringBones } from '../../web/springbones.js';
import { glbOfJson } from '../lib/fixtures/glb.mjs';

const SMALL = 256 * 1024, LARGE = 4 * SMALL, MAX_RATIO = 6, TARGET_MS = 100;
// A run of the small input longer than this is already too slow to be linear at 1 MiB (4x would
// blow the target): the large one is not run, so a quadratic shape cannot stall the bench.
const GIVE_UP_MS = 2000;
const median = (xs) => [...xs].sort((a, b) => a - b)[xs.length >> 1];

const glb = (doc) => glbOfJson(typeof doc === 'string' ? doc : JSON.stringify(doc));
const repeat = (count, unit) => Array.from({ length: count }, (_, i) => unit(i));
const nested = (depth, open, close, leaf = '0') => open.repeat(depth) + leaf + close.repeat(depth);
const asset = { version: '2.0' };

// A small wearable: one chain of three springbone joints under a head, and its metadata.
const wearableNodes = () => [
  { name: 'Avatar_Head', children: [1], translation: [0, 1.6, 0] },
  { name: 'springbone_0', children: [2], translation: [0, 0, 0.05] },
  { name: 'springbone_1', children: [3], translation: [0, -0.05, 0] },
  { name: 'springbone_2', children: [4], translation: [0, -0.05, 0] },
  { name: 'springbone_tip', translation: [0, -0.05, 0] },
];
const entry = { stiffness: 1, gravityPower: 0.5, gravityDir: [0, -1, 0], drag: 0.4 };
const HASH = 'bafkreihxvdsm6ackftvz5knqjjprtj5cum6u3tzsw2ooo2goem6ahyxuey';
const wearableSpringBones = (bones = { springbone_0: { ...entry, isRoot: true } }) => ({ version: 1, models: { [HASH]: bones } });

// glTF documents of one shape with `n` units (the wearable's nodes stay, so a load has joints).
const GLTF_SHAPES = {
  'nodes, flat': (n) => ({ asset, nodes: [...wearableNodes(), ...repeat(n, (i) => ({ name: `n${i}`, translation: [i, 0, 0] }))] }),
  'nodes, one deep chain': (n) => ({ asset, nodes: [...wearableNodes(), ...repeat(n, (i) => (i + 1 < n ? { children: [6 + i] } : {}))] }),
  'nodes, deep springbone chain': (n) => ({ asset, nodes: repeat(n, (i) => ({ name: `springbone_${i}`, translation: [0, -0.01, 0], ...(i + 1 < n ? { children: [i + 1] } : {}) })) }),
  'children, one long array': (n) => ({ asset, nodes: [...wearableNodes(), { children: repeat(n, (i) => 6 + i) }, ...repeat(n, () => ({}))] }),
  'node name, long string': (n) => ({ asset, nodes: [...wearableNodes(), { name: 'x'.repeat(n * 8) }] }),
  'node extras, small objects': (n) => ({ asset, nodes: [...wearableNodes(), { extras: { list: repeat(n, (i) => ({ a: i })) } }] }),
  'node extras, deep arrays': (n) => `{"asset":{"version":"2.0"},"nodes":${JSON.stringify(wearableNodes()).slice(0, -1)},{"extras":${nested(n * 4, '[', ']')}}]}`,
  'node extras, deep objects': (n) => `{"asset":{"version":"2.0"},"nodes":${JSON.stringify(wearableNodes()).slice(0, -1)},{"extras":${nested(n, '{"a":', '}')}}]}`,
  'node extensions, small objects': (n) => ({ asset, nodes: [...wearableNodes(), { extensions: { EXT_x: repeat(n, (i) => ({ a: i })) } }] }),
  'document extensions, many keys': (n) => ({ asset, nodes: wearableNodes(), extensions: Object.fromEntries(repeat(n, (i) => [`EXT_${i}`, { a: i }])) }),
  'document extras, deep objects': (n) => `{"asset":{"version":"2.0"},"nodes":${JSON.stringify(wearableNodes())},"extras":${nested(n, '{"a":', '}')}}`,
  'extensionsUsed, long array': (n) => ({ asset, nodes: wearableNodes(), extensionsUsed: repeat(n, (i) => `EXT_${i}`) }),
  'meshes and accessors': (n) => ({ asset, nodes: wearableNodes(), meshes: repeat(n, () => ({ primitives: [{ attributes: { POSITION: 0 } }] })), accessors: repeat(n, () => ({ componentType: 5126, count: 1, type: 'VEC3' })) }),
  'images with URIs': (n) => ({ asset, nodes: wearableNodes(), images: repeat(n, (i) => ({ uri: `img${i}.png` })) }),
  'buffer, long data URI': (n) => ({ asset, nodes: wearableNodes(), buffers: [{ byteLength: n * 6, uri: 'data:application/octet-stream;base64,' + 'AAAA'.repeat(n * 2) }] }),
  'asset, long string': (n) => ({ asset: { version: '2.0', generator: 'g'.repeat(n * 8) }, nodes: wearableNodes() }),
  'numbers, long array in extras': (n) => ({ asset, nodes: wearableNodes(), extras: repeat(n * 2, (i) => i * 0.5) }),
};

// springBones objects of one shape (as JSON text, the way a page holds a fetched entity).
const METADATA_SHAPES = {
  'entries, many': (n) => wearableSpringBones({ springbone_0: { ...entry, isRoot: true }, ...Object.fromEntries(repeat(n, (i) => [`springbone_x${i}`, entry])) }),
  'models, many keys': (n) => ({ version: 1, models: { ...wearableSpringBones().models, ...Object.fromEntries(repeat(n, (i) => [`hash${i}`, { springbone_0: entry }])) } }),
  'entry, many unknown keys': (n) => wearableSpringBones({ springbone_0: { ...entry, isRoot: true, ...Object.fromEntries(repeat(n, (i) => [`k${i}`, i])) } }),
  'entry, deep nesting': (n) => `{"version":1,"models":{"${HASH}":{"springbone_0":{"isRoot":true,"x":${nested(n, '{"a":', '}')}}}}}`,
  'entry, deep arrays': (n) => `{"version":1,"models":{"${HASH}":{"springbone_0":{"isRoot":true,"x":${nested(n * 4, '[', ']')}}}}}`,
  'entry name, long string': (n) => wearableSpringBones({ springbone_0: { ...entry, isRoot: true }, ['springbone' + 'x'.repeat(n * 8)]: entry }),
  'gravityDir, long array': (n) => wearableSpringBones({ springbone_0: { ...entry, isRoot: true, gravityDir: repeat(n * 2, () => 0.5) } }),
  'top level, many unknown keys': (n) => ({ ...wearableSpringBones(), ...Object.fromEntries(repeat(n, (i) => [`k${i}`, i])) }),
};

// Entities (the deployed item) of one shape, wearing the small wearable.
function entity({ content = [], representations = [], springBones = wearableSpringBones(), extra = {} } = {}) {
  return {
    version: 'v3', type: 'wearable', pointers: ['urn:x'], timestamp: 1,
    content: [{ file: 'w.glb', hash: HASH }, ...content],
    metadata: {
      id: 'urn:x', name: 'x', description: '', i18n: [{ code: 'en', text: 'x' }], thumbnail: 'thumbnail.png', image: 'image.png',
      collectionAddress: '0x0000000000000000000000000000000000000000', rarity: 'common',
      data: {
        replaces: [], hides: [], tags: [], category: 'hair',
        representations: [{ bodyShapes: ['urn:decentraland:off-chain:base-avatars:BaseMale'], mainFile: 'w.glb', contents: ['w.glb'], overrideHides: [], overrideReplaces: [] }, ...representations],
        springBones,
      },
      ...extra,
    },
  };
}
const ENTITY_SHAPES = {
  'content, many files': (n) => entity({ content: repeat(n, (i) => ({ file: `f${i}.glb`, hash: `h${i}` })) }),
  'representations, many': (n) => entity({ representations: repeat(n, (i) => ({ bodyShapes: ['urn:b'], mainFile: `f${i}.glb`, contents: [`f${i}.glb`], overrideHides: [], overrideReplaces: [] })) }),
  'representations and models, many': (n) => entity({
    content: repeat(n, (i) => ({ file: `f${i}.glb`, hash: `h${i}` })),
    representations: repeat(n, (i) => ({ bodyShapes: ['urn:b'], mainFile: `f${i}.glb`, contents: [`f${i}.glb`], overrideHides: [], overrideReplaces: [] })),
    springBones: { version: 1, models: { ...wearableSpringBones().models, ...Object.fromEntries(repeat(n, (i) => [`h${i}`, { springbone_0: entry }])) } },
  }),
  'springBones, many entries': (n) => entity({ springBones: METADATA_SHAPES['entries, many'](n) }),
  'metadata, deep nesting': (n) => entity({ extra: { x: JSON.parse(nested(Math.min(n, 4000), '{"a":', '}')) } }),
  'contents, one long array': (n) => entity({ representations: [{ bodyShapes: ['urn:b'], mainFile: 'w.glb', contents: repeat(n, (i) => `f${i}.glb`), overrideHides: [], overrideReplaces: [] }] }),
};

// VRM documents of one shape.
const vrmNodes = (n, named = (i) => `bone${i}`) => repeat(n, (i) => ({ name: named(i), translation: [0, -0.05, 0], ...(i + 1 < n ? { children: [i + 1] } : {}) }));
const sphere = (node) => ({ node, shape: { sphere: { offset: [0, 0, 0], radius: 0.05 } } });
const vrmc = (nodes, springBone) => ({ asset, nodes, extensionsUsed: ['VRMC_springBone'], extensions: { VRMC_springBone: { specVersion: '1.0', ...springBone } } });
const VRM_SHAPES = {
  'VRMC: one spring, many joints': (n) => vrmc(vrmNodes(n), { springs: [{ joints: repeat(n, (i) => ({ node: i })) }] }),
  'VRMC: many springs of two joints': (n) => vrmc(vrmNodes(2 * n), { springs: repeat(n, (i) => ({ joints: [{ node: 2 * i }, { node: 2 * i + 1 }] })) }),
  'VRMC: many springs, same root and deep tail': (n) => vrmc(vrmNodes(n), { springs: repeat(n, () => ({ joints: [{ node: 0 }, { node: n - 1 }] })) }),
  'VRMC: many colliders in one group': (n) => vrmc(vrmNodes(n + 8), {
    colliders: repeat(n, (i) => sphere(8 + i)), colliderGroups: [{ colliders: repeat(n, (i) => i) }],
    springs: [{ joints: repeat(8, (i) => ({ node: i })), colliderGroups: [0] }],
  }),
  'VRMC: many joints and many colliders': (n) => vrmc(vrmNodes(2 * n), {
    colliders: repeat(n, (i) => sphere(n + i)), colliderGroups: [{ colliders: repeat(n, (i) => i) }],
    springs: [{ joints: repeat(n, (i) => ({ node: i })), colliderGroups: [0] }],
  }),
  'VRMC: many groups per spring': (n) => vrmc(vrmNodes(n + 8), {
    colliders: [sphere(8)], colliderGroups: repeat(n, () => ({ colliders: [0] })),
    springs: [{ joints: repeat(8, (i) => ({ node: i })), colliderGroups: repeat(n, (i) => i) }],
  }),
  'VRMC: joints, many unknown keys': (n) => vrmc(vrmNodes(8), { springs: [{ joints: [{ node: 0, ...Object.fromEntries(repeat(n, (i) => [`k${i}`, i])) }, { node: 1 }] }] }),
  'VRMC: extension, deep nesting': (n) => `{"asset":{"version":"2.0"},"nodes":${JSON.stringify(vrmNodes(4))},"extensions":{"VRMC_springBone":{"specVersion":"1.0","springs":[{"joints":[{"node":0},{"node":1}]}],"x":${nested(n, '{"a":', '}')}}}}`,
  'VRM 0.x: one group, deep subtree': (n) => ({ asset, nodes: vrmNodes(n), extensions: { VRM: { secondaryAnimation: { boneGroups: [{ bones: [0], colliderGroups: [] }], colliderGroups: [] } } } }),
  'VRM 0.x: many groups, same bones': (n) => ({ asset, nodes: vrmNodes(64), extensions: { VRM: { secondaryAnimation: { boneGroups: repeat(n, () => ({ bones: [0], colliderGroups: [] })), colliderGroups: [] } } } }),
  'VRM 0.x: many colliders, deep subtree': (n) => ({
    asset, nodes: vrmNodes(n),
    extensions: { VRM: { secondaryAnimation: { boneGroups: [{ bones: [0], colliderGroups: [0] }], colliderGroups: [{ node: 0, colliders: repeat(n, () => ({ offset: { x: 0, y: 0, z: 0 }, radius: 0.1 })) }] } } },
  }),
};

/** Bytes of a document: a JSON value, or JSON text already. */
const textOf = (doc) => (typeof doc === 'string' ? doc : JSON.stringify(doc));

/** The unit count whose document is `target` bytes, from the sizes at two counts (size is linear in the count). */
function unitsFor(make, target) {
  const a = 64, b = 1024;
  const sa = textOf(make(a)).length, sb = textOf(make(b)).length;
  const perUnit = (sb - sa) / (b - a);
  return Math.max(1, Math.round(a + (target - sa) / perUnit));
}

/** Median ms of a few calls (at least 3, at most 15 or ~1 s); the error code when it throws. */
function time(call) {
  let outcome = 'ok';
  const once = () => {
    const t0 = performance.now();
    try { call(); } catch (e) { outcome = e.code ?? e.name; }
    return performance.now() - t0;
  };
  const first = once();
  if (first > GIVE_UP_MS) return { ms: first, outcome, gaveUp: true };
  const runs = [first];
  while (runs.length < 15 && (runs.length < 3 || runs.reduce((s, x) => s + x, 0) < 1000)) runs.push(once());
  return { ms: median(runs.slice(1).length ? runs.slice(1) : runs), outcome };
}

function cases(sb, tools) {
  const list = [];
  const dispose = (r) => r?.dispose?.();
  const wearableGlb = glb({ asset, nodes: wearableNodes() });
  const withVrm = (doc) => {
    const d = typeof doc === 'string' ? JSON.parse(doc) : structuredClone(doc);
    d.extensions = { ...d.extensions, VRMC_springBone: { specVersion: '1.0', springs: [{ joints: [{ node: 1 }, { node: 2 }, { node: 3 }, { node: 4 }] }] } };
    return d;
  };
  for (const [shape, make] of Object.entries(GLTF_SHAPES)) {
    const springBones = JSON.stringify(wearableSpringBones());
    list.push({ fn: 'loadRig', shape: `glTF: ${shape}`, make, input: (d) => glb(d), call: (x) => dispose(sb.loadRig(x, springBones, { contentHash: HASH })) });
    list.push({ fn: 'detectSpringBones', shape: `glTF: ${shape}`, make, input: (d) => glb(d), call: (x) => tools.detectSpringBones(x, springBones, { contentHash: HASH }) });
    if (!shape.startsWith('nodes, deep springbone') && !shape.startsWith('nodes, one deep')) {
      list.push({ fn: 'loadVrm', shape: `glTF: ${shape}`, make, input: (d) => glb(typeof d === 'string' && shape.includes('deep') ? d : withVrm(d)), call: (x) => dispose(sb.loadVrm(x)) });
    } else {
      list.push({ fn: 'loadVrm', shape: `glTF: ${shape}`, make, input: (d) => glb(d), call: (x) => dispose(sb.loadVrm(x)) });
    }
    list.push({ fn: 'contentHash', shape: `glTF: ${shape}`, make, input: (d) => glb(d), call: (x) => sb.contentHash(x) });
  }
  for (const [shape, make] of Object.entries(METADATA_SHAPES)) {
    list.push({ fn: 'loadRig', shape: `springBones: ${shape}`, make, input: textOf, call: (x) => dispose(sb.loadRig(wearableGlb, x, { contentHash: HASH })) });
    list.push({ fn: 'detectSpringBones', shape: `springBones: ${shape}`, make, input: textOf, call: (x) => tools.detectSpringBones(wearableGlb, x, { contentHash: HASH }) });
    list.push({ fn: 'setSpringBoneParams', shape: `springBones: ${shape}`, make, input: (d) => (typeof d === 'string' ? JSON.parse(d) : d), call: (x) => tools.setSpringBoneParams(x, entity(), 'BaseMale', 'springbone_0', entry) });
  }
  for (const [shape, make] of Object.entries(ENTITY_SHAPES)) {
    list.push({ fn: 'validateSpringBones', shape: `entity: ${shape}`, make, input: (d) => d, call: (x) => tools.validateSpringBones(x) });
    list.push({ fn: 'setSpringBoneParams', shape: `entity: ${shape}`, make, input: (d) => d, call: (x) => tools.setSpringBoneParams(x.metadata.data.springBones, x, 'BaseMale', 'springbone_0', entry) });
    list.push({ fn: 'loadRig', shape: `entity: ${shape}`, make, input: (d) => d, call: (x) => dispose(sb.loadRig(wearableGlb, x.metadata.data.springBones, { entity: x, bodyShape: 'BaseMale' })) });
  }
  for (const [shape, make] of Object.entries(VRM_SHAPES)) {
    list.push({ fn: 'loadVrm', shape, make, input: (d) => glb(d), call: (x) => dispose(sb.loadVrm(x)) });
  }
  return list;
}

export async function runScaling({ filter = '' } = {}) {
  const sb = await createSpringBones();
  const tools = await sb.creatorTools();
  const rows = [];
  const pad = (s, n) => String(s).padEnd(n);
  console.log(`scaling: each shape at N = ${SMALL / 1024} KiB and 4N = ${LARGE / 1024} KiB; ratio = time(4N) / time(N), linear ~4, flagged above ${MAX_RATIO}; 1 MiB target ${TARGET_MS} ms`);
  console.log(`${pad('function', 20)} ${pad('shape', 48)} ${pad('N ms', 9)} ${pad('4N ms', 9)} ${pad('ratio', 7)} outcome`);
  for (const c of cases(sb, tools)) {
    if (filter && !`${c.fn} ${c.shape}`.includes(filter)) continue;
    const small = c.input(c.make(unitsFor(c.make, SMALL)));
    const rSmall = time(() => c.call(small));
    let rLarge = null;
    if (!rSmall.gaveUp) {
      const large = c.input(c.make(unitsFor(c.make, LARGE)));
      rLarge = time(() => c.call(large));
    }
    const ratio = rLarge ? rLarge.ms / Math.max(rSmall.ms, 0.005) : Infinity;
    // Below ~0.05 ms the timer's steps and call overheads dominate: such a ratio says nothing.
    const tiny = rLarge && rLarge.ms < 0.2;
    const bad = (!tiny && ratio > MAX_RATIO) || !rLarge || rLarge.ms > TARGET_MS;
    rows.push({ fn: c.fn, shape: c.shape, smallMs: rSmall.ms, largeMs: rLarge?.ms ?? null, ratio: rLarge ? ratio : null, outcome: rLarge?.outcome ?? rSmall.outcome, bad });
    console.log(`${pad(c.fn, 20)} ${pad(c.shape, 48)} ${pad(rSmall.ms.toFixed(3), 9)} ${pad(rLarge ? rLarge.ms.toFixed(3) : `gave up (N took ${(rSmall.ms / 1000).toFixed(1)} s)`, 9)} ${pad(rLarge ? (tiny ? '(tiny)' : ratio.toFixed(2)) : '-', 7)} ${rLarge?.outcome ?? rSmall.outcome}${bad ? '   <-- FAIL' : ''}`);
  }
  const failed = rows.filter((r) => r.bad);
  const worst = rows.filter((r) => r.ratio !== null && r.largeMs >= 0.2).reduce((w, r) => (r.ratio > (w?.ratio ?? 0) ? r : w), null);
  const slowest = rows.reduce((w, r) => ((r.largeMs ?? Infinity) > (w?.largeMs ?? -1) ? r : w), null);
  console.log(`scaling: ${rows.length} function/shape pairs, ${failed.length} over ratio ${MAX_RATIO} or ${TARGET_MS} ms at 1 MiB; worst ratio ${worst?.ratio.toFixed(2)} (${worst?.fn}, ${worst?.shape}); slowest 1 MiB input ${slowest?.largeMs?.toFixed(1) ?? 'gave up'} ms (${slowest?.fn}, ${slowest?.shape})`);
  return { rows, failed };
}

if (import.meta.url === `file://${process.argv[1]}`) {
  const { failed } = await runScaling({ filter: process.argv[2] ?? '' });
  process.exitCode = failed.length ? 1 : 0;
}
