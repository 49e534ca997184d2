// The idle warm-up in Chromium, where a preview runs it: createSpringBones schedules it, the page's
// next idle period runs it on the runtime module alone (no readers module is downloaded), and its
// outcome is a report of the step it ran, not an error. A warm-up that threw (as one handing
// loadRig bytes did, the error hidden by an empty catch) fails here.
import assert from 'node:assert/strict';
import { after, test } from 'node:test';
import { openPage, skip } from './demo_page.mjs';

let close;
after(async () => { await close?.(); });

test('the idle warm-up runs the typed load path in Chromium without the readers module', { skip }, async () => {
  const opened = await openPage('/tests/browser/pages/blank.html', () => window.blankPageReady === true);
  close = opened.close;
  const outcome = await opened.page.evaluate(async () => {
    const { createSpringBones } = await import('/web/springbones.js');
    const { warmUpOutcome } = await import('/web/warm_up.js');
    const sb = await createSpringBones();
    // The warm-up waits for the page's next idle period; the limit is for a hung page.
    for (let waited = 0; warmUpOutcome(sb) === undefined && waited < 30000; waited += 50) {
      await new Promise((resolve) => setTimeout(resolve, 50));
    }
    const result = warmUpOutcome(sb);
    return result && { report: result.report, error: result.error && String(result.error.stack ?? result.error) };
  });
  assert.ok(outcome, 'the warm-up ran');
  assert.equal(outcome.error, undefined, `the warm-up threw: ${outcome.error}`);
  assert.ok(outcome.report.joints >= 1, `the rig it loaded has joints (${outcome.report.joints})`);
  assert.ok(outcome.report.turned > 0, 'its step turned a joint');
  assert.ok(!opened.requests.some((path) => path.includes('readers')), `no readers requested: ${opened.requests.join(', ')}`);
  assert.deepEqual(opened.consoleErrors, []);
});
