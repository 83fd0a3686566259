'use strict';
// The page at / in headless Chromium (Debian's, driven by playwright-core):
// it loads, talks to the daemon, loads three.js from the web root and draws.
const { test, before, after } = require('node:test');
const assert = require('node:assert/strict');
const path = require('node:path');
const { chromium } = require('playwright-core');
const { startDaemon } = require('../support/daemon.js');

const CHROMIUM_ARGS = ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
  '--disable-background-networking', '--disable-component-update', '--disable-sync',
  '--use-angle=swiftshader', '--enable-unsafe-swiftshader'];

let d, browser, page;
const errors = [];
before(async () => {
  if (!process.env.CHROMIUM) throw new Error('CHROMIUM is not set; configure found no chromium');
  d = await startDaemon();
  browser = await chromium.launch({ executablePath: process.env.CHROMIUM, headless: true,
    args: CHROMIUM_ARGS });
  page = await browser.newPage({ viewport: { width: 800, height: 600 } });
  page.on('pageerror', (e) => errors.push(String(e)));
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  page.on('requestfailed', (r) => errors.push(`request failed: ${r.url()}`));
  page.on('response', (r) => { if (r.status() >= 400) errors.push(`${r.status()} ${r.url()}`); });
  await page.goto(`${d.url}/`);
});
after(async () => { await browser?.close(); await d?.stop(); });

test('the page at / is the meristem client', async () => {
  assert.equal(await page.title(), 'meristem');
});

test('shows the daemon is healthy, with its version', async () => {
  await page.waitForFunction(() => document.querySelector('#status')?.dataset.state === 'ok',
    null, { timeout: 15000 });
  assert.match(await page.textContent('#status'), new RegExp(`meristemd ${process.env.PACKAGE_VERSION}`));
});

test('three.js from the web root draws a non-blank canvas', async () => {
  await page.waitForFunction(() => window.meristemFramesDrawn > 0, null, { timeout: 15000 });
  // The page's own probe (web/js/viewer/probe.js), through its test hook.
  const variance = await page.evaluate(() => window.meristem.pixelVariance());
  assert.ok(variance > 10, `canvas luminance variance ${variance} shows a drawing`);
  await page.screenshot({ path: path.join(process.env.MER_ARTIFACTS, 'page.png') });
});

test('no script errors and no failed requests', () => {
  assert.deepEqual(errors, []);
});
