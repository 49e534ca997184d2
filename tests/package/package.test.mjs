// The npm package as its users take it: scripts/package packs the tarball, and throwaway projects
// outside the repository install it with npm and use it (a Node test suite, a Vite app and an
// esbuild bundle opened in Debian's Chromium, a strict TypeScript check, the Node suite again
// under the lowest `three` of the peer range, and springbones/babylon with Babylon 4.2 and 9.x, and
// bundled with the preview's @babylonjs/core 4.2.2). Nothing here imports the checkout's web/: the
// consumers' files are in tests/package/consumer/, copied into each project.
//
// Needs npm and the registry (the projects install pinned versions), /usr/bin/chromium (or
// CHROMIUM_PATH) and Emscripten (scripts/package builds the module). Set
// SPRINGBONES_KEEP_CONSUMER=1 to keep the projects (their paths are printed).
import assert from 'node:assert/strict';
import { execFileSync, spawn, spawnSync } from 'node:child_process';
import { cpSync, existsSync, mkdirSync, mkdtempSync, readFileSync, readdirSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, join, resolve } from 'node:path';
import { after, before, describe, test } from 'node:test';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';
import { startServer } from '../../scripts/lib/serve.mjs';

const root = resolve(dirname(fileURLToPath(import.meta.url)), '..', '..');
const consumer = join(root, 'tests', 'package', 'consumer');
const sampleAssets = ['avatar.glb', 'hair_wearable.glb', 'hair_wearable.metadata.json', 'hair_wearable.entity.json'];
const chromiumPath = process.env.CHROMIUM_PATH ?? '/usr/bin/chromium';
const repoPackage = JSON.parse(readFileSync(join(root, 'package.json'), 'utf8'));

// What the consumers install, pinned. vite 7 rather than 8, which needs npm 11; esbuild in the
// range vite 7 depends on, so that the two share one install.
const kThreeHighest = '0.187.0';
const kThreeLowest = '0.160.0';
const kTools = { vite: '7.3.8', esbuild: '0.28.2', typescript: '5.9.3', '@types/three': '0.187.0' };
// The two Babylon.js lines springbones/babylon is tested with, as the repository pins them: 4.2
// (what Decentraland's preview pins; its UMD build, as its ES modules do not load in Node) and the
// current major.
const kBabylon = {
  '4.2': { babylonjs: '4.2.2', 'babylonjs-loaders': '4.2.2' },
  current: { '@babylonjs/core': '9.28.0', '@babylonjs/loaders': '9.28.0' },
};
// What Decentraland's wearable-preview itself depends on: Babylon 4.2 as ES modules, which it
// bundles (so does the test, with esbuild: unbundled they do not load in Node).
const kPreviewBabylon = { '@babylonjs/core': '4.2.2', '@babylonjs/loaders': '4.2.2' };

/** Runs a command; on failure the assertion shows its output. */
function run(command, args, cwd, env = {}) {
  const result = spawnSync(command, args, { cwd, env: { ...process.env, ...env }, encoding: 'utf8', maxBuffer: 64 << 20 });
  assert.equal(result.status, 0, `${command} ${args.join(' ')} failed in ${cwd}:\n${result.stdout}\n${result.stderr}`);
  return result.stdout;
}

// The READMEs whose ```js snippets a TypeScript user may paste, and what their relative imports
// (the repository's paths) are as the package exports them.
const kReadmes = ['README.md', 'web/three/README.md', 'web/babylon/README.md'];
const kPackageImports = [
  [/'\.\/web\/springbones\.js'/g, "'springbones'"],
  [/'\.\/web\/three\/[A-Za-z]+\.js'/g, "'springbones/three'"],
  [/'\.\/web\/babylon\/[A-Za-z]+\.js'/g, "'springbones/babylon'"],
];

/**
 * Every ```js block of the READMEs as a TypeScript module of its own in `dir` (its imports as the
 * package exports them; `export {}` so that its declarations are its own). A block is Babylon's
 * when it is in web/babylon/README.md or imports springbones/babylon, else three.js's: each kind
 * is checked against the page objects of globals_<kind>.d.ts. Returns the files by kind.
 */
function writeReadmeSnippets(dir) {
  const written = { three: [], babylon: [] };
  for (const readme of kReadmes) {
    const text = readFileSync(join(root, readme), 'utf8');
    let n = 0;
    for (const [, block] of text.matchAll(/```js\n([\s\S]*?)```/g)) {
      let code = block;
      for (const [from, to] of kPackageImports) code = code.replace(from, to);
      const kind = readme.startsWith('web/babylon/') || code.includes("'springbones/babylon'") ? 'babylon' : 'three';
      const file = `${readme.replace(/[/.]/g, '_')}_${++n}.ts`;
      writeFileSync(join(dir, file), `${code}\nexport {};\n`);
      written[kind].push(file);
    }
  }
  return written;
}

/** A throwaway project (in the system's temp folder, away from the repository's node_modules). */
function makeProject(name, dependencies, devDependencies = {}) {
  const dir = mkdtempSync(join(tmpdir(), `springbones-${name}-`));
  cpSync(consumer, dir, { recursive: true });
  for (const target of [join(dir, 'assets'), join(dir, 'web', 'public'), join(dir, 'web-inline', 'public')]) {
    mkdirSync(target, { recursive: true });
    for (const file of sampleAssets) cpSync(join(root, 'web', 'demo', 'assets', file), join(target, file));
  }
  writeFileSync(join(dir, 'package.json'), JSON.stringify({
    name: `springbones-${name}`, private: true, type: 'module', dependencies, devDependencies,
  }, null, 2));
  // Every version is pinned, so what npm's cache holds is what the registry would answer:
  // --prefer-offline takes it without asking the registry again (anything missing is fetched).
  run('npm', ['install', '--prefer-offline', '--no-audit', '--no-fund', '--loglevel=error'], dir);
  if (process.env.SPRINGBONES_KEEP_CONSUMER) console.log(`# kept: ${dir}`);
  return dir;
}

function removeProject(dir) {
  if (dir && !process.env.SPRINGBONES_KEEP_CONSUMER) rmSync(dir, { recursive: true, force: true });
}

const bin = (project, tool) => join(project, 'node_modules', '.bin', tool);

const kGpuDriverNote = /^\[\.WebGL-0x[0-9a-f]+\]GL Driver Message \(OpenGL, Performance, /;
// The colour codes of a terminal, which vite prints around its URL.
// eslint-disable-next-line no-control-regex -- the escape character is what is matched
const kAnsiColour = /\x1b\[[0-9;]*m/g;

/**
 * Opens `url` in headless Chromium until the page reports window.springbonesResult. Returns the
 * result, every console error or warning, page error and failed HTTP response, and the .wasm
 * responses.
 */
async function openPage(url) {
  const profileDir = mkdtempSync(join(tmpdir(), 'springbones-chromium-'));
  let context;
  try {
    context = await chromium.launchPersistentContext(profileDir, {
      executablePath: chromiumPath,
      headless: true,
      args: ['--no-sandbox', '--disable-gpu', '--disable-background-networking', '--disable-component-update',
        '--disable-sync', '--no-first-run', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
    });
    const page = context.pages()[0] ?? await context.newPage();
    const messages = [];
    const wasm = [];
    page.on('console', (m) => {
      // Chromium's GPU process reports software GL's performance notes (SwiftShader: "GPU stall
      // due to ReadPixels") as warnings of the page; they come from the browser, not the page.
      if (m.type() === 'warning' && kGpuDriverNote.test(m.text())) return;
      if (m.type() === 'error' || m.type() === 'warning') messages.push(`${m.type()}: ${m.text()}`);
    });
    page.on('pageerror', (e) => messages.push(`page error: ${e.message}`));
    page.on('response', (r) => {
      if (r.status() >= 400) messages.push(`HTTP ${r.status()}: ${r.url()}`);
      if (new URL(r.url()).pathname.endsWith('.wasm')) {
        wasm.push({ path: new URL(r.url()).pathname, status: r.status(), type: r.headers()['content-type'] });
      }
    });
    await page.goto(url);
    await page.waitForFunction(() => window.springbonesResult !== undefined || document.title === 'failed', null, { timeout: 90_000 })
      .catch((error) => { throw new Error(`${error.message}\n${messages.join('\n')}`); });
    const result = await page.evaluate(() => window.springbonesResult);
    return { result, messages, wasm };
  } finally {
    await context?.close();
    rmSync(profileDir, { recursive: true, force: true });
  }
}

/** Serves `dir` (a bundle's output) on a free port and opens its index.html (openPage). */
async function openBundle(dir) {
  const { server } = await startServer({ port: 0, root: dir });
  try {
    return await openPage(`http://127.0.0.1:${server.address().port}/index.html`);
  } finally {
    server.close();
  }
}

/** Starts `vite` (the dev server) in `dir` on a free port; resolves to { url, stop }. */
function startViteDevServer(project, dir) {
  const child = spawn(bin(project, 'vite'), ['--host', '127.0.0.1', '--port', '0', '--clearScreen', 'false'], { cwd: dir });
  let output = '';
  const stop = () => new Promise((resolve) => {
    if (child.exitCode !== null) return resolve();
    child.once('exit', resolve);
    child.kill();
  });
  return new Promise((resolve, reject) => {
    const timer = setTimeout(() => { stop(); reject(new Error(`vite did not start:\n${output}`)); }, 60_000);
    const read = (chunk) => {
      output += chunk;
      const url = output.replace(kAnsiColour, '').match(/Local:\s+(http:\/\/127\.0\.0\.1:\d+\/)/)?.[1];
      if (url) {
        clearTimeout(timer);
        resolve({ url, stop });
      }
    };
    child.stdout.setEncoding('utf8').on('data', read);
    child.stderr.setEncoding('utf8').on('data', read);
    child.once('exit', (code) => { clearTimeout(timer); reject(new Error(`vite exited (${code}):\n${output}`)); });
  });
}

/**
 * What the page must show in every bundle: the package loaded, the sample's bones moved, and one
 * .wasm fetched (none for springbones/inline, whose module is in the JavaScript).
 */
function assertPageWorked({ result, messages, wasm }, where, { wasmFetched = 1 } = {}) {
  assert.deepEqual(messages, [], `${where}: the console stays clean`);
  assert.equal(wasm.length, wasmFetched, `${where}: ${wasmFetched} .wasm fetched: ${JSON.stringify(wasm)}`);
  for (const response of wasm) {
    assert.equal(response.status, 200);
    assert.equal(response.type, 'application/wasm');
  }
  assert.equal(result.version, repoPackage.version);
  assert.equal(result.joints, 15);
  assert.equal(result.warnings, 0);
  assert.equal(result.finite, true);
  assert.ok(result.moved > 0.05, `${where}: the hair swings as the avatar walks (rotations moved by up to ${result.moved})`);
}

let tarball;
before(() => {
  const out = execFileSync(join(root, 'scripts', 'package'), { cwd: root, encoding: 'utf8', stdio: ['ignore', 'pipe', 'inherit'] });
  tarball = resolve(root, out.trim().split('\n').pop());
  assert.ok(existsSync(tarball), tarball);
});

describe('the tarball', () => {
  test('holds what runs: the minified API, adapter and glue (with their source maps), the three modules, the inline entry, their types, the CLI, the READMEs, CHANGELOG, LICENSE', () => {
    const files = execFileSync('tar', ['-tzf', tarball], { encoding: 'utf8' }).trim().split('\n').sort();
    assert.deepEqual(files, [
      'package/CHANGELOG.md',
      'package/LICENSE',
      'package/README.md',
      'package/bin/springbones-cli.mjs',
      'package/bin/sway.mjs',
      'package/package.json',
      'package/web/babylon/README.md',
      'package/web/babylon/index.d.ts',
      'package/web/babylon/springBoneSimulation.d.ts',
      'package/web/babylon/springBonesLoaderExtension.d.ts',
      'package/web/dist/babylon.min.js',
      'package/web/dist/babylon.min.js.map',
      'package/web/dist/chunk.min.js',
      'package/web/dist/chunk.min.js.map',
      'package/web/dist/creator_tools.min.js',
      'package/web/dist/creator_tools.min.js.map',
      'package/web/dist/inline.min.js',
      'package/web/dist/page_module.min.js',
      'package/web/dist/page_module.min.js.map',
      'package/web/dist/readers.min.js',
      'package/web/dist/readers.min.js.map',
      'package/web/dist/springbones.min.js',
      'package/web/dist/springbones.min.js.map',
      'package/web/dist/springbones_creator_tools.min.js',
      'package/web/dist/springbones_creator_tools.min.js.map',
      'package/web/dist/springbones_creator_tools.wasm',
      'package/web/dist/springbones_crowd.wasm',
      'package/web/dist/springbones_readers.min.js',
      'package/web/dist/springbones_readers.min.js.map',
      'package/web/dist/springbones_readers.wasm',
      'package/web/dist/springbones_wasm.min.js',
      'package/web/dist/springbones_wasm.min.js.map',
      'package/web/dist/springbones_wasm.wasm',
      'package/web/dist/three.min.js',
      'package/web/dist/three.min.js.map',
      'package/web/inline.d.ts',
      'package/web/springbones.d.ts',
      'package/web/three/README.md',
      'package/web/three/index.d.ts',
      'package/web/three/springBonesLoaderPlugin.d.ts',
      'package/web/three/springBonesThree.d.ts',
      'package/web/wearable/diagnostics.d.ts',
    ]);
  });

  test('package.json is publishable, with exports and types for both entries', () => {
    const pkg = JSON.parse(execFileSync('tar', ['-xzOf', tarball, 'package/package.json'], { encoding: 'utf8' }));
    assert.equal(pkg.private, undefined);
    assert.match(pkg.version, /^0\.\d+\.\d+$/);
    assert.equal(pkg.type, 'module');
    assert.equal(pkg.sideEffects, false);
    assert.ok(pkg.engines.node);
    assert.deepEqual(Object.keys(pkg.exports).sort(), ['.', './babylon', './creator-tools-wasm', './crowd-wasm', './inline', './package.json', './readers-wasm', './three', './wasm']);
    for (const entry of ['.', './three', './babylon', './inline']) {
      assert.ok(pkg.exports[entry].types.endsWith('.d.ts'), `${entry} has types`);
      assert.ok(pkg.exports[entry].default.endsWith('.js'), `${entry} has a module`);
    }
    // The command line is the package's bin, under a file name other than the library's.
    assert.deepEqual(pkg.bin, { springbones: './bin/springbones-cli.mjs' });
    // The README's relative links resolve on the registry through the repository.
    assert.match(pkg.repository.url, /^git\+https:\/\/github\.com\/[\w.-]+\/[\w.-]+\.git$/);
    const repository = pkg.repository.url.replace(/^git\+/, '').replace(/\.git$/, '');
    assert.equal(pkg.homepage, `${repository}#readme`);
    assert.equal(pkg.bugs.url, `${repository}/issues`);
    assert.equal(pkg.peerDependenciesMeta.three.optional, true);
    // The peer range is what this file tests: from kThreeLowest up to kThreeHighest's minor.
    const next = `0.${Number(kThreeHighest.split('.')[1]) + 1}.0`;
    assert.equal(pkg.peerDependencies.three, `>=${kThreeLowest} <${next}`);
    assert.equal(repoPackage.devDependencies.three, kThreeHighest, 'the repository tests the highest too');
    // Babylon: optional peers whose ranges hold the versions tested below, as the repository pins them.
    assert.equal(pkg.peerDependencies.babylonjs, '>=4.2.0 <4.3.0');
    assert.equal(pkg.peerDependencies['@babylonjs/core'],
      `>=${kPreviewBabylon['@babylonjs/core'].replace(/\.\d+$/, '.0')} <4.3.0 || >=${kBabylon.current['@babylonjs/core']} <10.0.0`);
    for (const name of ['babylonjs', '@babylonjs/core']) assert.equal(pkg.peerDependenciesMeta[name].optional, true);
    for (const deps of Object.values(kBabylon)) {
      for (const [name, version] of Object.entries(deps)) assert.equal(repoPackage.devDependencies[name], version, name);
    }
  });
});

describe(`a project with three ${kThreeHighest}, vite, esbuild and TypeScript`, () => {
  let project;
  before(() => {
    project = makeProject('consumer', { springbones: `file:${tarball}`, three: kThreeHighest }, kTools);
  });
  after(() => removeProject(project));

  test('Node: node --test loads the sample, steps and reads rotations from the installed package', () => {
    run(process.execPath, ['--test', 'node/sample.spec.mjs', 'node/loader_plugin.spec.mjs', 'node/three_internals.spec.mjs',
      'node/inline.spec.mjs'], project, { SPRINGBONES_THREE_REVISION: kThreeHighest.split('.')[1] });
  });

  test('the CLI: npx springbones hash | validate | inspect | simulate runs the installed bin', () => {
    const manifest = JSON.parse(readFileSync(join(root, 'web', 'demo', 'assets', 'manifest.json'), 'utf8'));
    const npx = (...args) => run('npx', ['--no-install', 'springbones', ...args], project);
    assert.equal(npx('hash', 'assets/hair_wearable.glb').trim(), manifest.files['hair_wearable.glb'].contentHash);
    assert.match(npx('validate', 'assets/hair_wearable.entity.json'), /hair_wearable\.entity\.json: valid$/m);
    const inspected = npx('inspect', 'assets/hair_wearable.glb', '--metadata', 'assets/hair_wearable.entity.json', '--body-shape', 'BaseMale');
    assert.match(inspected, /15 simulated joints/);
    const frames = npx('simulate', 'assets/hair_wearable.glb', '--metadata', 'assets/hair_wearable.metadata.json', '--frames', '3', '--drive', 'sway')
      .trim().split('\n').map((line) => JSON.parse(line));
    assert.equal(frames.length, 3);
    const usage = spawnSync(bin(project, 'springbones'), [], { cwd: project, encoding: 'utf8' });
    assert.equal(usage.status, 2);
    assert.match(usage.stderr, /^usage: springbones <command>/);
  });

  test('TypeScript: tsc --noEmit --strict on a consumer of both .d.ts (bundler and NodeNext resolution)', () => {
    run(bin(project, 'tsc'), ['--noEmit', '--strict', '-p', 'ts/tsconfig.json'], project);
    run(bin(project, 'tsc'), ['--noEmit', '--strict', '-p', 'ts/tsconfig.node.json'], project);
  });

  test('TypeScript: every js snippet of the READMEs passes tsc --noEmit --strict, as the package resolves it', () => {
    const written = writeReadmeSnippets(join(project, 'ts', 'readme'));
    assert.ok(written.three.length >= 5 && written.babylon.length >= 3, JSON.stringify(written));
    for (const [which, files] of Object.entries(written)) {
      writeFileSync(join(project, 'ts', 'readme', `tsconfig.${which}.json`), JSON.stringify({
        extends: '../tsconfig.json', files: [`globals_${which}.d.ts`, ...files],
      }, null, 2));
      run(bin(project, 'tsc'), ['--noEmit', '--strict', '-p', `ts/readme/tsconfig.${which}.json`], project);
    }
  });

  test('Vite: vite build, served from dist/, in Chromium: the wasm loads from the bundle and the bones move', async () => {
    const built = spawnSync(bin(project, 'vite'), ['build', '--logLevel', 'warn'], { cwd: join(project, 'web'), encoding: 'utf8' });
    assert.equal(built.status, 0, `vite build failed:\n${built.stdout}\n${built.stderr}`);
    assert.doesNotMatch(built.stdout + built.stderr, /node:fs/, 'no warning about the module loader\'s Node-only import');
    const dist = join(project, 'web', 'dist');
    assert.ok(readdirSync(join(dist, 'assets')).some((f) => f.endsWith('.wasm')), 'vite copied the .wasm');
    const page = await openBundle(dist);
    assertPageWorked(page, 'vite');
    assert.match(page.wasm[0].path, /^\/assets\/springbones_wasm-[\w-]+\.wasm$/, 'the bundle\'s copy, with its content hash');
  });

  test('Vite dev server (with the README\'s optimizeDeps.exclude), in Chromium: the bones move', async () => {
    const server = await startViteDevServer(project, join(project, 'web'));
    try {
      const page = await openPage(`${server.url}index.html`);
      assertPageWorked(page, 'vite dev');
      assert.match(page.wasm[0].path, /\/node_modules\/springbones\/web\/dist\/springbones_wasm\.wasm$/);
    } finally {
      await server.stop();
    }
  });

  test('esbuild: bundled with the .wasm as a file, served, in Chromium: the bones move', async () => {
    const dist = join(project, 'esbuild-dist');
    run(bin(project, 'esbuild'), ['web/esbuildEntry.js', '--bundle', '--format=esm', '--loader:.wasm=file',
      '--log-level=warning', `--outdir=${dist}`], project);
    cpSync(join(project, 'web', 'public'), dist, { recursive: true });
    writeFileSync(join(dist, 'index.html'), readFileSync(join(project, 'web', 'index.html'), 'utf8')
        .replace('./viteEntry.js', './esbuildEntry.js'));
    const page = await openBundle(dist);
    assertPageWorked(page, 'esbuild');
  });

  test('springbones/inline, Vite with no configuration: vite build, served, in Chromium: no .wasm fetched, the bones move', async () => {
    const root = join(project, 'web-inline');
    run(bin(project, 'vite'), ['build', '--logLevel', 'warn'], root);
    assertPageWorked(await openBundle(join(root, 'dist')), 'vite inline', { wasmFetched: 0 });
  });

  test('springbones/inline, esbuild with no configuration (--bundle alone): served, in Chromium: no .wasm fetched, the bones move', async () => {
    const dist = join(project, 'esbuild-inline-dist');
    run(bin(project, 'esbuild'), ['web-inline/inlineEntry.js', '--bundle', '--format=esm', '--log-level=warning',
      `--outdir=${dist}`], project);
    cpSync(join(project, 'web-inline', 'public'), dist, { recursive: true });
    cpSync(join(project, 'web-inline', 'index.html'), join(dist, 'index.html'));
    assertPageWorked(await openBundle(dist), 'esbuild inline', { wasmFetched: 0 });
  });
});

describe(`a Node project with three ${kThreeLowest}, the lowest of the peer range`, () => {
  let project;
  before(() => {
    project = makeProject('three-lowest', { springbones: `file:${tarball}`, three: kThreeLowest });
  });
  after(() => removeProject(project));

  test('the Node suite and the three.js internals checks pass', () => {
    run(process.execPath, ['--test', 'node/sample.spec.mjs', 'node/loader_plugin.spec.mjs', 'node/three_internals.spec.mjs'],
        project, { SPRINGBONES_THREE_REVISION: kThreeLowest.split('.')[1] });
  });
});

for (const [which, babylon] of Object.entries(kBabylon)) {
  describe(`a Node project with Babylon.js ${Object.values(babylon)[0]} (${Object.keys(babylon).join(' + ')})`, () => {
    let project;
    before(() => {
      project = makeProject(`babylon-${which}`, { springbones: `file:${tarball}`, ...babylon },
        which === 'current' ? { typescript: kTools.typescript } : {});
    });
    after(() => removeProject(project));

    test('springbones/babylon on a NullEngine: the drop-in class and the loader extension', () => {
      run(process.execPath, ['--test', 'babylon/babylon.spec.mjs'], project, { SPRINGBONES_BABYLON: which });
    });

    if (which === 'current') {
      test('TypeScript: tsc --noEmit --strict on a consumer of springbones/babylon with @babylonjs/core', () => {
        run(bin(project, 'tsc'), ['--noEmit', '--strict', '-p', 'ts/tsconfig.babylon.json'], project);
      });
    }
  });
}

describe(`the preview's Babylon: @babylonjs/core ${kPreviewBabylon['@babylonjs/core']} (ES modules), installed, type-checked, bundled and run`, () => {
  let project;
  before(() => {
    // npm's peer check is part of the test: no --legacy-peer-deps (makeProject runs a plain install).
    project = makeProject('babylon-preview', { springbones: `file:${tarball}`, ...kPreviewBabylon },
      { esbuild: kTools.esbuild, typescript: kTools.typescript });
  });
  after(() => removeProject(project));

  test('TypeScript: the preview\'s calls type-check against @babylonjs/core 4.2 with tsc --noEmit --strict', () => {
    run(bin(project, 'tsc'), ['--noEmit', '--strict', '-p', 'ts/tsconfig.babylon42.json'], project);
  });

  test('esbuild: the preview\'s flow bundled with @babylonjs/core 4.2, run in Node: the class starts the module itself, the hair swings', () => {
    const dist = join(project, 'babylon-dist');
    run(bin(project, 'esbuild'), ['babylon/preview42.spec.mjs', '--bundle', '--platform=node', '--format=esm',
      '--log-level=warning', `--outdir=${dist}`], project);
    // Where a page serves it: beside the bundle (esbuild copies no file named by new URL()).
    cpSync(join(project, 'node_modules', 'springbones', 'web', 'dist', 'springbones_wasm.wasm'), join(dist, 'springbones_wasm.wasm'));
    run(process.execPath, ['--test', join(dist, 'preview42.spec.js')], project);
  });
});
