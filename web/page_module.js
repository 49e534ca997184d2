// The page's own springbones module, for the adapters when the page gives them none (the Babylon.js
// drop-in constructed without a module, the three.js loader plugin without `sb`). One per page,
// shared by every simulation and wearable that asked for it.
//
// Asking for it (pageModule()) downloads nothing; its download starts when a holder calls
// start(), which the adapters do when the first wearable is worn (three.js: wear(); Babylon:
// registerWearable). By then the page has its GLBs, so on a slow
// link the module's download (the API, the glue, the WebAssembly) never shares the bandwidth with
// them, and the item is drawn as early as without springbones; docs/performance.md ("Fetch
// order") has the measurements against the other orders. The API is imported then too, so a page
// that bundles an adapter downloads only the adapter before it draws.

let shared = null;

/**
 * The page's module as { promise, start }: `promise` settles once `start()` has been called (by
 * any holder) and the module is there. A failed start is forgotten, so that the next caller of
 * pageModule() gets a new one that tries again.
 */
export function pageModule() {
  if (shared === null) {
    let start;
    const requested = new Promise((resolve) => {
      start = resolve;
    });
    const entry = {
      promise: requested
        .then(() => import('./springbones.js'))
        .then(({ createSpringBones }) => createSpringBones()),
      start: () => start(),
    };
    entry.promise.catch(() => {
      if (shared === entry) shared = null;
    });
    shared = entry;
  }
  return shared;
}
