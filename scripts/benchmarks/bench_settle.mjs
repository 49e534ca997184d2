// How long instance.settle() takes on the demo's sample wearable in Node, for each integrator: the
// avatar's hips bent forward and turned (a pose far from the rest pose, so every chain has to
// fall into a new balance), settle(seconds) on a fresh instance each run, alone and with the
// demo's body colliders. Prints the steps it ran and the fastest, median and 90th percentile of
// RUNS runs after WARMUP. A benchmark, never a test (no timing in
// tests): `node scripts/benchmarks/bench_settle.mjs [seconds]` after `scripts/build wasm`.
import { readFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { performance } from 'node:perf_hooks';
import { createSpringBones } from '../../web/springbones.js';

const root = join(dirname(fileURLToPath(import.meta.url)), '..', '..');
const assets = join(root, 'web', 'demo', 'assets');
const seconds = Number(process.argv[2] ?? 2);
const WARMUP = 20, RUNS = 200;

const sb = await createSpringBones();
const glb = new Uint8Array(readFileSync(join(assets, 'hair_wearable.glb')));
const metadata = JSON.parse(readFileSync(join(assets, 'hair_wearable.metadata.json'), 'utf8'));

// Every driver turned 0.9 rad about X and 0.6 rad about Y (the avatar bent and turned) and moved.
function bentDrivers(rest, out) {
  const a = 0.9, b = 0.6;
  const ca = Math.cos(a), sa = Math.sin(a), cb = Math.cos(b), sb2 = Math.sin(b);
  // R = Rx(a) * Ry(b), column-major.
  const r = [cb, sa * sb2, -ca * sb2, 0, 0, ca, sa, 0, sb2, -sa * cb, ca * cb, 0];
  for (let d = 0; d < rest.length; d += 16) {
    for (let col = 0; col < 4; col++) {
      const x = rest[d + 4 * col], y = rest[d + 4 * col + 1], z = rest[d + 4 * col + 2];
      out[d + 4 * col] = r[0] * x + r[4] * y + r[8] * z + (col === 3 ? 0.3 : 0);
      out[d + 4 * col + 1] = r[1] * x + r[5] * y + r[9] * z;
      out[d + 4 * col + 2] = r[2] * x + r[6] * y + r[10] * z;
      out[d + 4 * col + 3] = rest[d + 4 * col + 3];
    }
  }
}

// As loaded alone, and as the demo loads it: with the body colliders (a hair tail may rest on one).
for (const [label, options] of [['alone', {}], ["with 'dcl-body' colliders", { colliders: 'dcl-body', hitRadius: 0.01 }]]) {
  const rig = sb.loadRig(glb, metadata, options);
  console.log(`sample wearable ${label}: ${rig.joints.length} joints, ${rig.chains.length} chains, ${rig.colliders.length} colliders; settle(${seconds}), Node ${process.version}`);
  for (const integrator of ['vrm', 'xpbd']) {
    const times = [];
    let steps = 0;
    for (let run = 0; run < WARMUP + RUNS; run++) {
      const inst = rig.createInstance({ integrator });
      bentDrivers(Float32Array.from(inst.driverMatrices), inst.driverMatrices);
      const t0 = performance.now();
      steps = inst.settle(seconds);
      const ms = performance.now() - t0;
      inst.dispose();
      if (run >= WARMUP) times.push(ms);
    }
    times.sort((x, y) => x - y);
    // The fastest and the median: on a loaded machine the slow runs measure the other processes.
    const at = (q) => times[Math.floor(q * (times.length - 1))].toFixed(3);
    console.log(`  ${integrator.padEnd(4)}  steps ${String(steps).padStart(3)}  fastest ${at(0)} ms  median ${at(0.5)} ms  90% ${at(0.9)} ms`);
  }
  rig.dispose();
}
