// `scripts/bench --soak`: the backpack soak in full, 2,000 cycles of load a wearable -> wear it on
// the avatar -> 30 frames -> take it off and dispose in headless Chromium
// (tests/browser/backpackSoak.mjs), printing a sample every 100 cycles and judging them as the CI
// test does (tests/browser/soakBounds.mjs). Exit 1 when memory, handles or the avatar are not flat.
//   node scripts/benchmarks/soak.mjs [cycles]
import { runBackpackSoak } from '../../tests/browser/backpackSoak.mjs';
import { soakProblems } from '../../tests/browser/soakBounds.mjs';

const cycles = Number(process.argv[2] ?? 2000);
if (!Number.isInteger(cycles) || cycles < 200) {
  console.error('usage: node scripts/benchmarks/soak.mjs [cycles >= 200]');
  process.exit(2);
}
const started = Date.now();
console.log('cycles  wasm memory  heap in use  rigs instances scenes  avatar objects  JS heap after GC');
const { samples, consoleErrors } = await runBackpackSoak({
  cycles,
  batch: 100,
  onSample: (s) => console.log(`${String(s.cycles).padStart(6)}  ${String(s.heapBytes).padStart(11)}  ` +
    `${String(s.heapInUse).padStart(11)}  ${s.rigs} ${s.instances} ${s.scenes}  ${String(s.avatarObjects).padStart(14)}  ` +
    `${String(s.jsHeapUsed).padStart(16)}`),
});
const problems = [...soakProblems(samples), ...consoleErrors.map((e) => `console error: ${e}`)];
console.log(`${cycles} cycles in ${((Date.now() - started) / 1000).toFixed(1)} s: ${problems.length ? 'NOT flat' : 'flat'}`);
for (const p of problems) console.log(`  ${p}`);
process.exit(problems.length ? 1 : 0);
