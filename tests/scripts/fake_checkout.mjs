// A throwaway checkout for the tests of the build scripts: the real scripts/build and its helpers
// copied into a temporary folder, beside a fake `cmake` (first on PATH) that logs its arguments
// and writes what a WebAssembly build would leave in web/dist/, and a fake scripts/lib/minify.mjs.
// The scripts run as they are, with no compiler: each test takes well under a second of CPU.
import { spawn, spawnSync } from 'node:child_process';
import { chmodSync, copyFileSync, mkdirSync, mkdtempSync, readFileSync, rmSync, writeFileSync, existsSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

export const repoRoot = join(dirname(fileURLToPath(import.meta.url)), '..', '..');

const kCopied = ['scripts/build', 'scripts/lib/build_lock.sh', 'scripts/lib/cmake_preset.sh',
  'scripts/lib/dist_freshness.mjs'];

// Logs "cmake <args>" to $FAKE_CMAKE_LOG; sleeps $FAKE_CMAKE_SLEEP seconds in a build; a build of
// wasm-release writes the two files of each module to web/dist/. Fails when the build folder's
// cache names another folder, as CMake does.
const kFakeCmake = `#!/usr/bin/env bash
echo "cmake $*" >>"$FAKE_CMAKE_LOG"
if [ "$1" = --preset ]; then
  cache="build/$2/CMakeCache.txt"
  if [ -f "$cache" ] && ! grep -qx "CMAKE_CACHEFILE_DIR:INTERNAL=$PWD/build/$2" "$cache"; then
    echo "CMake Error: The current CMakeCache.txt directory is different" >&2
    exit 1
  fi
  mkdir -p "build/$2"
  printf 'CMAKE_CACHEFILE_DIR:INTERNAL=%s\\nCMAKE_HOME_DIRECTORY:INTERNAL=%s\\n' "$PWD/build/$2" "$PWD" >"$cache"
elif [ "$1" = --build ]; then
  sleep "\${FAKE_CMAKE_SLEEP:-0}"
  if [ "$3" = wasm-release ]; then
    mkdir -p web/dist
    for m in springbones_wasm springbones_readers springbones_creator_tools; do
      echo module >web/dist/$m.js
      echo module >web/dist/$m.wasm
    done
  fi
fi
`;

const kFakeMinify = `import { writeFileSync } from 'node:fs';
writeFileSync(new URL('../../web/dist/springbones.min.js', import.meta.url), 'bundle\\n');
`;

/** Makes a fake checkout; returns its paths and a cleanup. */
export function makeFakeCheckout() {
  const dir = mkdtempSync(join(tmpdir(), 'springbones-scripts-'));
  for (const file of kCopied) {
    mkdirSync(dirname(join(dir, file)), { recursive: true });
    copyFileSync(join(repoRoot, file), join(dir, file));
  }
  writeFileSync(join(dir, 'scripts/lib/minify.mjs'), kFakeMinify);
  mkdirSync(join(dir, 'bin'));
  writeFileSync(join(dir, 'bin/cmake'), kFakeCmake);
  chmodSync(join(dir, 'bin/cmake'), 0o755);
  // A few of the inputs web/dist/ is built from.
  mkdirSync(join(dir, 'src/simulation'), { recursive: true });
  writeFileSync(join(dir, 'src/simulation/solver.cpp'), '// a source\n');
  mkdirSync(join(dir, 'web/demo'), { recursive: true });
  writeFileSync(join(dir, 'web/springbones.js'), '// the API\n');
  writeFileSync(join(dir, 'web/demo/index.html'), '<!doctype html>\n');
  writeFileSync(join(dir, 'CMakeLists.txt'), '# the build\n');
  const log = join(dir, 'cmake.log');
  return {
    dir,
    log,
    env: (extra = {}) => ({ ...process.env, PATH: `${join(dir, 'bin')}:${process.env.PATH}`, FAKE_CMAKE_LOG: log, ...extra }),
    cmakeCalls: () => (existsSync(log) ? readFileSync(log, 'utf8').trim().split('\n').filter(Boolean) : []),
    cleanup: () => rmSync(dir, { recursive: true, force: true }),
  };
}

/** Runs `scripts/build args` in the checkout to its end: { status, stdout, stderr }. */
export function runBuild(checkout, args, env = {}) {
  const result = spawnSync('scripts/build', args, { cwd: checkout.dir, env: checkout.env(env), encoding: 'utf8', timeout: 30000 });
  return { status: result.status, stdout: result.stdout, stderr: result.stderr };
}

/**
 * Starts `command` (a bash line, with the build lock's functions loaded) in the checkout and
 * resolves once `ready` (a predicate on the checkout) holds; returns the child.
 */
export async function startHolder(checkout, command, ready) {
  const child = spawn('bash', ['-c', `source scripts/lib/build_lock.sh; ${command}`],
    { cwd: checkout.dir, env: checkout.env(), stdio: 'ignore', detached: true });
  const deadline = Date.now() + 10000;
  while (!ready()) {
    if (Date.now() > deadline) throw new Error(`the lock holder did not start: ${command}`);
    await new Promise((resolve) => setTimeout(resolve, 20));
  }
  return child;
}

/** Ends a holder started by startHolder, with its children (the whole process group). */
export async function stopHolder(child) {
  if (child.exitCode !== null || child.signalCode !== null) return;
  const exited = new Promise((resolve) => child.once('exit', resolve));
  process.kill(-child.pid, 'SIGTERM');
  await exited;
}
