// A preview's second visit: each cold page (scripts/benchmarks/pages/cold_*.html) opened in a new
// Chromium with a new profile, unthrottled, then again in the same browser after the harness's
// 3 s (the HTTP cache and Chromium's compiled-code cache warm), the two libraries' pages
// interleaved. Prints per library the medians of the second visit's parts (the cold page's own
// timings, cold_start.mjs) and the requests it made. `--cache VALUE` serves every file with that
// Cache-Control (default no-cache, as scripts/lib/serve.mjs: each file revalidated, a round trip
// before its use; `max-age=600` lets the browser use its copy without asking).
//
//   node scripts/benchmarks/bench_second_visit.mjs [samples] [--cache max-age=600] [--query fetch=...]
// (after scripts/build wasm; default 7 samples). scripts/benchmarks/trace_cold_page.mjs --second
// traces one.
import { loadavg } from 'node:os';
import { coldVisit, fillGzipCopies, freshBrowser, LINKS, REVISIT_AFTER_MS } from './lib/bench_browser.mjs';
import { median } from './lib/bench_rigs.mjs';
import { startServer } from '../lib/serve.mjs';

const args = process.argv.slice(2);
const option = (name, fallback) => {
  const i = args.indexOf(`--${name}`);
  if (i < 0) return fallback;
  const [, value] = args.splice(i, 2);
  if (value === undefined) throw new Error(`--${name} needs a value`);
  return value;
};
const cacheControl = option('cache', 'no-cache');
const query = option('query', '');
const samples = Number(args[0] ?? 7);
if (!Number.isInteger(samples) || samples < 1) throw new Error(`samples must be a positive integer, got ${args[0]}`);

const PARTS = [
  ['libraryMs', 'library total'], ['importMs', '  import the library JS'], ['startMs', '  module start'],
  ['wearMs', '  wear the item'], ['loadMs', '  first load'], ['loadRigMs', '    of which loadRig'], ['stepMs', '  first step'],
  ['navigationToDrawableMs', 'navigation to the first drawable frame'], ['navigationToFirstFrameMs', 'navigation to the first simulated frame'],
  ['longestTaskMs', 'longest task (0: none of 50 ms)'], ['requests', 'requests'], ['pageKB', 'KB on the wire'],
];

const { server, url: base } = await startServer({ port: 0, isolated: false, cacheControl });
const pages = [
  { library: 'springbones', url: `${base}scripts/benchmarks/pages/cold_springbones.html${query ? `?${query}` : ''}` },
  { library: 'three-vrm', url: `${base}scripts/benchmarks/pages/cold_threevrm.html` },
];
const results = { springbones: [], 'three-vrm': [] };
const loadBefore = loadavg();
let version = null;
try {
  await fillGzipCopies(pages.map((page) => page.url));
  for (let s = 0; s < samples; s++) {
    for (const page of s % 2 ? [...pages].reverse() : pages) {
      const browser = await freshBrowser();
      try {
        version ??= browser.version;
        await coldVisit(browser, page.url, LINKS[0]);
        await browser.page.waitForTimeout(REVISIT_AFTER_MS);
        const again = await coldVisit(browser, page.url, LINKS[0]);
        results[page.library].push(again);
      } finally {
        await browser.close();
      }
    }
    console.error(`second visit: sample ${s + 1} of ${samples}`);
  }
} finally {
  server.close();
}

const loadAfter = loadavg();
console.log(`second visit, unthrottled, ${REVISIT_AFTER_MS / 1000} s after the first in the same browser; Chromium ${version}; ` +
  `Cache-Control: ${cacheControl}; ${samples} fresh profiles per page, interleaved; load average ` +
  `${loadBefore.map((x) => x.toFixed(2)).join(' ')} before, ${loadAfter.map((x) => x.toFixed(2)).join(' ')} after; medians (range), ms`);
console.log(`${''.padEnd(42)}${'springbones'.padStart(22)}${'three-vrm'.padStart(22)}`);
const cell = (values) => (values.every(Number.isFinite)
  ? `${median(values).toFixed(1)} (${Math.min(...values).toFixed(0)}-${Math.max(...values).toFixed(0)})` : '-').padStart(22);
for (const [key, label] of PARTS) {
  console.log(`${label.padEnd(42)}${cell(results.springbones.map((r) => r[key]))}${cell(results['three-vrm'].map((r) => r[key]))}`);
}
