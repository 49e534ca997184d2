// What "flat" means for the backpack soak (tests/browser/backpackSoak.mjs), shared by its CI test
// and `scripts/bench --soak`: after the first 100 cycles (one-time allocations: compiled code,
// three.js and module caches, the allocator's first pools) the WebAssembly memory, the module's
// heap in use, its live handles and the objects on the avatar do not change at all, and the JS
// heap after a forced GC stays within 1 MiB of its size at cycle 100. Measured in Chromium 156:
// within 300 KB over 3,000 cycles, with no trend after ~1,000 (V8's own caches settling); a
// leaked clone of the sample hair (tens of objects and matrices) would pass 1 MiB within a few
// hundred cycles, a leak of 512 bytes a cycle within 2,000.
export const kWarmupCycles = 100;
export const kJsHeapBoundBytes = 1 << 20;

/** The reasons the samples are not flat; empty when they are. */
export function soakProblems(samples) {
  const base = samples.find((s) => s.cycles === kWarmupCycles);
  if (!base) return [`no sample at cycle ${kWarmupCycles}`];
  const problems = [];
  for (const s of samples.filter((x) => x.cycles > kWarmupCycles)) {
    for (const key of ['heapBytes', 'heapInUse', 'rigs', 'instances', 'scenes', 'avatarObjects']) {
      if (s[key] !== base[key]) problems.push(`cycle ${s.cycles}: ${key} ${s[key]}, ${base[key]} at cycle ${kWarmupCycles}`);
    }
    if (s.jsHeapUsed - base.jsHeapUsed > kJsHeapBoundBytes) {
      problems.push(`cycle ${s.cycles}: JS heap ${s.jsHeapUsed} bytes, more than 1 MiB above ${base.jsHeapUsed} at cycle ${kWarmupCycles}`);
    }
  }
  if (base.rigs !== 0 || base.instances !== 0 || base.scenes !== 0) problems.push(`handles left after a cycle: ${JSON.stringify(base)}`);
  return problems;
}
