// Loading the demo's sample wearable (web/demo/assets: hair_wearable.glb, 15 joints, and its
// entity's springBones object, as a page has it after JSON.parse of the fetched entity):
//   - first: the first loadRig of a fresh Node process, after createSpringBones. WebAssembly is
//     compiled lazily, function by function, on first call, so this is the load a page pays
//     once; each sample is a new process (`node bench_sample_load.mjs --child`), median of
//     SAMPLE_PROCESSES;
//   - warm: the median of WARM_LOADS loads in one process, after the first.
import { execFileSync } from 'node:child_process';
import { readFileSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import { performance } from 'node:perf_hooks';
import { median } from './bench_rigs.mjs';

const ASSETS = new URL('../../../web/demo/assets/', import.meta.url);
const SAMPLE_PROCESSES = 7, WARM_LOADS = 200;

function sample() {
  const bytes = readFileSync(new URL('hair_wearable.glb', ASSETS));
  const manifest = JSON.parse(readFileSync(new URL('manifest.json', ASSETS), 'utf8'));
  const metadata = JSON.parse(readFileSync(new URL(manifest.files['hair_wearable.glb'].metadata, ASSETS), 'utf8'));
  return { bytes, springBones: metadata, contentHash: manifest.files['hair_wearable.glb'].contentHash };
}

/** In this process: createSpringBones, the first loadRig, then WARM_LOADS more. */
async function measureInProcess(warmLoads) {
  const { bytes, springBones, contentHash } = sample();
  const { createSpringBones } = await import('../../../web/springbones.js');
  let t = performance.now();
  const sb = await createSpringBones();
  const createMs = performance.now() - t;
  t = performance.now();
  const rig = sb.loadRig(bytes, springBones, { contentHash });
  const firstMs = performance.now() - t;
  const joints = rig.joints.length;
  rig.dispose();
  const warm = [];
  for (let i = 0; i < warmLoads; i++) {
    t = performance.now();
    sb.loadRig(bytes, springBones, { contentHash }).dispose();
    warm.push(performance.now() - t);
  }
  return { joints, createMs, firstMs, warmMs: warm.length ? median(warm) : null };
}

/** First loadRig in fresh processes and the warm load; numbers in ms. */
export async function measureSampleLoad() {
  const firsts = [];
  for (let i = 0; i < SAMPLE_PROCESSES; i++) {
    const out = execFileSync(process.execPath, [fileURLToPath(import.meta.url), '--child'], { encoding: 'utf8' });
    firsts.push(JSON.parse(out).firstMs);
  }
  const { joints, warmMs } = await measureInProcess(WARM_LOADS);
  return { joints, firstMs: median(firsts), firstRangeMs: [Math.min(...firsts), Math.max(...firsts)], processes: SAMPLE_PROCESSES, warmMs };
}

if (process.argv[2] === '--child') {
  process.stdout.write(JSON.stringify(await measureInProcess(0)));
}
