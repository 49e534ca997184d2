// A change to the cold page or the library, before against after: the springbones cold page served
// from two checkouts (each with its web/dist built, node_modules beside it) and the three-vrm page
// beside them, each visit in a new Chromium with a new profile, interleaved in a rotating order,
// on one of the benchmark's links. Prints the medians of the page's timings per page and the gaps
// to three-vrm's, with every sample's drawable frame (the spread says how far to trust a median).
// With --second, the visit measured is a second one (as bench_second_visit.mjs).
//
//   node scripts/benchmarks/bench_cold_before_after.mjs BEFORE_ROOT AFTER_ROOT [samples] [--link "slow 4G"]
//     [--second] [--query wasm=api] [--cache max-age=600]
// e.g. BEFORE_ROOT a `git worktree add` of the commit before, built with scripts/build wasm.
import { loadavg } from 'node:os';
import { resolve } from 'node:path';
import { coldVisit, fillGzipCopies, freshBrowser, LINKS, REVISIT_AFTER_MS } from './lib/bench_browser.mjs';
import { commandLine } from './lib/command_line.mjs';
import { median } from './lib/bench_rigs.mjs';
import { startServer } from '../lib/serve.mjs';

const args = process.argv.slice(2);
const { option, flag } = commandLine(args);
const second = flag('second');
const link = LINKS.find((l) => l.name === option('link', 'slow 4G'));
if (!link) throw new Error(`unknown link (expected ${LINKS.map((l) => l.name).join(', ')})`);
const query = option('query', '');
const cacheControl = option('cache', 'no-cache');
const [beforeRoot, afterRoot, samplesArg] = args;
if (!beforeRoot || !afterRoot) throw new Error('usage: bench_cold_before_after.mjs BEFORE_ROOT AFTER_ROOT [samples] [options]');
const samples = Number(samplesArg ?? 7);
if (!Number.isInteger(samples) || samples < 1) throw new Error(`samples must be a positive integer, got ${samplesArg}`);

const before = await startServer({ port: 0, isolated: false, root: resolve(beforeRoot), cacheControl });
const after = await startServer({ port: 0, isolated: false, root: resolve(afterRoot), cacheControl });
const page = (base, name) => `${base}scripts/benchmarks/pages/cold_${name}.html${name === 'springbones' && query ? `?${query}` : ''}`;
const pages = [
  { key: 'before', url: page(before.url, 'springbones') },
  { key: 'after', url: page(after.url, 'springbones') },
  { key: 'three-vrm', url: page(after.url, 'threevrm') },
];
const results = {};
const loadBefore = loadavg();
try {
  await fillGzipCopies(pages.map((p) => p.url));
  for (let s = 0; s < samples; s++) {
    for (const p of pages.map((_, i) => pages[(i + s) % pages.length])) {
      const browser = await freshBrowser();
      try {
        let result = await coldVisit(browser, p.url, second ? LINKS[0] : link);
        if (second) {
          await browser.page.waitForTimeout(REVISIT_AFTER_MS);
          result = await coldVisit(browser, p.url, link);
        }
        (results[p.key] ??= []).push(result);
      } finally {
        await browser.close();
      }
    }
    console.error(`before/after: sample ${s + 1} of ${samples}`);
  }
} finally {
  before.server.close();
  after.server.close();
}

const m = (key, field) => median(results[key].map((r) => r[field]));
const KEYS = ['navigationToDrawableMs', 'navigationToFirstFrameMs', 'libraryMs', 'startMs', 'loadMs', 'longestTaskMs', 'requests'];
console.log(`${second ? 'second' : 'first'} visit on ${link.name}, Cache-Control ${cacheControl}${query ? `, ?${query}` : ''}; ` +
  `${samples} fresh profiles per page, interleaved; load average ${loadBefore.map((x) => x.toFixed(2)).join(' ')} before, ` +
  `${loadavg().map((x) => x.toFixed(2)).join(' ')} after; medians, ms`);
console.log(`${'page'.padEnd(10)}${['drawable', 'simulated', 'library', 'start', 'load', 'longest task', 'requests'].map((h) => h.padStart(13)).join('')}`);
for (const key of Object.keys(results)) console.log(`${key.padEnd(10)}${KEYS.map((k) => m(key, k).toFixed(1).padStart(13)).join('')}`);
for (const key of ['before', 'after']) {
  const gap = (field) => (m(key, field) - m('three-vrm', field)).toFixed(0);
  console.log(`${key}: drawable ${gap('navigationToDrawableMs')} ms from three-vrm's, simulated ${gap('navigationToFirstFrameMs')}; ` +
    `drawable per sample ${results[key].map((r) => r.navigationToDrawableMs.toFixed(0)).join(' ')}`);
}
console.log(`three-vrm: drawable per sample ${results['three-vrm'].map((r) => r.navigationToDrawableMs.toFixed(0)).join(' ')}`);
