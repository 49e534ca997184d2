// When web/dist/ can be used without building (scripts/lib/dist_freshness.mjs), and
// `scripts/build --if-stale wasm` (what scripts/demo and scripts/package run) acting on it.
import assert from 'node:assert/strict';
import { readFileSync, renameSync, rmSync, statSync, utimesSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { test } from 'node:test';
import { distState, writeDistStamp } from '../../scripts/lib/dist_freshness.mjs';
import { makeFakeCheckout, runBuild, startHolder, stopHolder } from './fake_checkout.mjs';

/** Sets a file's (or folder's) times to `seconds` after 2026-01-01. */
function age(path, seconds) {
  const when = new Date(Date.UTC(2026, 0, 1) + seconds * 1000);
  utimesSync(path, when, when);
}

/** A checkout whose web/dist/ was built (by the fake cmake) and stamped at t = 100 s, its sources at t = 0. */
function builtCheckout(t) {
  const checkout = makeFakeCheckout();
  t.after(checkout.cleanup);
  assert.equal(runBuild(checkout, ['wasm']).status, 0);
  for (const path of ['src/simulation/solver.cpp', 'web/springbones.js', 'web/demo/index.html', 'CMakeLists.txt',
    'scripts/lib/minify.mjs']) {
    age(join(checkout.dir, path), 0);
  }
  writeDistStamp(checkout.dir, Date.UTC(2026, 0, 1) + 100_000);
  return checkout;
}

test('a build leaves a stamp that lists every file of web/dist/, dated when the build started', (t) => {
  const checkout = makeFakeCheckout();
  t.after(checkout.cleanup);
  const before = Date.now();
  assert.equal(runBuild(checkout, ['wasm']).status, 0);
  const stamp = join(checkout.dir, 'web/dist/.complete');
  assert.deepEqual(JSON.parse(readFileSync(stamp, 'utf8')).files, ['springbones.min.js', 'springbones_creator_tools.js',
    'springbones_creator_tools.wasm', 'springbones_readers.js', 'springbones_readers.wasm', 'springbones_wasm.js',
    'springbones_wasm.wasm']);
  const stampTime = statSync(stamp).mtimeMs;
  assert.ok(stampTime >= before - 1000, 'not older than the build');
  assert.ok(stampTime <= statSync(join(checkout.dir, 'web/dist/springbones.min.js')).mtimeMs,
    'not newer than the last file the build wrote: the build started before it');
  assert.equal(distState(checkout.dir).fresh, true, distState(checkout.dir).reason);
});

test('web/dist/ without a stamp is incomplete', (t) => {
  const checkout = builtCheckout(t);
  rmSync(join(checkout.dir, 'web/dist/.complete'));
  assert.deepEqual(distState(checkout.dir),
    { fresh: false, reason: 'web/dist/.complete is missing: no complete build of web/dist/ is recorded' });
});

test('a file of the build missing from web/dist/ makes it incomplete', (t) => {
  const checkout = builtCheckout(t);
  rmSync(join(checkout.dir, 'web/dist/springbones_readers.wasm'));
  assert.deepEqual(distState(checkout.dir), { fresh: false, reason: 'web/dist/springbones_readers.wasm is missing' });
});

test('a source saved after the build started makes web/dist/ stale, one saved before does not', (t) => {
  const checkout = builtCheckout(t);
  age(join(checkout.dir, 'src/simulation/solver.cpp'), 99);
  assert.equal(distState(checkout.dir).fresh, true);
  age(join(checkout.dir, 'src/simulation/solver.cpp'), 101);
  assert.deepEqual(distState(checkout.dir),
    { fresh: false, reason: 'src/simulation/solver.cpp changed after web/dist/ was built' });
});

test('a source removed or added after the build makes web/dist/ stale, whatever the times say', (t) => {
  const checkout = builtCheckout(t);
  const source = join(checkout.dir, 'src/simulation/solver.cpp');
  const moved = join(checkout.dir, 'src/simulation/integrator.cpp');
  renameSync(source, moved);
  assert.deepEqual(distState(checkout.dir), { fresh: false, reason: 'src/simulation/solver.cpp was removed after web/dist/ was built' });
  writeFileSync(source, '// back\n');
  age(source, 0);
  assert.deepEqual(distState(checkout.dir), { fresh: false, reason: 'src/simulation/integrator.cpp was added after web/dist/ was built' });
  rmSync(moved);
  assert.equal(distState(checkout.dir).fresh, true, distState(checkout.dir).reason);
});

test('the demo page and web/dist/ itself are not sources of the build', (t) => {
  const checkout = builtCheckout(t);
  age(join(checkout.dir, 'web/demo/index.html'), 500);
  age(join(checkout.dir, 'web/dist/springbones.min.js'), 500);
  assert.equal(distState(checkout.dir).fresh, true, distState(checkout.dir).reason);
  age(join(checkout.dir, 'web/springbones.js'), 500);
  assert.equal(distState(checkout.dir).fresh, false);
});

test('--if-stale uses a fresh web/dist/ without building, even while a build holds the lock', async (t) => {
  const checkout = builtCheckout(t);
  const calls = checkout.cmakeCalls().length;
  const holder = await startHolder(checkout, 'with_build_lock wasm-release sleep 30',
    () => { try { return readFileSync(join(checkout.dir, 'build/wasm-release.lock'), 'utf8').includes('pid='); } catch { return false; } });
  t.after(() => stopHolder(holder));
  const result = runBuild(checkout, ['--if-stale', 'wasm'], { SPRINGBONES_BUILD_LOCK_WAIT: '0' });
  assert.equal(result.status, 0, result.stderr);
  assert.equal(result.stdout.trim(),
    'scripts/build: web/dist/ is complete (7 files) and newer than its sources; not building');
  assert.equal(checkout.cmakeCalls().length, calls, 'cmake did not run');
});

test('--if-stale builds a stale web/dist/, says why, and the next run does not build', (t) => {
  const checkout = builtCheckout(t);
  writeFileSync(join(checkout.dir, 'src/simulation/solver.cpp'), '// an edit\n');
  const calls = checkout.cmakeCalls().length;
  const result = runBuild(checkout, ['--if-stale', 'wasm']);
  assert.equal(result.status, 0, result.stderr);
  assert.match(result.stdout, /^scripts\/build: src\/simulation\/solver\.cpp changed after web\/dist\/ was built; building$/m);
  assert.deepEqual(checkout.cmakeCalls().slice(calls).map((c) => c.split(' -j')[0]),
    ['cmake --preset wasm-release', 'cmake --build --preset wasm-release']);
  const again = runBuild(checkout, ['--if-stale', 'wasm']);
  assert.match(again.stdout, /not building/);
  assert.equal(checkout.cmakeCalls().length, calls + 2);
});

test('--if-stale is refused for the native build', (t) => {
  const checkout = makeFakeCheckout();
  t.after(checkout.cleanup);
  const result = runBuild(checkout, ['--if-stale', 'native']);
  assert.equal(result.status, 2);
  assert.match(result.stderr, /--if-stale is for wasm only/);
  assert.deepEqual(checkout.cmakeCalls(), []);
});
