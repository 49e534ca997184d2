// Where a cold page's time goes, from a Chromium trace: opens a cold page (scripts/benchmarks/pages/
// cold_<page>.html) in a new profile, on one of the benchmark's links, records a trace of the visit
// through the DevTools protocol (Tracing: devtools.timeline, v8, v8.wasm, the compile events,
// loading, user timing), and prints
//   - every request: when it was sent and finished (ms after navigation), its status and whether
//     it came from the HTTP cache, its bytes on the wire;
//   - the renderer's main thread before the page's mark (first-drawable-frame on a first visit,
//     first-simulated-frame on a second): the time of its tasks by what they ran (script
//     evaluation and compilation per file, HTML parsing, GC, frames, WebAssembly), and the time it
//     was idle;
//   - the WebAssembly events (compilation, the code cache's hits and writes).
// With --second, the visit traced is a second one: the page is opened first unthrottled, then
// again in the same browser after the harness's 3 s (its HTTP cache and compiled-code cache warm),
// on the link. The trace's JSON goes to build/bench/trace-<page>-<visit>-<sample>.json (open it
// in Chromium's DevTools, Performance panel).
//
//   node scripts/benchmarks/trace_cold_page.mjs [--second] [--link "slow 4G"] [--samples 1] [--query fetch=...]
//     [--cache max-age=600] [page ...]
// --cache: every file's Cache-Control (default no-cache, scripts/lib/serve.mjs).
// pages: springbones (default) and threevrm. After scripts/build wasm.
import { mkdirSync, writeFileSync } from 'node:fs';
import { loadavg } from 'node:os';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { freshBrowser, LINKS, REVISIT_AFTER_MS } from './lib/bench_browser.mjs';
import { commandLine } from './lib/command_line.mjs';
import { startServer } from '../lib/serve.mjs';

const root = join(dirname(fileURLToPath(import.meta.url)), '..', '..');
const CATEGORIES = [
  '-*', 'devtools.timeline', 'disabled-by-default-devtools.timeline', 'toplevel', 'v8', 'v8.execute', 'v8.wasm',
  'disabled-by-default-v8.compile', 'disabled-by-default-v8.wasm.detailed', 'loading', 'blink.user_timing', 'netlog',
  'disabled-by-default-devtools.timeline.frame', 'blink', 'navigation',
];

const args = process.argv.slice(2);
const { option, flag } = commandLine(args);
const second = flag('second');
const link = LINKS.find((l) => l.name === option('link', second ? 'LAN' : 'slow 4G'));
if (!link) throw new Error(`unknown link (expected ${LINKS.map((l) => l.name).join(', ')})`);
const samples = Number(option('samples', 1));
if (!Number.isInteger(samples) || samples < 1) throw new Error('--samples must be a positive integer');
const query = option('query', '');
const cacheControl = option('cache', 'no-cache');
const pages = args.length ? args : ['springbones'];
for (const page of pages) if (!['springbones', 'threevrm'].includes(page)) throw new Error(`unknown page ${page} (springbones, threevrm)`);

/** Records a trace (CDP Tracing on the page's session) around `run`; resolves to its events. */
async function traced(browser, run) {
  const cdp = await browser.context.newCDPSession(browser.page);
  await cdp.send('Tracing.start', { transferMode: 'ReturnAsStream', traceConfig: { includedCategories: CATEGORIES } });
  await run();
  const done = new Promise((resolve) => cdp.once('Tracing.tracingComplete', resolve));
  await cdp.send('Tracing.end');
  const { stream } = await done;
  let text = '';
  for (;;) {
    const chunk = await cdp.send('IO.read', { handle: stream });
    text += chunk.base64Encoded ? Buffer.from(chunk.data, 'base64').toString() : chunk.data;
    if (chunk.eof) break;
  }
  await cdp.send('IO.close', { handle: stream });
  await cdp.detach();
  const parsed = JSON.parse(text);
  return Array.isArray(parsed) ? parsed : parsed.traceEvents;
}

/** Opens the page and waits for its result, with the link's conditions. */
async function visit(browser, url, conditions) {
  const cdp = await browser.context.newCDPSession(browser.page);
  await cdp.send('Network.enable');
  await cdp.send('Network.setCacheDisabled', { cacheDisabled: false });
  if (conditions) await cdp.send('Network.emulateNetworkConditions', { offline: false, ...conditions });
  await browser.page.goto(url);
  await browser.page.waitForFunction(() => window.coldResult !== undefined || window.benchError !== undefined);
  const { result, error } = await browser.page.evaluate(() => ({ result: window.coldResult, error: window.benchError }));
  await cdp.detach();
  if (error || browser.errors.length) throw new Error(`${url}: ${error ?? browser.errors.join('\n')}`);
  return result;
}

const ms = (us) => us / 1000;

/** The breakdown of one trace (see the top of this file). */
function breakdown(events, markName) {
  const threadNames = new Map();
  for (const e of events) if (e.ph === 'M' && e.name === 'thread_name') threadNames.set(`${e.pid}:${e.tid}`, e.args.name);
  const mark = events.find((e) => e.cat?.includes('blink.user_timing') && e.name === markName);
  if (!mark) throw new Error(`no ${markName} mark in the trace`);
  const mainKey = `${mark.pid}:${mark.tid}`;
  // Navigation start: the renderer's navigationStart of the page's document (the last one before the mark).
  const starts = events.filter((e) => e.name === 'navigationStart' && e.pid === mark.pid && e.ts <= mark.ts);
  const t0 = starts.length ? Math.max(...starts.map((e) => e.ts)) : Math.min(...events.filter((e) => e.ts > 0).map((e) => e.ts));
  const end = mark.ts;

  // Requests (devtools.timeline's Resource* events, from every process).
  const requests = new Map();
  for (const e of events) {
    const d = e.args?.data;
    if (!d?.requestId) continue;
    const r = requests.get(d.requestId) ?? { id: d.requestId };
    if (e.name === 'ResourceSendRequest') Object.assign(r, { url: d.url, sent: e.ts, priority: d.priority });
    if (e.name === 'ResourceReceiveResponse') Object.assign(r, { status: d.statusCode, fromCache: d.fromCache || d.fromServiceWorker, response: e.ts });
    if (e.name === 'ResourceFinish') Object.assign(r, { finished: e.ts, bytes: d.encodedDataLength });
    requests.set(d.requestId, r);
  }
  // The page's own (Chromium's WebUI pages, chrome://, load beside it in a fresh profile).
  const list = [...requests.values()].filter((r) => /^https?:/.test(r.url ?? '') && r.sent >= t0 - 1000).sort((a, b) => a.sent - b.sent);

  // The main thread's tasks before the mark, each attributed to what it ran.
  const main = events.filter((e) => `${e.pid}:${e.tid}` === mainKey && e.ph === 'X' && e.ts >= t0 && e.ts < end);
  // Busy time: the union of the tasks (a task nested in another counts once).
  const tasks = main.filter((e) => e.name === 'RunTask' || e.name === 'ThreadControllerImpl::RunTask').sort((a, b) => a.ts - b.ts);
  let busy = 0, until = 0;
  for (const e of tasks) {
    const stop = Math.min(e.ts + (e.dur ?? 0), end);
    if (stop > until) busy += stop - Math.max(e.ts, until);
    until = Math.max(until, stop);
  }
  const kinds = new Map();
  const add = (key, dur) => kinds.set(key, (kinds.get(key) ?? 0) + dur);
  const short = (url) => (url ? new URL(url).pathname.split('/').slice(-2).join('/') : '');
  // Self time of the named events inside tasks: each event's duration less its named children's.
  const named = main.filter((e) => e.name !== 'RunTask' && e.name !== 'ThreadControllerImpl::RunTask' && e.dur > 0)
    .sort((a, b) => a.ts - b.ts || b.dur - a.dur);
  const stack = [];
  const self = new Map();
  for (const e of named) {
    while (stack.length && stack.at(-1).ts + stack.at(-1).dur <= e.ts) stack.pop();
    const parent = stack.at(-1);
    if (parent) self.set(parent, (self.get(parent) ?? parent.dur) - e.dur);
    stack.push(e);
  }
  // What the script events were about (their own url, else the nearest ancestor's).
  const label = (e) => {
    const d = e.args?.data ?? e.args ?? {};
    const url = d.url ?? d.fileName ?? d.stackTrace?.[0]?.url ?? '';
    return url ? `${e.name} ${short(url)}` : e.name;
  };
  for (const e of named) add(label(e), self.get(e) ?? e.dur);
  const wasm = events.filter((e) => /wasm/i.test(e.cat ?? '') || /wasm/i.test(e.name))
    .filter((e) => e.ts >= t0 && e.ph !== 'M');
  const wasmNames = new Map();
  for (const e of wasm) {
    const entry = wasmNames.get(e.name) ?? { count: 0, dur: 0, first: e.ts, thread: threadNames.get(`${e.pid}:${e.tid}`) };
    entry.count++;
    entry.dur += e.dur ?? 0;
    wasmNames.set(e.name, entry);
  }
  return { t0, end, list, busy, kinds, wasmNames };
}

function print(page, visitName, result, b) {
  console.log(`\n== ${page}, ${visitName} on ${link.name}: ${link.conditions ? '' : 'unthrottled; '}mark at ${ms(b.end - b.t0).toFixed(1)} ms ` +
    `(the page: drawable ${result.navigationToDrawableMs.toFixed(1)}, simulated ${result.navigationToFirstFrameMs.toFixed(1)}, library ${result.libraryMs.toFixed(1)} ms)`);
  console.log('requests: sent -> response -> finished (ms after navigation), status, cache, bytes');
  for (const r of b.list) {
    const at = (t) => (t === undefined ? '-' : ms(t - b.t0).toFixed(1)).padStart(8);
    console.log(`${at(r.sent)}${at(r.response)}${at(r.finished)}  ${String(r.status ?? '-').padStart(3)} ${r.fromCache ? 'cache' : 'net  '} ` +
      `${String(r.bytes ?? '-').padStart(8)}  ${new URL(r.url).pathname}`);
  }
  console.log(`main thread before the mark: ${ms(b.busy).toFixed(1)} ms in tasks of ${ms(b.end - b.t0).toFixed(1)}; self time by event (>= 0.5 ms):`);
  for (const [key, dur] of [...b.kinds].sort((x, y) => y[1] - x[1])) {
    if (dur >= 500) console.log(`${ms(dur).toFixed(1).padStart(8)}  ${key}`);
  }
  console.log('WebAssembly events after navigation: count, summed ms, first at (ms), thread');
  for (const [name, e] of b.wasmNames) {
    console.log(`${String(e.count).padStart(5)}${ms(e.dur).toFixed(1).padStart(8)}${ms(e.first - b.t0).toFixed(1).padStart(9)}  ${name} (${e.thread ?? '?'})`);
  }
}

const { server, url: base } = await startServer({ port: 0, isolated: false, cacheControl });
const outDir = join(root, 'build', 'bench');
mkdirSync(outDir, { recursive: true });
console.log(`load average ${loadavg().map((x) => x.toFixed(2)).join(' ')}; Cache-Control: ${cacheControl}`);
try {
  for (let s = 1; s <= samples; s++) {
    for (const page of s % 2 ? pages : [...pages].reverse()) {
      const url = `${base}scripts/benchmarks/pages/cold_${page}.html${query ? `?${query}` : ''}`;
      const browser = await freshBrowser();
      try {
        let result;
        if (second) {
          await visit(browser, url, null);
          await browser.page.waitForTimeout(REVISIT_AFTER_MS);
        }
        const events = await traced(browser, async () => { result = await visit(browser, url, link.conditions); });
        const visitName = second ? 'second visit' : 'first visit';
        const file = join(outDir, `trace-${page}-${second ? 'second' : 'first'}-${s}.json`);
        writeFileSync(file, JSON.stringify({ traceEvents: events }));
        print(page, visitName, result, breakdown(events, second ? 'first-simulated-frame' : 'first-drawable-frame'));
        console.log(`(trace: ${file})`);
      } finally {
        await browser.close();
      }
    }
  }
} finally {
  server.close();
}
console.log(`load average ${loadavg().map((x) => x.toFixed(2)).join(' ')}`);
