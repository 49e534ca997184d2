// Opens the demo page for a browser test: serves the repository in-process on a free port and
// drives Debian's Chromium (headless, no sandbox, background networking off, software WebGL
// through SwiftShader) with playwright-core. Collects console errors and page errors.
//
// Needs the WebAssembly module (scripts/build wasm) and /usr/bin/chromium (or CHROMIUM_PATH).
import assert from 'node:assert/strict';
import { existsSync, mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, join } from 'node:path';
import { after, before } from 'node:test';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';
import { startServer } from '../../scripts/lib/serve.mjs';

export const root = join(dirname(fileURLToPath(import.meta.url)), '..', '..');
export const artifacts = join(root, 'tests', 'artifacts');
const chromiumPath = process.env.CHROMIUM_PATH ?? '/usr/bin/chromium';

/**
 * A reason to skip (no Chromium), or false. Only for a quick local `node --test` without the
 * browser: scripts/test sets SPRINGBONES_REQUIRE_BROWSER=1 (it installs Chromium), and there a
 * missing browser fails every test instead of skipping it.
 */
export const skip = !existsSync(chromiumPath) && process.env.SPRINGBONES_REQUIRE_BROWSER !== '1'
  ? `no Chromium at ${chromiumPath}` : false;

/**
 * Opens the demo (openDemo) before a test file's tests and closes it after them; `opened` gets
 * the page and its console errors once it is open (not called when the browser is skipped):
 *   let page, consoleErrors;
 *   useDemoPage((demo) => ({ page, consoleErrors } = demo));
 */
export function useDemoPage(opened, options) {
  let close;
  before(async () => {
    if (skip) return;
    const demo = await openDemo(options);
    close = demo.close;
    opened(demo);
  });
  after(async () => {
    await close?.();
  });
}

/**
 * Serves the repository, opens web/demo/ (or `page`, e.g. 'babylon.html', waiting for
 * window[readyHook].ready) and waits until the sample wearable is loaded.
 * `beforeOpen(page)`, if given, runs before the page is opened (e.g. to route its requests).
 * `requests` lists the paths the page asked the server for, in order; `consoleWarnings` its
 * console warnings.
 * @returns {Promise<{ page, consoleErrors: string[], consoleWarnings: string[], requests: string[],
 *                     close: () => Promise<void> }>}
 */
export function openDemo({ page: demoPage = '', readyHook = 'springbonesDemo', beforeOpen = null, viewport } = {}) {
  return openPage(`/web/demo/${demoPage}`, (hook) => window[hook]?.ready === true, { arg: readyHook, beforeOpen, viewport });
}

/**
 * The window a test's page opens in unless it asks for another. Without a GPU every frame is
 * drawn on the CPU (SwiftShader), at a cost that follows the canvas's pixels, and the demo pages
 * draw every frame: in a 1280 x 800 window their canvas is 900 x 800 pixels, and a test waits on
 * those frames. 820 x 500 keeps the pages' wide layout (the panel beside the canvas above 800 px)
 * with a canvas of 440 x 500. A test about what a user sees at a given size (tests/browser/
 * view.test.mjs) asks for that size.
 */
export const kTestViewport = { width: 820, height: 500 };
/** A desktop browser's window: what the wide layout is designed for. */
export const kWideViewport = { width: 1280, height: 800 };

/**
 * Serves the repository, opens `path` in Chromium, in a window of `viewport` (kTestViewport unless
 * given), and waits until `ready(arg)` (a function evaluated in the page) is true;
 * `beforeOpen(page)` runs first. Same result as openDemo.
 */
export async function openPage(path, ready, { arg = null, beforeOpen = null, viewport = kTestViewport } = {}) {
  assert.ok(existsSync(join(root, 'web/dist/springbones_wasm.wasm')), 'build the WebAssembly module first: scripts/build wasm');
  const { server } = await startServer({ port: 0 });
  const { port } = server.address();
  const profileDir = mkdtempSync(join(tmpdir(), 'springbones-chromium-'));
  const context = await chromium.launchPersistentContext(profileDir, {
    executablePath: chromiumPath,
    headless: true,
    viewport,
    args: [
      '--no-sandbox', '--disable-gpu', '--disable-background-networking', '--disable-component-update',
      '--disable-sync', '--no-first-run',
      // software WebGL without a GPU (SwiftShader through ANGLE); newer Chromium wants the opt-in
      '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
    ],
  }).catch((error) => {
    server.close();
    rmSync(profileDir, { recursive: true, force: true });
    throw error;
  });
  const close = async () => {
    await context.close();
    server.close();
    rmSync(profileDir, { recursive: true, force: true });
  };
  const consoleErrors = [], consoleWarnings = [], requests = [];
  let page;
  try {
    page = context.pages()[0] ?? await context.newPage();
    page.on('console', (m) => { if (m.type() === 'error') consoleErrors.push(m.text()); });
    page.on('pageerror', (e) => consoleErrors.push(`page error: ${e.message}`));
    page.on('console', (m) => { if (m.type() === 'warning') consoleWarnings.push(m.text()); });
    page.on('request', (r) => requests.push(new URL(r.url()).pathname));
    // Generous waits: software WebGL on a 2-core machine shared with builds can take a while;
    // these are limits for a hung page, not timings.
    page.setDefaultTimeout(90000);
    if (beforeOpen) await beforeOpen(page);
    await page.goto(`http://127.0.0.1:${port}${path}`);
    await page.waitForFunction(ready, arg, { timeout: 180000 });
  } catch (error) {
    // The caller gets no close(): without this, Chromium and the server would keep the test
    // process alive forever after a failed start.
    await close().catch(() => {});
    throw error;
  }
  return { page, consoleErrors, consoleWarnings, requests, close };
}

/**
 * The library's modules (web/ outside the demo's own folder, the glue in web/dist/ included) the
 * page loaded without a <link rel="modulepreload"> for them: each is a request the browser only
 * starts once the module importing it has arrived, a round trip more on a cold first visit. The
 * creator tools (with json_arguments.js, which only they import) and the readers are left out:
 * they load on first use, after the first render, by design (the three.js page's creator panel
 * reads the sample GLB's bytes).
 */
export function libraryModulesNotPreloaded(page) {
  return page.evaluate(() => {
    const preloaded = new Set([...document.querySelectorAll('link[rel=modulepreload]')].map((l) => l.href));
    return performance.getEntriesByType('resource')
      .map((entry) => entry.name)
      .filter((url) => /\/web\/(?!demo\/).*\.js$/.test(new URL(url).pathname) && !/creator_tools|readers|json_arguments/.test(url))
      .filter((url) => !preloaded.has(url));
  });
}

/** Largest absolute difference between two equally long arrays. */
export const maxAbsDiff = (a, b) => a.reduce((m, v, i) => Math.max(m, Math.abs(v - b[i])), 0);

/**
 * The demo's joint rotations after `seconds` of `animation` from rest, paused and advanced by the
 * debug hook, so the same settings give the same frames.
 */
export function rotationsAfter(page, animation, seconds) {
  return page.evaluate(([clip, s]) => {
    const d = window.springbonesDemo;
    d.setPaused(true);
    d.setAnimation(clip);
    d.reset();
    d.advance(s);
    return d.rotations();
  }, [animation, seconds]);
}

/**
 * The demo's joint rotations once the running frame loop has moved some joint by more than
 * `threshold` from `before`: waited for frame by frame rather than slept on, since a loaded
 * machine may run few frames in any fixed interval. Fails (the page's default limit for a hung
 * page) when the joints never move.
 */
export async function rotationsMovedFrom(page, before, threshold = 1e-3) {
  const moved = await page.waitForFunction(([a, t]) => {
    const b = window.springbonesDemo.rotations();
    return b.length === a.length && b.some((v, i) => Math.abs(v - a[i]) > t) ? b : null;
  }, [before, threshold]).catch((error) => {
    throw new Error(`the joints did not move by more than ${threshold}: ${error.message}`);
  });
  return moved.jsonValue();
}
