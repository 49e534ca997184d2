// The first loadRig of a preview in Chromium after an idle second, with the API's idle warm-up
// (web/warm_up.js) and without it: each sample a new browser with a new profile (no code cache),
// the two pages interleaved, unthrottled. Prints the medians (and ranges) of loadRig,
// createInstance and the first step. Page: scripts/benchmarks/pages/first_load.html.
//
//   node scripts/benchmarks/bench_first_load.mjs [samples]      (after scripts/build wasm; default 7)
import { loadavg } from 'node:os';
import { freshBrowser } from './lib/bench_browser.mjs';
import { median } from './lib/bench_rigs.mjs';
import { startServer } from '../lib/serve.mjs';

const samples = Number(process.argv[2] ?? 7);
if (!Number.isInteger(samples) || samples < 1) throw new Error(`samples must be a positive integer, got ${process.argv[2]}`);

const { server, url: base } = await startServer({ port: 0, isolated: false });
const modes = ['on', 'off'];
const results = { on: [], off: [] };
const loadBefore = loadavg()[0];
let version = null;
try {
  for (let s = 0; s < samples; s++) {
    for (const mode of s % 2 ? [...modes].reverse() : modes) {
      const browser = await freshBrowser();
      try {
        version ??= browser.version;
        await browser.page.goto(`${base}scripts/benchmarks/pages/first_load.html?warmup=${mode}`);
        await browser.page.waitForFunction(() => window.firstLoad !== undefined || window.benchError !== undefined);
        const { result, error } = await browser.page.evaluate(() => ({ result: window.firstLoad, error: window.benchError }));
        if (error || browser.errors.length) throw new Error(error ?? browser.errors.join('\n'));
        results[mode].push(result);
      } finally {
        await browser.close();
      }
    }
  }
} finally {
  server.close();
}

const range = (values) => `${median(values).toFixed(1)} (${Math.min(...values).toFixed(1)}-${Math.max(...values).toFixed(1)})`;
console.log(`first loadRig after an idle second, Chromium ${version}, ${samples} fresh profiles each, ` +
  `load average ${loadBefore.toFixed(1)} before and ${loadavg()[0].toFixed(1)} after; medians (range), ms`);
console.log(`${'warm-up'.padEnd(8)}${'loadRig'.padStart(20)}${'createInstance'.padStart(20)}${'first step'.padStart(20)}`);
for (const mode of modes) {
  const r = results[mode];
  console.log(`${mode.padEnd(8)}${range(r.map((x) => x.loadRigMs)).padStart(20)}${range(r.map((x) => x.createInstanceMs)).padStart(20)}` +
    `${range(r.map((x) => x.firstStepMs)).padStart(20)}`);
}
