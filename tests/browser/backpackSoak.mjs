// A backpack that never leaks, Node's side: opens the blank test page, runs the cycles of
// tests/scenarios/backpack_soak.mjs in batches, and after each batch forces a garbage collection
// (DevTools protocol) and samples WebAssembly memory, the module's heap in use, its live handles,
// the objects left on the avatar and the JS heap. Used by tests/browser/backpack_soak.test.mjs
// (a short run) and scripts/benchmarks/soak.mjs (`scripts/bench --soak`, the full run).
import { openPage } from './demoPage.mjs';

/**
 * @param {{cycles: number, batch: number, onSample?: (sample) => void}} options
 * @returns {Promise<{samples: object[], consoleErrors: string[]}>} one sample per batch (the
 *   first after `batch` cycles), each { cycles, rigs, instances, scenes, heapBytes, heapInUse,
 *   avatarObjects, jsHeapUsed }
 */
export async function runBackpackSoak({ cycles, batch, onSample = () => {} }) {
  const { page, consoleErrors, close } = await openPage('/tests/browser/pages/blank.html', () => window.blankPageReady === true);
  try {
    const cdp = await page.context().newCDPSession(page);
    await page.evaluate(async () => {
      const { openSoak } = await import('/tests/scenarios/backpack_soak.mjs');
      window.soak = await openSoak();
    });
    const samples = [];
    for (let done = 0; done < cycles; done += batch) {
      const sample = await page.evaluate((n) => window.soak.runCycles(n), Math.min(batch, cycles - done));
      await cdp.send('HeapProfiler.collectGarbage');
      sample.jsHeapUsed = (await cdp.send('Runtime.getHeapUsage')).usedSize;
      samples.push(sample);
      onSample(sample);
    }
    return { samples, consoleErrors };
  } finally {
    await close();
  }
}
