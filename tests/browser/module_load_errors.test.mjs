// A .wasm that is missing, or an HTML page served where it should be, in Chromium: the error names
// the URL, the HTTP status and the content type, and nothing of Emscripten's reaches the console
// (tests/wasm/module_load_errors.test.mjs has every case in Node).
import assert from 'node:assert/strict';
import { after, before, test } from 'node:test';
import { openPage, skip } from './demo_page.mjs';

let page, consoleErrors, consoleWarnings, close;
before(async () => {
  if (skip) return;
  ({ page, consoleErrors, consoleWarnings, close } =
    await openPage('/tests/browser/pages/blank.html', () => window.blankPageReady === true));
});
after(async () => { await close?.(); });

test('a 404 and an HTML page where the module should be are said in our words, and nothing is printed', { skip }, async () => {
  const errors = await page.evaluate(async () => {
    const { createSpringBones } = await import('/web/springbones.js');
    const messageOf = (wasmUrl) => createSpringBones({ wasmUrl }).then(() => null, (e) => ({ code: e.code, message: e.message }));
    return { missing: await messageOf('/web/dist/no_such_module.wasm'), page: await messageOf('/tests/browser/pages/blank.html') };
  });
  const origin = new URL(page.url()).origin;
  assert.equal(errors.missing.code, 'module-load-failed');
  assert.ok(errors.missing.message.includes(`${origin}/web/dist/no_such_module.wasm`), errors.missing.message);
  assert.match(errors.missing.message, /the server answered HTTP 404/);
  assert.equal(errors.page.code, 'module-load-failed');
  assert.match(errors.page.message, /HTTP 200 OK \(text\/html, not application\/wasm\).*not WebAssembly \(it begins "</);
  for (const { message } of Object.values(errors)) assert.doesNotMatch(message, /Aborted|ASSERTIONS|magic word/);
  // Chromium itself logs the 404 of a fetch; nothing else may appear.
  assert.deepEqual(consoleErrors.filter((e) => !/Failed to load resource: .*404/.test(e)), []);
  assert.deepEqual(consoleWarnings, []);
});
