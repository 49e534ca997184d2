// What tests/scenarios/out_of_memory.mjs's report must say, in Node and in Chromium alike.

/** @param assert node:assert/strict */
export function checkOutOfMemoryReport(assert, report) {
  const label = JSON.stringify(report, null, 1);
  assert.ok(report.rigsLoaded > 10, `some wearables fit under the cap: ${report.rigsLoaded}`);
  assert.equal(report.firstFailure?.code, 'out-of-memory', label);
  // The memory grew up to the cap and no further.
  assert.ok(report.full.heapBytes > report.start.heapBytes && report.full.heapBytes <= report.start.heapBytes + report.headroomBytes, label);
  for (const [entry, failure] of Object.entries(report.onTheFullHeap)) {
    assert.equal(failure?.name, 'SpringBonesError', `${entry}: ${JSON.stringify(failure)}`);
    assert.equal(failure.code, 'out-of-memory', `${entry}: ${failure.message}`);
  }
  assert.ok(report.heldInstances >= report.instancesCreated);
  assert.equal(report.heldInstancesFinite, true, 'what was loaded before still steps, finite');
  assert.deepEqual([report.afterDispose.rigs, report.afterDispose.instances, report.afterDispose.scenes], [0, 0, 0]);
  // The handle tables keep their grown arrays (wasm/handle_table.h); nothing else stays.
  assert.ok(report.afterDispose.heapInUse - report.start.heapInUse < 64 * 1024,
            `${report.afterDispose.heapInUse - report.start.heapInUse} bytes still in use after disposing everything`);
  assert.equal(report.end.heapInUse, report.afterDispose.heapInUse, 'loading again leaves nothing behind');
  assert.equal(report.sameRotationsAfterwards, true, 'a load after running out gives the same rotations, bit for bit');
}
