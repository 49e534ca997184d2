// A build folder that came with a copied or moved tree (scripts/lib/cmake_preset.sh): configured
// afresh in place, with one line that says so, where CMake alone would refuse its cache.
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import { cpSync, existsSync, mkdirSync, readFileSync, symlinkSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { test } from 'node:test';
import { makeFakeCheckout, runBuild } from './fake_checkout.mjs';

const kMovedLine = /^build\/native-release: its CMake cache was made in (.*); configuring it afresh here$/;

function writeCache(dir, madeIn, home) {
  mkdirSync(join(dir, 'CMakeFiles'), { recursive: true });
  writeFileSync(join(dir, 'CMakeFiles', 'Makefile.cmake'), `# stale, of ${madeIn}\n`);
  writeFileSync(join(dir, 'CMakeCache.txt'),
    `CMAKE_CACHEFILE_DIR:INTERNAL=${madeIn}\nCMAKE_HOME_DIRECTORY:INTERNAL=${home}\n`);
}

test('a cache made in a folder that no longer exists is replaced, with one line', (t) => {
  const checkout = makeFakeCheckout();
  t.after(checkout.cleanup);
  const buildDir = join(checkout.dir, 'build/native-release');
  writeCache(buildDir, '/gone/checkout/build/native-release', '/gone/checkout');
  const result = runBuild(checkout, ['native']);
  assert.equal(result.status, 0, result.stderr);
  const lines = result.stdout.split('\n').filter((line) => kMovedLine.test(line));
  assert.deepEqual(lines, ['build/native-release: its CMake cache was made in /gone/checkout/build/native-release; configuring it afresh here']);
  assert.ok(!existsSync(join(buildDir, 'CMakeFiles')), 'the stale CMakeFiles/ is gone');
  assert.match(readFileSync(join(buildDir, 'CMakeCache.txt'), 'utf8'), new RegExp(`=${buildDir}\n`));
});

test('a build folder copied from another checkout that still exists is configured for this one', (t) => {
  const first = makeFakeCheckout();
  const second = makeFakeCheckout();
  t.after(first.cleanup);
  t.after(second.cleanup);
  assert.equal(runBuild(first, ['native']).status, 0);
  cpSync(join(first.dir, 'build'), join(second.dir, 'build'), { recursive: true });
  const result = runBuild(second, ['native']);
  assert.equal(result.status, 0, result.stderr);
  const moved = result.stdout.split('\n').map((line) => line.match(kMovedLine)).filter(Boolean);
  assert.deepEqual(moved.map((match) => match[1]), [join(first.dir, 'build/native-release')]);
  assert.deepEqual(second.cmakeCalls().map((c) => c.split(' -j')[0]),
    ['cmake --preset native-release', 'cmake --build --preset native-release']);
});

test('a cache made here is kept, without a word', (t) => {
  const checkout = makeFakeCheckout();
  t.after(checkout.cleanup);
  assert.equal(runBuild(checkout, ['native']).status, 0);
  const again = runBuild(checkout, ['native']);
  assert.equal(again.status, 0, again.stderr);
  assert.ok(!again.stdout.split('\n').some((line) => kMovedLine.test(line)), again.stdout);
});

test('a cache that names this checkout through a symbolic link is kept', (t) => {
  const checkout = makeFakeCheckout();
  t.after(checkout.cleanup);
  const link = `${checkout.dir}-link`;
  symlinkSync(checkout.dir, link);
  t.after(() => spawnSync('rm', ['-f', link]));
  const buildDir = join(checkout.dir, 'build/native-release');
  writeCache(buildDir, join(link, 'build/native-release'), link);
  const result = spawnSync('bash', ['-c', 'source scripts/lib/cmake_preset.sh; forget_moved_cmake_cache build/native-release'],
    { cwd: checkout.dir, encoding: 'utf8' });
  assert.equal(result.status, 0, result.stderr);
  assert.equal(result.stdout, '');
  assert.ok(existsSync(join(buildDir, 'CMakeCache.txt')));
  assert.ok(existsSync(join(buildDir, 'CMakeFiles')));
});
