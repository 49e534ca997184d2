// The native side of tests/scenarios/frame_hash.mjs: tools/dump_rotations --hash on the
// same cases, from the native build scripts/test makes before the Node and browser suites.
import { execFileSync } from 'node:child_process';
import { existsSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

import { frameHashCases } from './frame_hash.mjs';

const root = join(dirname(fileURLToPath(import.meta.url)), '..', '..');

/** The native hashes by case name, or throws naming the missing build. */
export function nativeFrameHashes() {
  const dumper = ['native-release', 'native-debug']
    .map((preset) => join(root, 'build', preset, 'tools', 'dump_rotations'))
    .find((path) => existsSync(path));
  if (!dumper) throw new Error('build/native-release/tools/dump_rotations is missing: run scripts/build native');
  const out = {};
  for (const c of frameHashCases) {
    const args = c.vrm
      ? [join(root, c.file), '-', '-', '1000', '60', '--drive', 'sway', '--vrm', '--hash']
      : [join(root, c.file), join(root, c.metadata), '-', '1000', '60', '--drive', 'sway', '--hash'];
    out[c.name] = JSON.parse(execFileSync(dumper, args, { encoding: 'utf8' }));
  }
  return out;
}
