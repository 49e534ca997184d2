// Errors in Node are readable from the package as it ships (web/dist/*.min.js, what the exports
// point at): an uncaught error prints as a SpringBonesError (not a class renamed to a letter by the
// minifier), Node never prints a line of minified code thousands of characters long, and with
// source maps on (node --enable-source-maps; the CLI turns them on for its own process)
// the stack names our source files. Every bundle the package ships has its source map beside it.
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import { existsSync, readFileSync } from 'node:fs';
import { dirname, join, resolve } from 'node:path';
import { test } from 'node:test';
import { root } from './helpers.mjs';

const pkg = JSON.parse(readFileSync(join(root, 'package.json'), 'utf8'));
// Minified code breaks lines near 500 characters (scripts/lib/minify.mjs); a string literal can run
// past that. The bundles used to be one line each, 5 to 17 KB long.
const kLongestLine = 1500;

/** Runs a module text in a child Node process at the repository's root ('springbones' is the package itself). */
function runModule(source, nodeOptions = []) {
  return spawnSync(process.execPath, [...nodeOptions, '--input-type=module', '-e', source], { cwd: root, encoding: 'utf8' });
}

const kUncaught = `
  import { createSpringBones } from 'springbones';
  const sb = await createSpringBones();
  sb.loadRig(new Uint8Array([1, 2, 3, 4]), null);
`;

test('an uncaught error of the minified package prints as SpringBonesError, without a long line of minified code', () => {
  const child = runModule(kUncaught);
  assert.equal(child.status, 1);
  assert.match(child.stderr, /^SpringBonesError: input is neither a GLB/m);
  assert.doesNotMatch(child.stderr, /\[SpringBonesError\]/, 'the constructor is named as the error is');
  assert.match(child.stderr, /web\/dist\/\w+\.min\.js:\d+:\d+/, 'the package as it ships (exports) was what ran');
  const longest = Math.max(...child.stderr.split('\n').map((line) => line.length));
  assert.ok(longest < kLongestLine, `the longest line printed is ${longest} characters`);
});

test('with source maps on, the stack names our source files', () => {
  const child = runModule(kUncaught, ['--enable-source-maps']);
  assert.equal(child.status, 1);
  assert.match(child.stderr, /^SpringBonesError: input is neither a GLB/m);
  assert.match(child.stderr, /web\/errors\.js:\d+:\d+/);
  assert.match(child.stderr, /web\/springbones\.js:\d+:\d+/);
  assert.doesNotMatch(child.stderr, /\.min\.js/);
});

test('the SpringBonesError class is named SpringBonesError in every entry', async () => {
  const { SpringBonesError } = await import('../../web/dist/springbones.min.js');
  const inline = await import('../../web/dist/inline.min.js');
  assert.equal(SpringBonesError.name, 'SpringBonesError');
  assert.equal(inline.SpringBonesError.name, 'SpringBonesError');
  assert.equal(new SpringBonesError('x', 'y').name, 'SpringBonesError');
});

test('every bundle the package ships has short lines and its source map (with the sources) shipped beside it', () => {
  const bundles = pkg.files.filter((f) => f.endsWith('.min.js'));
  assert.ok(bundles.length >= 7, bundles.join(', '));
  for (const file of bundles) {
    const text = readFileSync(join(root, file), 'utf8');
    const longest = Math.max(...text.split('\n').map((line) => line.length));
    assert.ok(longest < kLongestLine, `${file}: a line of ${longest} characters`);
    if (file === 'web/dist/inline.min.js') continue;  // its map would repeat the module's base64: none
    const mapFile = `${file}.map`;
    assert.ok(pkg.files.includes(mapFile), `package.json's files ship ${mapFile}`);
    assert.match(text, new RegExp(`//# sourceMappingURL=${mapFile.split('/').pop().replace(/\./g, '\\.')}\\n?$`));
    const map = JSON.parse(readFileSync(join(root, mapFile), 'utf8'));
    assert.equal(map.sources.length, map.sourcesContent.length, `${mapFile} carries its sources`);
    for (const [i, source] of map.sources.entries()) {
      assert.ok(existsSync(resolve(dirname(join(root, file)), source)), `${mapFile}: ${source} is a file of web/`);
      assert.ok(map.sourcesContent[i].length > 0);
    }
  }
});
