// The build lock (scripts/lib/build_lock.sh) as scripts/build meets it: one lock per build folder
// of one checkout; a script that has to wait says who holds the lock, since when, and how to go on.
import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import { existsSync, readFileSync } from 'node:fs';
import { join } from 'node:path';
import { test } from 'node:test';
import { makeFakeCheckout, runBuild, startHolder, stopHolder } from './fake_checkout.mjs';

const lockHasNote = (checkout, name) => () => {
  try {
    return readFileSync(join(checkout.dir, 'build', `${name}.lock`), 'utf8').includes('pid=');
  } catch {
    return false;
  }
};

test('a held lock is named with its pid, its start and its command, and SPRINGBONES_BUILD_LOCK_WAIT=0 does not wait', async (t) => {
  const checkout = makeFakeCheckout();
  t.after(checkout.cleanup);
  const holder = await startHolder(checkout, 'with_build_lock wasm-release sleep 30', lockHasNote(checkout, 'wasm-release'));
  t.after(() => stopHolder(holder));
  const result = runBuild(checkout, ['wasm'], { SPRINGBONES_BUILD_LOCK_WAIT: '0' });
  assert.equal(result.status, 75, result.stderr);
  assert.match(result.stderr, new RegExp(`build/wasm-release\\.lock is held by pid ${holder.pid} since \\d\\d:\\d\\d:\\d\\d UTC \\(\\d+ s ago\\): bash: sleep 30`));
  assert.match(result.stderr, /not waiting \(SPRINGBONES_BUILD_LOCK_WAIT=0\)/);
  assert.deepEqual(checkout.cmakeCalls(), [], 'nothing was built');
});

test('a bounded wait gives up with the holder named again', async (t) => {
  const checkout = makeFakeCheckout();
  t.after(checkout.cleanup);
  const holder = await startHolder(checkout, 'with_build_lock native-release sleep 30', lockHasNote(checkout, 'native-release'));
  t.after(() => stopHolder(holder));
  const result = runBuild(checkout, ['native'], { SPRINGBONES_BUILD_LOCK_WAIT: '1' });
  assert.equal(result.status, 75, result.stderr);
  assert.match(result.stderr, /waiting up to 1 s \(SPRINGBONES_BUILD_LOCK_WAIT=<seconds> bounds the wait/);
  assert.match(result.stderr, new RegExp(`gave up after 1 s: .*held by pid ${holder.pid}`));
  assert.deepEqual(checkout.cmakeCalls(), []);
});

test('a waiting build says so, and builds once the holder is done', async (t) => {
  const checkout = makeFakeCheckout();
  t.after(checkout.cleanup);
  const holder = await startHolder(checkout, 'with_build_lock native-release sleep 30', lockHasNote(checkout, 'native-release'));
  t.after(() => stopHolder(holder));
  const waiter = spawn('scripts/build', ['native'], { cwd: checkout.dir, env: checkout.env() });
  let stderr = '';
  const sawWaiting = new Promise((resolve) => {
    waiter.stderr.on('data', (chunk) => {
      stderr += chunk;
      if (stderr.includes('build lock: waiting (')) resolve();
    });
  });
  const exited = new Promise((resolve) => waiter.once('exit', resolve));
  await sawWaiting;
  assert.deepEqual(checkout.cmakeCalls(), [], 'it waits before it configures');
  await stopHolder(holder);
  assert.equal(await exited, 0, stderr);
  assert.deepEqual(checkout.cmakeCalls().map((c) => c.split(' -j')[0]),
    ['cmake --preset native-release', 'cmake --build --preset native-release']);
  assert.equal(readFileSync(join(checkout.dir, 'build/native-release.lock'), 'utf8'), '', 'the note goes with the lock');
});

test('another checkout, or another build folder of this one, does not wait', async (t) => {
  const first = makeFakeCheckout();
  const second = makeFakeCheckout();
  t.after(first.cleanup);
  t.after(second.cleanup);
  const holder = await startHolder(first, 'with_build_lock wasm-release sleep 30', lockHasNote(first, 'wasm-release'));
  t.after(() => stopHolder(holder));
  const elsewhere = runBuild(second, ['wasm'], { SPRINGBONES_BUILD_LOCK_WAIT: '0' });
  assert.equal(elsewhere.status, 0, elsewhere.stderr);
  const otherFolder = runBuild(first, ['native'], { SPRINGBONES_BUILD_LOCK_WAIT: '0' });
  assert.equal(otherFolder.status, 0, otherFolder.stderr);
  assert.ok(first.cmakeCalls().every((c) => c.includes('native-release')), first.cmakeCalls().join('\n'));
});

test('a holder that left no note is reported as such, with how to find it', async (t) => {
  const checkout = makeFakeCheckout();
  t.after(checkout.cleanup);
  const holder = await startHolder(checkout, 'mkdir -p build; exec flock build/wasm-release.lock bash -c "touch build/held; sleep 30"',
    () => existsSync(join(checkout.dir, 'build/held')));
  t.after(() => stopHolder(holder));
  const result = runBuild(checkout, ['wasm'], { SPRINGBONES_BUILD_LOCK_WAIT: '0' });
  assert.equal(result.status, 75);
  assert.match(result.stderr, /build\/wasm-release\.lock is held by a process that left no note .*'fuser -v build\/wasm-release\.lock' names it/);
});

test('a wait that is not a number of seconds is refused before anything runs', (t) => {
  const checkout = makeFakeCheckout();
  t.after(checkout.cleanup);
  const result = runBuild(checkout, ['native'], { SPRINGBONES_BUILD_LOCK_WAIT: 'soon' });
  assert.equal(result.status, 2);
  assert.match(result.stderr, /SPRINGBONES_BUILD_LOCK_WAIT=soon: expected a number of seconds \(0: do not wait\)/);
  assert.deepEqual(checkout.cmakeCalls(), []);
});
