// Versioning: package.json is the source of truth; sb.version (web/version.js) and the CHANGELOG
// follow it.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { test } from 'node:test';
import { createSpringBones } from '../../web/springbones.js';

const root = new URL('../../', import.meta.url);
const packageJson = JSON.parse(readFileSync(new URL('package.json', root), 'utf8'));

test('sb.version is package.json\'s version', async () => {
  const sb = await createSpringBones();
  assert.equal(sb.version, packageJson.version);
  assert.match(sb.version, /^0\.\d+\.\d+$/, 'semver, still 0.x');
});

test('the CHANGELOG has a section for this version', () => {
  const changelog = readFileSync(new URL('CHANGELOG.md', root), 'utf8');
  assert.match(changelog, new RegExp(`^## \\[${packageJson.version.replaceAll('.', '\\.')}\\] - \\d{4}-\\d{2}-\\d{2}$`, 'm'));
});
