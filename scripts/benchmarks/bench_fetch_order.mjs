// When should a cold preview start the module's download? Opens the cold springbones page
// (scripts/benchmarks/pages/cold_springbones.html) once per fetch order and the three-vrm page beside
// it, each visit in a new Chromium with a new profile, on the emulated links of the benchmark
// (slow 4G and 4G by default), interleaved, and prints per order the medians of: the first
// drawable frame and the first simulated frame, each as the gap to three-vrm's on the same link,
// and the longest main-thread task. The orders are cold_start.mjs's.
//
//   node scripts/benchmarks/bench_fetch_order.mjs [samples] [order...]
// Environment: BENCH_LINKS (comma-separated link names, default "slow 4G,4G"), CHROMIUM_PATH.
import { coldVisit, fillGzipCopies, freshBrowser, LINKS } from './lib/bench_browser.mjs';
import { median } from './lib/bench_rigs.mjs';
import { startServer } from '../lib/serve.mjs';

const ORDERS = ['after-draw', 'at-wear', 'after-downloads', 'with-glbs', 'with-glbs-low', 'preload', 'preload-low'];
const samples = Number(process.argv[2] ?? 5);
const orders = process.argv.length > 3 ? process.argv.slice(3) : ORDERS;
for (const order of orders) {
  if (!ORDERS.includes(order)) throw new Error(`unknown fetch order ${order} (expected ${ORDERS.join(', ')})`);
}
if (!Number.isInteger(samples) || samples < 1) throw new Error(`samples must be a positive integer, got ${process.argv[2]}`);
const linkNames = (process.env.BENCH_LINKS ?? 'slow 4G,4G').split(',');
const links = linkNames.map((name) => {
  const link = LINKS.find((l) => l.name === name);
  if (!link) throw new Error(`unknown link ${name} (expected ${LINKS.map((l) => l.name).join(', ')})`);
  return link;
});

const { server, url: base } = await startServer({ port: 0, isolated: false });
const pages = [
  ...orders.map((order) => ({ key: order, url: `${base}scripts/benchmarks/pages/cold_springbones.html?fetch=${order}` })),
  { key: 'three-vrm', url: `${base}scripts/benchmarks/pages/cold_threevrm.html` },
];
const results = {};  // link -> page key -> [result]
try {
  await fillGzipCopies(pages.map((page) => page.url));
  for (let s = 0; s < samples; s++) {
    for (const link of links) {
      results[link.name] ??= {};
      // A different order each sample, so that a drift in the machine's load hits every page.
      const rotated = pages.map((_, i) => pages[(i + s) % pages.length]);
      for (const page of rotated) {
        const browser = await freshBrowser();
        try {
          (results[link.name][page.key] ??= []).push(await coldVisit(browser, page.url, link));
        } finally {
          await browser.close();
        }
      }
    }
    console.error(`fetch order: sample ${s + 1} of ${samples}`);
  }
} finally {
  server.close();
}

const f = (x) => (x >= 0 ? `+${x.toFixed(0)}` : x.toFixed(0)).padStart(8);
console.log(`cold start by fetch order, medians of ${samples} samples (gaps: springbones minus three-vrm on the same link)`);
console.log(`${'link'.padEnd(9)}${'order'.padEnd(17)}${'drawable'.padStart(9)}${'simulated'.padStart(10)}${'sim-draw'.padStart(10)}${'longest task'.padStart(14)}`);
for (const link of links) {
  const byPage = results[link.name];
  const m = (key, field) => median(byPage[key].map((r) => r[field]));
  const vrmDrawable = m('three-vrm', 'navigationToDrawableMs'), vrmSimulated = m('three-vrm', 'navigationToFirstFrameMs');
  console.log(`${link.name.padEnd(9)}${'three-vrm'.padEnd(17)}${vrmDrawable.toFixed(0).padStart(9)}${vrmSimulated.toFixed(0).padStart(10)}` +
    `${(vrmSimulated - vrmDrawable).toFixed(0).padStart(10)}${m('three-vrm', 'longestTaskMs').toFixed(0).padStart(14)}`);
  for (const order of orders) {
    const drawable = m(order, 'navigationToDrawableMs'), simulated = m(order, 'navigationToFirstFrameMs');
    console.log(`${link.name.padEnd(9)}${order.padEnd(17)}${f(drawable - vrmDrawable)} ${f(simulated - vrmSimulated)}` +
      `${(simulated - drawable).toFixed(0).padStart(10)}${m(order, 'longestTaskMs').toFixed(0).padStart(14)}`);
  }
}
