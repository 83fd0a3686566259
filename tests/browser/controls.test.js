'use strict';
// The brush client's symmetric brushing and its progress bar and Cancel button,
// in headless Chromium against a real meristemd.
const { test, before, after } = require('node:test');
const assert = require('node:assert/strict');
const path = require('node:path');
const { chromium } = require('playwright-core');
const { startDaemon, api } = require('../support/daemon.js');

const CHROMIUM_ARGS = ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
  '--disable-background-networking', '--disable-component-update', '--disable-sync',
  '--use-angle=swiftshader', '--enable-unsafe-swiftshader'];

let d, browser, page;
const errors = [];
const edits = [];
const summary = async () => (await api(d.url, 'GET', `/v1/sessions/${await page.evaluate(() => window.meristem.sessionId)}`)).body;

before(async () => {
  d = await startDaemon(['--quiet']);
  browser = await chromium.launch({ executablePath: process.env.CHROMIUM, headless: true, args: CHROMIUM_ARGS });
  page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  page.on('pageerror', (e) => errors.push(String(e)));
  page.on('request', (r) => {
    if (r.method() === 'POST' && /\/edits$/.test(r.url())) edits.push(JSON.parse(r.postData()));
  });
  await page.goto(`${d.url}/`);
  await page.waitForFunction(() => window.meristem?.ready, null, { timeout: 30000 });
});
after(async () => { await browser?.close(); await d?.stop(); });

test('a symmetric stroke: the copies are drawn live and the server lays every copy', async () => {
  await page.selectOption('#preset', 'fig15-brushed');
  await page.fill('#seed', '3');
  await page.click('#new-session');
  await page.waitForFunction(() => window.meristem.summary?.step === 0, null, { timeout: 15000 });
  const before = (await summary()).markers;
  await page.click('[data-tool="brush"]');
  await page.check('#sym-rot');
  await page.fill('#sym-rot-n', '3');
  await page.check('#sym-mirror');
  await page.uncheck('#constrain');
  // Away from the stem, so the stroke does not start on the tree (no constraint).
  const box = await page.locator('canvas').boundingBox();
  const from = { x: box.x + box.width * 0.75, y: box.y + box.height * 0.3 };
  await page.mouse.move(from.x, from.y);
  await page.mouse.down();
  let previewDuringStroke = 0;
  for (let i = 1; i <= 8; i++) {
    await page.mouse.move(from.x - 6 * i, from.y + 4 * i);
    await new Promise((r) => setTimeout(r, 40));
    previewDuringStroke = Math.max(previewDuringStroke,
      await page.evaluate(() => window.meristem.brush.dabMesh.count));
  }
  await page.mouse.up();
  await page.evaluate(() => window.meristem.idle());
  // Live preview: each dab is drawn with its 3 × 2 copies.
  assert.ok(previewDuringStroke >= 6 && previewDuringStroke % 6 === 0,
    `${previewDuringStroke} dab spheres drawn during the stroke`);
  const dabs = edits.flatMap((b) => b.edits || [b]).filter((e) => e.op === 'add_markers' && e.center);
  assert.ok(dabs.length > 0, 'the stroke sent dabs');
  for (const e of dabs) {
    assert.equal(e.symmetry.rotational, 3);
    assert.ok(e.symmetry.mirror && e.symmetry.mirror.normal, 'a mirror plane');
    assert.equal(e.constrain, undefined);
  }
  // The server keeps the dab's markers and all five copies (none fall below ground here).
  const perDab = (e) => 1 + Math.round(((e.count ?? 50) - 1) * (e.pressure ?? 0.5) ** 2);
  const expected = dabs.reduce((n, e) => n + 6 * perDab(e), 0);
  const after = (await summary()).markers;
  assert.ok(after - before <= expected && after - before >= expected * 0.9,
    `${after - before} markers added, ${expected} expected from ${dabs.length} dabs × 6 copies`);
  await page.screenshot({ path: path.join(process.env.MER_ARTIFACTS, 'controls-symmetry.png') });
});

test('a long step shows its progress and Cancel stops it at a whole step', async () => {
  await page.selectOption('#preset', 'fig7-bh-0.54');
  await page.fill('#seed', '5');
  await page.click('#new-session');
  await page.waitForFunction(() => window.meristem.summary?.preset === 'fig7-bh-0.54', null, { timeout: 15000 });
  await page.fill('#step-count', '200');
  await page.click('#step-n');
  await page.waitForFunction(() => !document.querySelector('#progress').hidden &&
    /step [1-9]\d* \/ 200/.test(document.querySelector('#progress-text').textContent), null, { timeout: 30000 });
  const shown = await page.textContent('#progress-text');
  await page.screenshot({ path: path.join(process.env.MER_ARTIFACTS, 'controls-progress.png') });
  await page.click('#cancel');
  await page.waitForFunction(() => document.querySelector('#progress').hidden, null, { timeout: 60000 });
  const s = await page.evaluate(() => window.meristem.idle());
  assert.ok(s.step > 0 && s.step < 200, `stopped at step ${s.step} (the bar said "${shown}")`);
  assert.equal(s.running.active, false);
  assert.equal((await summary()).step, s.step);
});

test('no script errors', () => {
  assert.deepEqual(errors, []);
});
