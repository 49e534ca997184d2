// The Chromium half of the benchmark: serves the repository with COOP/COEP (scripts/serve.mjs),
// drives Debian's Chromium with playwright-core and prints
//   - the conditions: Chromium version, cross-origin isolation, the timer step and the
//     requestAnimationFrame interval the page observed, CPUs, load average;
//   - per frame, rAF-paced and in a tight loop, three-vrm, our solver path and our adapter on the
//     rigs of scripts/lib/bench_rigs.mjs (page: scripts/bench_pages/frames.html);
//   - the cold start on the demo's sample, each sample in a new browser with a new profile
//     (pages: scripts/bench_pages/cold_*.html), then the same page once more in that browser (a
//     second visit), medians;
// and returns the summary line (ratios are three-vrm's time over ours). Also writes
// build/bench/browser-latest.json.
//
// Environment: CHROMIUM_PATH (default /usr/bin/chromium), BENCH_COLD_SAMPLES (default 9, at least
// 7 for the README), BENCH_FRAMES (tight-loop frames per run, default 600), BENCH_RAF_BATCHES
// (default 5 batches of 60 callbacks after 60 warm-up callbacks).
import assert from 'node:assert/strict';
import { existsSync, mkdirSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { cpus, loadavg, tmpdir } from 'node:os';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { gzipSync } from 'node:zlib';
import { chromium } from 'playwright-core';
import { startServer } from '../serve.mjs';
import { median, rigName } from './bench_rigs.mjs';

const root = join(dirname(fileURLToPath(import.meta.url)), '..', '..');
const chromiumPath = process.env.CHROMIUM_PATH ?? '/usr/bin/chromium';
const COLD_SAMPLES = Number(process.env.BENCH_COLD_SAMPLES ?? 9);
const REVISIT_AFTER_MS = 3000;
const LOOP = {
  frames: Number(process.env.BENCH_FRAMES ?? 600), runs: 5,
  warmup: 60, batches: Number(process.env.BENCH_RAF_BATCHES ?? 5), batchSize: 60,
};
const LIBRARIES = ['three-vrm', 'solver', 'adapter'];
const FIVE_THOUSAND = '100x10x5';
const ONE_WEARABLE = '1x3x5';

// The flags that work on this machine (as tests/browser/demoPage.mjs), plus no throttling of
// timers and frames: the benchmark page is never in the background, but say so anyway.
const ARGS = [
  '--no-sandbox', '--disable-gpu', '--disable-background-networking', '--disable-component-update',
  '--disable-sync', '--no-first-run', '--disable-background-timer-throttling',
  '--disable-renderer-backgrounding', '--disable-backgrounding-occluded-windows',
];

/** A new Chromium with a new, empty profile (no HTTP cache, no code cache); close() removes it. */
async function freshBrowser() {
  const profile = mkdtempSync(join(tmpdir(), 'springbones-bench-'));
  const context = await chromium.launchPersistentContext(profile, { executablePath: chromiumPath, headless: true, args: ARGS })
    .catch((error) => { rmSync(profile, { recursive: true, force: true }); throw error; });
  const page = context.pages()[0] ?? await context.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  page.setDefaultTimeout(600000);
  return {
    page, errors, version: context.browser()?.version() ?? null,
    close: async () => { await context.close(); rmSync(profile, { recursive: true, force: true }); },
  };
}

/** Opens `url` and waits for `ready` (a window property), failing with the page's errors. */
async function open(browser, url, ready) {
  await browser.page.goto(url);
  await browser.page.waitForFunction((name) => window[name] !== undefined || window.benchError !== undefined, ready);
  const error = await browser.page.evaluate(() => window.benchError);
  if (error || browser.errors.length) throw new Error(`${url}: ${error ?? browser.errors.join('\n')}`);
}

/** Per-frame costs of every library on every rig, in one page of one browser. */
async function perFrame(base, log) {
  const browser = await freshBrowser();
  try {
    await open(browser, `${base}scripts/bench_pages/frames.html`, 'benchFramesReady');
    const { page } = browser;
    const conditions = await page.evaluate(() => window.benchFrames.conditions());
    const rigs = await page.evaluate(() => window.benchFrames.rigs);
    const results = [];
    for (let i = 0; i < rigs.length; i++) {
      const row = { rig: rigName(rigs[i]), joints: rigs[i][0] * rigs[i][1] * rigs[i][2] };
      for (const library of LIBRARIES) {
        row[library] = await page.evaluate(([r, l, o]) => window.benchFrames.run(r, l, o), [i, library, LOOP]);
      }
      results.push(row);
      log(`  measured ${row.rig}`);
    }
    assert.deepEqual(browser.errors, [], 'the per-frame page reported errors');
    return { version: browser.version, conditions, results };
  } finally {
    await browser.close();
  }
}

/**
 * COLD_SAMPLES cold starts of each library, interleaved so that the machine's load hits both; after
 * each, the same page again in the same browser (a second visit: HTTP cache, and Chromium's cache of
 * the code it compiled, which it writes a while after the first compilation: REVISIT_AFTER_MS).
 */
async function coldStarts(base, log) {
  const samples = { springbones: [], 'three-vrm': [] }, revisits = { springbones: [], 'three-vrm': [] };
  for (let s = 0; s < COLD_SAMPLES; s++) {
    const order = s % 2 === 0 ? ['springbones', 'threevrm'] : ['threevrm', 'springbones'];
    for (const page of order) {
      const browser = await freshBrowser();
      try {
        const pageUrl = `${base}scripts/bench_pages/cold_${page}.html`;
        await open(browser, pageUrl, 'coldResult');
        const result = await browser.page.evaluate(() => window.coldResult);
        samples[result.library].push(result);
        await browser.page.waitForTimeout(REVISIT_AFTER_MS);
        await open(browser, pageUrl, 'coldResult');
        revisits[result.library].push(await browser.page.evaluate(() => window.coldResult));
      } finally {
        await browser.close();
      }
    }
    log(`  cold start sample ${s + 1} of ${COLD_SAMPLES}`);
  }
  const joints = new Set([...samples.springbones, ...samples['three-vrm']].map((r) => r.joints));
  assert.equal(joints.size, 1, `both pages must simulate the same joints, got ${[...joints]}`);
  const mediansOf = (byLibrary) => {
    const medians = {};
    for (const [library, list] of Object.entries(byLibrary)) {
      medians[library] = {};
      for (const key of Object.keys(list[0])) {
        if (typeof list[0][key] === 'number') medians[library][key] = median(list.map((r) => r[key]));
      }
    }
    return medians;
  };
  return { samples, medians: mediansOf(samples), revisits, revisitMedians: mediansOf(revisits), joints: [...joints][0] };
}

const gzipKB = (paths) => paths.reduce((n, p) => n + gzipSync(readFileSync(join(root, p)), { level: 9 }).length, 0) / 1024;

export async function runBrowserBench({ log = console.log } = {}) {
  if (!existsSync(chromiumPath)) throw new Error(`no Chromium at ${chromiumPath} (set CHROMIUM_PATH)`);
  if (!existsSync(join(root, 'web/dist/springbones_wasm.wasm'))) throw new Error('build the WebAssembly module first: scripts/build wasm');
  const loadBefore = loadavg();
  const { server, url } = await startServer({ port: 0 });
  let frames, cold;
  try {
    log(`== springbones vs three-vrm, Chromium (headless, pages served with COOP/COEP) ==`);
    frames = await perFrame(url, log);
    cold = await coldStarts(url, log);
  } finally {
    server.close();
  }
  const loadAfter = loadavg();
  const c = frames.conditions;
  const download = {
    springbones: gzipKB(['web/springbones.js', 'web/three/springBonesThree.js', 'web/dist/springbones_wasm.js', 'web/dist/springbones_wasm.wasm']),
    threeVrm: gzipKB(['node_modules/@pixiv/three-vrm-springbone/lib/three-vrm-springbone.module.js']),
    threeVrmMinified: gzipKB(['node_modules/@pixiv/three-vrm-springbone/lib/three-vrm-springbone.module.min.js']),
  };

  const lines = [];
  const out = (line = '') => { lines.push(line); log(line); };
  out(`Chromium ${frames.version}; crossOriginIsolated ${c.crossOriginIsolated}; timer step ${c.timerStepUs.toFixed(1)} us; ` +
    `rAF every ${c.rafIntervalMs.toFixed(2)} ms; ${c.hardwareConcurrency} CPUs in the page, ${cpus().length} on the machine ` +
    `(${cpus()[0]?.model ?? 'unknown'}); load average ${loadBefore.map((x) => x.toFixed(2)).join(' ')} before, ` +
    `${loadAfter.map((x) => x.toFixed(2)).join(' ')} after`);
  const f = (x, d = 3) => (Number.isFinite(x) ? x.toFixed(d) : '-').padStart(9);
  const table = (title, pick) => {
    out(title);
    out('rig          joints | three-vrm update ms  frame ms | solver ms | adapter update ms  frame ms');
    for (const r of frames.results) {
      const v = pick(r);
      out(`${r.rig.padEnd(12)} ${String(r.joints).padStart(6)} |${f(v['three-vrm'].updateMs)}${f(v['three-vrm'].frameMs)} |` +
        `${f(v.solver.updateMs)} |${f(v.adapter.updateMs)}${f(v.adapter.frameMs)}`);
    }
  };
  const rafIntervals = frames.results.flatMap((r) => LIBRARIES.map((l) => r[l].raf.intervalMs));
  table(`per frame, rAF-paced: one frame's work in each requestAnimationFrame callback, ${LOOP.warmup} callbacks of warm-up, ` +
    `then the median of ${LOOP.batches} batches of ${LOOP.batchSize} (each the batch's summed time / ${LOOP.batchSize}); ` +
    `callbacks every ${Math.min(...rafIntervals).toFixed(1)}-${Math.max(...rafIntervals).toFixed(1)} ms (medians per run)`, (r) => ({
    'three-vrm': r['three-vrm'].raf, solver: r.solver.raf, adapter: r.adapter.raf,
  }));
  table(`per frame, tight loop: one warm-up run, then the median of ${LOOP.runs} runs of ${LOOP.frames} frames, each run timed as a whole`, (r) => ({
    'three-vrm': r['three-vrm'].tight, solver: r.solver.tight, adapter: r.adapter.tight,
  }));
  const sb = cold.medians.springbones, vrm = cold.medians['three-vrm'];
  out(`cold start on the demo's sample (${cold.joints} joints), medians of ${COLD_SAMPLES} samples, each a new browser with a new profile, ms:`);
  out('part                                         springbones   three-vrm');
  const row = (label, a, b) => out(`${label.padEnd(44)}${f(a, 1).padStart(12)}${f(b, 1).padStart(12)}`);
  row('import the library JS', sb.importMs, vrm.importMs);
  row('module start (createSpringBones)', sb.startMs, NaN);
  row('first load (loadRig + attachWearable / joints)', sb.loadMs, vrm.loadMs);
  row('  of which loadRig', sb.loadRigMs, NaN);
  row('  of which attachWearable (bone matching)', sb.attachMs, NaN);
  row('first step', sb.stepMs, vrm.stepMs);
  row('library total (median of per-sample sums)', sb.libraryMs, vrm.libraryMs);
  row('navigation to the first simulated frame', sb.navigationToFirstFrameMs, vrm.navigationToFirstFrameMs);
  const sb2 = cold.revisitMedians.springbones, vrm2 = cold.revisitMedians['three-vrm'];
  out(`the same page again in the same browser, ${REVISIT_AFTER_MS / 1000} s later (HTTP and compiled-code caches warm), medians, ms:`);
  row('library total', sb2.libraryMs, vrm2.libraryMs);
  row('  of which loadRig / joints', sb2.loadRigMs, vrm2.loadMs);
  row('navigation to the first simulated frame', sb2.navigationToFirstFrameMs, vrm2.navigationToFirstFrameMs);
  out(`download, gzip -9: springbones ${download.springbones.toFixed(1)} KB (API, adapter, glue, wasm), three-vrm-springbone ${download.threeVrm.toFixed(1)} KB ` +
    `(the module build the page imports; ${download.threeVrmMinified.toFixed(1)} KB minified)`);

  const at = (rig) => frames.results.find((r) => r.rig === rig);
  const big = at(FIVE_THOUSAND), small = at(ONE_WEARABLE);
  // Every ratio is rAF-paced (as a page runs) and compares updates: three-vrm's manager.update
  // over our solver path or our adapter's update. One wearable per frame: the adapter, as a
  // preview calls it.
  const ratios = {
    oneWearable: small['three-vrm'].raf.updateMs / small.adapter.raf.updateMs,
    solver: big['three-vrm'].raf.updateMs / big.solver.raf.updateMs,
    adapter: big['three-vrm'].raf.updateMs / big.adapter.raf.updateMs,
  };
  const summary = `cold start: springbones ${sb.libraryMs.toFixed(0)} ms, three-vrm ${vrm.libraryMs.toFixed(0)} ms; ` +
    `one wearable per frame: ${ratios.oneWearable.toFixed(2)}x; 5000 joints: solver ${ratios.solver.toFixed(1)}x, adapter ${ratios.adapter.toFixed(1)}x`;

  const report = {
    date: new Date().toISOString(), chromium: frames.version, conditions: c, loadavg: { before: loadBefore, after: loadAfter },
    machineCpus: cpus().length, loop: LOOP, perFrame: frames.results, cold, download, ratios, summary, table: lines,
  };
  const outDir = join(root, 'build', 'bench');
  mkdirSync(outDir, { recursive: true });
  writeFileSync(join(outDir, 'browser-latest.json'), JSON.stringify(report, null, 2));
  return report;
}
