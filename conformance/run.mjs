#!/usr/bin/env node
// Replays the conformance pack on springbones through its public JavaScript API and exits with 1
// when any expected rotation is missed (README.md describes the cases).
//
//   node conformance/run.mjs [--cases <dir>] [--module <path or package>] [case name ...]
//
// --cases: the folder of case files (default: cases/ and vrm/cases/ beside this file); a case's
// "glb" is relative to its own file. --module: what to import createSpringBones from (default: ../web/springbones.js
// in a checkout, else the installed package "springbones"). Case names filter by substring.
import { existsSync, readFileSync, readdirSync } from 'node:fs';
import { dirname, join, relative, resolve } from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';

const here = dirname(fileURLToPath(import.meta.url));

function parseArguments(argv) {
  const options = { cases: null, module: null, names: [] };
  for (let i = 0; i < argv.length; i++) {
    const a = argv[i];
    if (a === '--cases' || a === '--module') {
      if (i + 1 >= argv.length) throw new Error(`${a} needs a value`);
      options[a.slice(2)] = argv[++i];
    } else if (a === '--help' || a === '-h') {
      console.log('usage: node conformance/run.mjs [--cases <dir>] [--module <path or package>] [case name ...]');
      process.exit(0);
    } else {
      options.names.push(a);
    }
  }
  return options;
}

async function importSpringBones(module) {
  if (module) {
    const spec = existsSync(module) ? pathToFileURL(resolve(module)).href : module;
    return import(spec);
  }
  const source = join(here, '..', 'web', 'springbones.js');
  return import(existsSync(source) ? pathToFileURL(source).href : 'springbones');
}

// ---------------------------------------------------------------------------------------------
// What the runner needs of a GLB: its nodes (names, hierarchy, rest transforms). Read here rather
// than through the repository's fixture helpers so that the runner works from the npm package or a
// copy of this folder alone.
function gltfNodes(bytes) {
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  if (view.getUint32(0, true) !== 0x46546c67) throw new Error('not a GLB');
  const json = new TextDecoder().decode(bytes.subarray(20, 20 + view.getUint32(12, true)));
  return JSON.parse(json).nodes;
}

function trs({ translation: [tx, ty, tz] = [0, 0, 0], rotation: [x, y, z, w] = [0, 0, 0, 1], scale: [sx, sy, sz] = [1, 1, 1] }) {
  return [
    (1 - 2 * (y * y + z * z)) * sx, 2 * (x * y + z * w) * sx, 2 * (x * z - y * w) * sx, 0,
    2 * (x * y - z * w) * sy, (1 - 2 * (x * x + z * z)) * sy, 2 * (y * z + x * w) * sy, 0,
    2 * (x * z + y * w) * sz, 2 * (y * z - x * w) * sz, (1 - 2 * (x * x + y * y)) * sz, 0,
    tx, ty, tz, 1,
  ];
}

function multiply(a, b) {
  const out = new Array(16).fill(0);
  for (let c = 0; c < 4; c++) {
    for (let r = 0; r < 4; r++) {
      let s = 0;
      for (let k = 0; k < 4; k++) s += a[k * 4 + r] * b[c * 4 + k];
      out[c * 4 + r] = s;
    }
  }
  return out;
}

// World matrices of every node for one frame: a node the pose names has that world matrix; any
// other its parent's times its rest local matrix (README.md, "Driver motion"). Spring joints get
// their rest pose here too; only the drivers' matrices are handed to the simulation.
function worldMatrices(nodes, parent, pose) {
  const world = new Array(nodes.length);
  const order = parentsFirst(nodes, parent);
  for (const i of order) {
    const name = nodes[i].name;
    if (Object.hasOwn(pose, name)) world[i] = pose[name];
    else world[i] = parent[i] >= 0 ? multiply(world[parent[i]], trs(nodes[i])) : trs(nodes[i]);
  }
  return world;
}

function parentsFirst(nodes, parent) {
  const children = nodes.map(() => []);
  const roots = [];
  nodes.forEach((_, i) => (parent[i] >= 0 ? children[parent[i]].push(i) : roots.push(i)));
  const order = [];
  const stack = [...roots].reverse();
  while (stack.length) {
    const i = stack.pop();
    order.push(i);
    for (let k = children[i].length - 1; k >= 0; k--) stack.push(children[i][k]);
  }
  return order;
}

// {"$nonFinite": "NaN" | "Infinity" | "-Infinity"} -> the IEEE value (README.md, "Non-finite numbers").
const NON_FINITE = { NaN, Infinity, '-Infinity': -Infinity };
function decodeNonFinite(value) {
  if (Array.isArray(value)) return value.map(decodeNonFinite);
  if (value !== null && typeof value === 'object') {
    const keys = Object.keys(value);
    if (keys.length === 1 && keys[0] === '$nonFinite') {
      if (!Object.hasOwn(NON_FINITE, value.$nonFinite)) throw new Error(`unknown $nonFinite ${value.$nonFinite}`);
      return NON_FINITE[value.$nonFinite];
    }
    return Object.fromEntries(keys.map((k) => [k, decodeNonFinite(value[k])]));
  }
  return value;
}

// The angle in radians between the rotations of two quaternions (q and -q are the same rotation):
// with b on a's side, |a - b| = 2 sin(phi / 2) and |a + b| = 2 cos(phi / 2), phi being the angle
// between them as 4-vectors and 2 phi the rotation's: 4 atan2(|a - b|, |a + b|), accurate for small
// angles where acos of the dot product is not.
function angleBetween(a, b) {
  const s = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3] < 0 ? -1 : 1;
  let d = 0;
  let p = 0;
  for (let i = 0; i < 4; i++) {
    d += (a[i] - s * b[i]) ** 2;
    p += (a[i] + s * b[i]) ** 2;
  }
  return 4 * Math.atan2(Math.sqrt(d), Math.sqrt(p));
}

const sameList = (a, b) => a.length === b.length && a.every((v, i) => v === b[i]);

// ---------------------------------------------------------------------------------------------

/** Replays one case; returns the misses (strings), none when it passes. */
function replay(sb, file) {
  const c = JSON.parse(readFileSync(file, 'utf8'));
  if (c.format !== 'springbones-conformance/1') return [`unknown format ${c.format}`];
  const glb = new Uint8Array(readFileSync(resolve(dirname(file), c.glb)));
  const nodes = gltfNodes(glb);
  const parent = new Array(nodes.length).fill(-1);
  nodes.forEach((n, i) => (n.children ?? []).forEach((k) => { parent[k] = i; }));
  const nodeIndex = new Map();
  nodes.forEach((n, i) => { if (!nodeIndex.has(n.name)) nodeIndex.set(n.name, i); });

  const misses = [];
  // A VRM case's spring bones are the file's own VRMC_springBone; an ADR case's come with the case.
  const rig = c.load.vrm === true ? sb.loadVrm(glb) : sb.loadRig(glb, decodeNonFinite(c.springBones), c.load);
  try {
    // springbones' own reading, beyond the rotations: which joints it simulates and what it warns.
    const joints = rig.joints.map((j) => j.name);
    const simulated = [...joints].sort();
    if (c.springbones?.joints && !sameList(simulated, c.springbones.joints)) {
      misses.push(`joints: [${simulated.join(', ')}], expected [${c.springbones.joints.join(', ')}]`);
    }
    const warnings = [...new Set(rig.warnings.map((w) => w.code))].sort();
    if (c.springbones?.warnings && !sameList(warnings, c.springbones.warnings)) {
      misses.push(`warnings: [${warnings.join(', ')}], expected [${c.springbones.warnings.join(', ')}]`);
    }
    const { integrator, stepHz, maxSubsteps, jumpDistance, jumpAngle } = c.instance;
    const instance = rig.createInstance({ integrator, stepHz, maxSubsteps, jumpDistance, jumpAngle });
    try {
      const jointOf = new Map(joints.map((name, i) => [name, i]));
      // A listed node springbones does not simulate keeps its rest rotation from the GLB.
      const sources = c.nodes.map((name) => {
        if (jointOf.has(name)) return { joint: jointOf.get(name) };
        if (!nodeIndex.has(name)) throw new Error(`${c.name}: node ${name} is not in ${c.glb}`);
        return { rest: nodes[nodeIndex.get(name)].rotation ?? [0, 0, 0, 1] };
      });
      const driverNodes = rig.drivers.map((d) => d.node);
      let worst = 0;
      c.frames.forEach((frame, k) => {
        const world = worldMatrices(nodes, parent, frame.pose);
        const input = instance.driverMatrices;
        driverNodes.forEach((node, d) => {
          if (node < 0) throw new Error(`${c.name}: driver ${rig.drivers[d].name} is not a node of the GLB`);
          input.set(world[node], 16 * d);
        });
        if (frame.jump) instance.jump();
        instance.step(frame.dt);
        if (frame.steps !== undefined && instance.lastSteps !== frame.steps) {
          misses.push(`frame ${k}: ${instance.lastSteps} steps, expected ${frame.steps}`);
        }
        const rotations = instance.rotations;
        sources.forEach((source, i) => {
          const actual = source.rest ?? Array.from(rotations.subarray(4 * source.joint, 4 * source.joint + 4));
          const miss = angleBetween(actual, frame.rotations[i]);
          worst = Math.max(worst, miss);
          if (!(miss <= c.tolerance)) {
            misses.push(`frame ${k}, ${c.nodes[i]}: off by ${miss.toExponential(2)} rad (tolerance ${c.tolerance}); ` +
              `got [${actual.map((v) => v.toFixed(9)).join(', ')}], expected [${frame.rotations[i].join(', ')}]`);
          }
        });
      });
      if (c.springbones?.jumps !== undefined && instance.jumps !== c.springbones.jumps) {
        misses.push(`jumps: ${instance.jumps}, expected ${c.springbones.jumps}`);
      }
      misses.worst = worst;
    } finally {
      instance.dispose();
    }
  } finally {
    rig.dispose();
  }
  return misses;
}

async function main() {
  const options = parseArguments(process.argv.slice(2));
  const { createSpringBones } = await importSpringBones(options.module);
  const sb = await createSpringBones();
  const folders = options.cases ? [options.cases] : [join(here, 'cases'), join(here, 'vrm', 'cases')];
  const files = folders.flatMap((folder) => readdirSync(folder).filter((f) => f.endsWith('.json')).sort()
    .map((f) => ({ folder, f, shown: options.cases ? f : relative(here, join(folder, f)) })))
    .filter(({ shown }) => options.names.length === 0 || options.names.some((n) => shown.includes(n)));
  if (files.length === 0) {
    console.error(`no cases in ${folders.join(', ')}${options.names.length ? ` matching ${options.names.join(', ')}` : ''}`);
    return 1;
  }
  let failed = 0;
  for (const { folder, f: name, shown: f } of files) {
    let misses;
    try {
      misses = replay(sb, join(folder, name));
    } catch (error) {
      misses = [`threw ${error?.stack ?? error}`];
    }
    if (misses.length === 0) {
      console.log(`ok    ${f} (largest difference ${misses.worst.toExponential(2)} rad)`);
    } else {
      failed += 1;
      console.log(`MISS  ${f}: ${misses.length} miss${misses.length === 1 ? '' : 'es'}`);
      for (const m of misses.slice(0, 10)) console.log(`      ${m}`);
      if (misses.length > 10) console.log(`      ... and ${misses.length - 10} more`);
    }
  }
  console.log(`${files.length - failed} of ${files.length} cases pass (springbones ${sb.version})`);
  return failed === 0 ? 0 : 1;
}

process.exitCode = await main();
