// What a Chromium benchmark page reports about where it ran: whether it is cross-origin isolated
// (without it performance.now() steps by 100 us instead of 5 us, and per-frame numbers mean less,
// so the per-frame page refuses to run; the cold pages run as a preview iframe does, without it),
// the smallest timer step observed, and the CPU count.

/** Throws unless the page is cross-origin isolated (COOP/COEP headers from scripts/lib/serve.mjs). */
export function requireIsolation() {
  if (globalThis.crossOriginIsolated !== true) {
    throw new Error('benchmark page is not cross-origin isolated: serve it with COOP/COEP (scripts/lib/serve.mjs)');
  }
}

/** The smallest non-zero step of performance.now() seen over ~20 ms of reading it, in us. */
export function timerStepUs() {
  let smallest = Infinity;
  const end = performance.now() + 20;
  let last = performance.now();
  for (let now = last; now < end; now = performance.now()) {
    if (now > last) {
      smallest = Math.min(smallest, now - last);
      last = now;
    }
  }
  return smallest * 1000;
}

export const conditions = () => ({
  crossOriginIsolated: globalThis.crossOriginIsolated === true,
  timerStepUs: timerStepUs(),
  hardwareConcurrency: navigator.hardwareConcurrency,
  userAgent: navigator.userAgent,
});
