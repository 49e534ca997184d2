// Out of memory is an error, not the end: with the module's memory capped, loading more rigs and
// instances than fit fails with 'out-of-memory', every other entry point called on the full heap
// fails the same way (the creator tools are another module, with a memory of their own), and the
// module then keeps working (the instances it holds still step, everything disposes, a load after
// that gives the answer of a module that never ran out).
//
// One scenario for both runtimes: tests/wasm/out_of_memory.test.mjs runs it in Node and
// tests/browser/out_of_memory.test.mjs in Chromium; it returns a plain report they assert on.
//
// How memory is capped: WebAssembly.Memory.prototype.grow refuses, with the RangeError an engine
// throws when it cannot reserve more, any growth past `current size + headroom`. That is exactly
// what the module meets at its real maximum (2 GiB) or on a device that cannot reserve more: the
// glue's resize fails, malloc returns null, the core sees std::bad_alloc. It needs no build option
// (one module or several, whatever their link flags) and does not touch 2 GiB of memory to get
// there; the cap is lifted when the scenario ends.

const kPage = 65536;
const kDt = 1 / 60;

/** Caps the growth of every WebAssembly.Memory at `limitBytes`; returns the function lifting it. */
export function capMemoryGrowth(limitBytes) {
  const { grow } = WebAssembly.Memory.prototype;
  WebAssembly.Memory.prototype.grow = function cappedGrow(pages) {
    if (this.buffer.byteLength + pages * kPage > limitBytes) {
      throw new RangeError(`WebAssembly.Memory.grow(): capped at ${limitBytes} bytes by the test`);
    }
    return grow.call(this, pages);
  };
  return () => { WebAssembly.Memory.prototype.grow = grow; };
}

/** The rotations of a fresh instance of `rig` after `frames` frames at rest, as a copy. */
function rotationsAfter(rig, frames) {
  const inst = rig.createInstance();
  try {
    for (let i = 0; i < frames; i++) inst.step(kDt);
    return Array.from(inst.rotations);
  } finally {
    inst.dispose();
  }
}

const describeError = (e) => ({ name: e?.constructor?.name ?? typeof e, code: e?.code ?? null, message: String(e?.message ?? e) });

/** Runs fn; its error described, or null when it returned. */
function failureOf(fn) {
  try {
    fn();
    return null;
  } catch (e) {
    return describeError(e);
  }
}

/**
 * @param {object} options
 * @param {Function} options.createSpringBones the library's factory
 * @param {{glb: Uint8Array, springBones: object}} options.wearable loaded until memory runs out
 * @param {Uint8Array} options.vrm a VRM avatar, loaded once more on the full heap
 * @param {number} [options.headroomMiB] how far memory may grow past its size after the reference run
 */
export async function outOfMemoryScenario({ createSpringBones, wearable, vrm, headroomMiB = 8 }) {
  const sb = await createSpringBones();
  // The answer of a module that never ran out, and its heap with nothing loaded.
  const referenceRig = sb.loadRig(wearable.glb, wearable.springBones);
  const reference = rotationsAfter(referenceRig, 30);
  referenceRig.dispose();
  const start = sb.stats();
  const report = { start, headroomBytes: headroomMiB * 1048576 };

  const lift = capMemoryGrowth(start.heapBytes + report.headroomBytes);
  try {
    const rigs = [];
    const instances = [];
    let failure = null;
    for (let i = 0; i < 1_000_000 && failure === null; i++) {
      failure = failureOf(() => {
        const rig = sb.loadRig(wearable.glb, wearable.springBones);
        rigs.push(rig);
        const inst = rig.createInstance();
        instances.push(inst);
        inst.step(kDt);
      });
    }
    report.rigsLoaded = rigs.length;
    report.instancesCreated = instances.length;
    report.firstFailure = failure;
    report.full = sb.stats();

    // Every entry point that allocates, called on the full heap. The JSON texts are larger than
    // the heap's low addresses, so a copy written through a null pointer would not go unnoticed.
    // The entity's padding is 256 KiB in strings under the bound on one string (docs/input.md).
    const entity = {
      content: [{ file: 'm.glb', hash: 'QmHash' }],
      metadata: { data: { representations: [{ bodyShapes: ['BaseMale'], mainFile: 'm.glb' }], springBones: wearable.springBones } },
      padding: Array.from({ length: 8 }, () => 'x'.repeat(32 * 1024)),
    };
    const bigGlb = new Uint8Array(report.headroomBytes + kPage);
    report.onTheFullHeap = {
      loadRig: failureOf(() => sb.loadRig(wearable.glb, wearable.springBones).dispose()),
      loadRigByEntity: failureOf(() => sb.loadRig(wearable.glb, wearable.springBones, { entity, bodyShape: 'BaseMale' }).dispose()),
      // VRM avatars kept until they no longer fit either (their bytes are read in the readers'
      // memory: what reaches this heap is the typed input and the rig).
      loadVrm: (() => {
        let failure = null;
        for (let i = 0; i < 100_000 && failure === null; i++) failure = failureOf(() => rigs.push(sb.loadVrm(vrm)));
        return failure;
      })(),
      // Then instances, smaller still, until none fits.
      createInstance: failureOf(() => { for (let i = 0; i < 100_000; i++) instances.push(rigs[0].createInstance()); }),
      contentHash: failureOf(() => sb.contentHash(bigGlb)),
      // Scenes of every instance, kept until one no longer fits (a failed allocation hands the
      // core's reserve back, src/common/memory_reserve.cpp: one scene may still fit in it).
      createScene: (() => {
        const scenes = [];
        const failure = failureOf(() => {
          for (let i = 0; i < 10_000; i++) {
            const scene = sb.createScene();
            scenes.push(scene);
            for (const inst of instances) scene.add(inst);
            scene.step(kDt);
          }
        });
        for (const scene of scenes) scene.dispose();
        return failure;
      })(),
    };

    // What the module held before it ran out still works: every instance steps to finite rotations.
    let finite = true;
    for (const inst of instances) {
      inst.step(kDt);
      for (const v of inst.rotations) finite &&= Number.isFinite(v);
    }
    report.heldInstancesFinite = finite;
    report.heldInstances = instances.length;

    for (const inst of instances) inst.dispose();
    for (const rig of rigs) rig.dispose();
    // The failed allocations handed the core's reserve back (src/common/memory_reserve.cpp); the first
    // allocation since, stats()'s own answer, takes it again: the second call sees the heap as
    // every later call will.
    sb.stats();
    report.afterDispose = sb.stats();

    // Load again on the same (still capped) memory: the same answer as before it ran out.
    const again = sb.loadRig(wearable.glb, wearable.springBones);
    const rotations = rotationsAfter(again, 30);
    again.dispose();
    report.sameRotationsAfterwards = rotations.length === reference.length && rotations.every((v, i) => Object.is(v, reference[i]));
    report.end = sb.stats();
  } finally {
    lift();
  }
  return report;
}
