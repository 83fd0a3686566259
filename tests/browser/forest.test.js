'use strict';
// A sown forest from the page, in headless Chromium against a real meristemd: the
// model "sown forest" swaps the preset list for the plants, their spacing, the area
// and the presets (on one line of the top bar); New tree sows them; the camera frames the whole forest (every
// plant's base on screen), also after it grows; a refused count shows the problem.
const { test, before, after } = require('node:test');
const assert = require('node:assert/strict');
const path = require('node:path');
const { openPage } = require('../support/chromium.js');
const { startDaemon } = require('../support/daemon.js');

let d, browser, page;
const errors = [];
const shot = (name) => page.screenshot({ path: path.join(process.env.MER_ARTIFACTS, name) });
const summary = () => page.evaluate(() => window.meristem.summary);
const idle = () => page.evaluate(() => window.meristem.idle());

before(async () => {
  d = await startDaemon(['--quiet']);
  ({ browser, page } = await openPage());
  page.on('pageerror', (e) => errors.push(String(e)));
  await page.goto(`${d.url}/`, { timeout: 120000 });
  await page.waitForFunction(() => window.meristem?.ready, null, { timeout: 30000 });
});
after(async () => { await browser?.close(); await d?.stop(); });

// Every plant's base, projected by the page's camera, inside the canvas.
async function allInView() {
  return page.evaluate(async () => {
    const m = window.meristem;
    const sk = await (await fetch(`/v1/sessions/${m.sessionId}/skeleton`)).json();
    const rect = m.viewer.renderer.domElement.getBoundingClientRect();
    const roots = sk.nodes.filter((n) => n.parent === null || n.parent === undefined);
    const out = roots.map((n) => m.viewer.screenOf(n.base))
      .filter((p) => p.x < rect.left || p.x > rect.right || p.y < rect.top || p.y > rect.bottom);
    return { roots: roots.length, outside: out.length };
  });
}

test('a forest sown from the page is framed whole', async () => {
  await page.selectOption('#model', 'forest');
  assert.ok(await page.isVisible('#sow-fields'));
  assert.ok(!(await page.isVisible('#preset')), 'no preset list for a forest');
  // The fields fit the top bar at 1280 px: one row, and the bar no taller than two lines.
  const bar = await page.evaluate(() => ({
    rows: new Set(['#sow-count', '#sow-distance', '#sow-size', '#sow-presets']
      .map((q) => Math.round(document.querySelector(q).getBoundingClientRect().top))).size,
    height: document.querySelector('#topbar').getBoundingClientRect().height,
  }));
  assert.equal(bar.rows, 1, 'the sow fields on one line');
  assert.ok(bar.height < 90, `the top bar is ${bar.height} px high`);
  await page.fill('#sow-count', '14');
  await page.fill('#sow-distance', '9');
  await page.fill('#sow-size', '60');
  await page.fill('#sow-presets', 'fig4-colonization, runions-2007, default, abop-1.24b');
  await page.fill('#seed', '3');
  await page.click('#new-session');
  await page.waitForFunction(() => window.meristem.summary?.model === 'forest', null, { timeout: 20000 });
  await idle();
  let s = await summary();
  assert.equal(s.plants, 14);
  assert.deepEqual(await allInView(), { roots: 14, outside: 0 });
  assert.ok(!(await page.isVisible('[data-tool="brush"]')), 'the brush is not a forest\'s');

  await page.evaluate(() => window.meristem.stepN(10));
  await page.waitForFunction(() => window.meristem.summary?.step === 10, null, { timeout: 60000 });
  await idle();
  s = await summary();
  assert.ok(s.internodes > 1000, String(s.internodes));
  assert.deepEqual(await allInView(), { roots: 14, outside: 0 });
  await shot('browser-forest.png');
  assert.deepEqual(errors, []);
});

test('a count the area cannot hold shows the problem and keeps the forest', async () => {
  const before = (await summary()).id;
  await page.fill('#sow-count', '400');
  await page.fill('#sow-presets', 'default');
  await page.click('#new-session');
  await page.waitForFunction(() => window.meristem.state.lastProblem, null, { timeout: 20000 });
  const problem = await page.evaluate(() => window.meristem.state.lastProblem);
  assert.match(JSON.stringify(problem), /only \d+ plants/);
  assert.equal((await summary()).id, before);
});
