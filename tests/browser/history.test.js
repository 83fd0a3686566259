'use strict';
// The History panel in headless Chromium against a real meristemd: the first screen
// says what to do; Ctrl+Z and Ctrl+Shift+Z undo and redo (the tree's hash and GLB as
// they were); the slider scrubs through past revisions without changing the session;
// Restore and a click in the list go back to a revision as a new one.
const { test, before, after } = require('node:test');
const assert = require('node:assert/strict');
const path = require('node:path');
const { chromium } = require('playwright-core');
const { startDaemon, api } = require('../support/daemon.js');

const CHROMIUM_ARGS = ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
  '--disable-background-networking', '--disable-component-update', '--disable-sync',
  '--use-angle=swiftshader', '--enable-unsafe-swiftshader'];
const shot = (name) => page.screenshot({ path: path.join(process.env.MER_ARTIFACTS, name) });

let d, browser, page;
const errors = [];
const snapshots = [];
before(async () => {
  d = await startDaemon(['--quiet']);
  browser = await chromium.launch({ executablePath: process.env.CHROMIUM, headless: true, args: CHROMIUM_ARGS });
  page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  page.on('pageerror', (e) => errors.push(String(e)));
  page.on('request', (r) => { if (r.url().includes('/snapshot.glb')) snapshots.push(r.url()); });
  await page.goto(`${d.url}/`);
  await page.waitForFunction(() => window.meristem?.ready, null, { timeout: 30000 });
});
after(async () => { await browser?.close(); await d?.stop(); });

const summary = () => page.evaluate(() => window.meristem.summary);
const glb = async (id, revision) => {
  const q = revision === undefined ? '' : `&revision=${revision}`;
  return Buffer.from(await (await fetch(`${d.url}/v1/sessions/${id}/snapshot.glb?leaves=1${q}`)).arrayBuffer());
};
const listed = () => page.$$eval('#history-list li', (lis) => lis.map((li) => ({
  revision: Number(li.dataset.revision), current: li.classList.contains('current'), text: li.textContent })));
async function settle(revisions) {
  await page.evaluate(() => window.meristem.idle());
  await page.waitForFunction((n) => document.querySelectorAll('#history-list li').length === n, revisions,
    { timeout: 15000 });
}

test('the first screen says what to do', async () => {
  assert.ok(await page.isVisible('#welcome'));
  const text = await page.textContent('#welcome');
  assert.match(text, /preset/);
  assert.match(text, /New tree/);
  await shot('history-first-screen.png');
});

test('Ctrl+Z and Ctrl+Shift+Z undo and redo a prune and a stroke, byte for byte', async () => {
  await page.selectOption('#preset', 'default');
  await page.fill('#seed', '2');
  await page.click('#new-session');
  await page.waitForFunction(() => window.meristem.summary?.step === 0, null, { timeout: 15000 });
  assert.equal(await page.isVisible('#welcome'), false, 'the first screen goes with a session');
  const id = await page.evaluate(() => window.meristem.sessionId);
  await page.evaluate(() => window.meristem.stepN(6));
  await settle(2);
  const grown = await summary();
  const grownGlb = await glb(id);
  // A brush stroke (two dabs) and growth on it, as the brush tool sends them.
  await page.evaluate(() => window.meristem.send([
    { op: 'add_markers', center: [2, 10, 0], radius: 3, pressure: 0.7, count: 60 },
    { op: 'add_markers', center: [3, 11, 0], radius: 3, pressure: 0.7, count: 60 },
    { op: 'step', count: 2 }]));
  await settle(3);
  const brushed = await summary();
  const brushedGlb = await glb(id);
  const skel = (await api(d.url, 'GET', `/v1/sessions/${id}/skeleton?alive=1`)).body;
  const twig = skel.nodes.find((n) => n.order === 1);
  await page.evaluate((node) => window.meristem.send([{ op: 'prune', node }]), twig.id);
  await settle(4);
  const pruned = await summary();
  assert.notEqual(pruned.hash, brushed.hash);
  const items = await listed();
  assert.deepEqual(items.map((i) => i.revision), [0, 1, 2, 3]);
  assert.match(items[2].text, /brush ×2, step ×2/);
  assert.match(items[3].text, new RegExp(`prune ${twig.id}`));
  assert.ok(items[3].current);

  await page.click('#view canvas', { position: { x: 5, y: 5 } });
  await page.keyboard.press('Control+z');   // undo the prune
  await settle(5);
  let now = await summary();
  assert.equal(now.hash, brushed.hash);
  assert.ok((await glb(id)).equals(brushedGlb), 'undo of a prune: the GLB byte for byte');
  assert.ok((await listed())[2].current, 'the list marks the tree shown');

  await page.keyboard.press('Control+z');   // undo the stroke
  await settle(6);
  now = await summary();
  assert.equal(now.hash, grown.hash);
  assert.ok((await glb(id)).equals(grownGlb), 'undo of a stroke: the GLB byte for byte');
  await shot('history-undone.png');

  await page.keyboard.press('Control+Shift+z');   // redo the stroke
  await settle(7);
  assert.equal((await summary()).hash, brushed.hash);
  await page.click('#redo');                       // and the prune
  await settle(8);
  assert.equal((await summary()).hash, pruned.hash);
  assert.equal(await page.isDisabled('#redo'), true, 'nothing left to redo');
  assert.deepEqual(errors, []);
});

test('the slider scrubs past revisions; Restore and the list go back to one', async () => {
  const id = await page.evaluate(() => window.meristem.sessionId);
  const before = await summary();
  const latestTriangles = await page.evaluate(() => window.meristem.lastLoad.triangles);
  snapshots.length = 0;
  // Scrub back to revision 1 (the first growth), one revision at a time.
  for (const r of [6, 4, 2, 1]) {
    await page.$eval('#history-slider', (s, v) => {
      s.value = String(v);
      s.dispatchEvent(new Event('input', { bubbles: true }));
    }, r);
  }
  await page.waitForFunction(() => document.querySelector('#history-at').textContent === 'r1');
  await page.waitForFunction(() => !window.meristem.panels.history.fetching);
  assert.ok(snapshots.some((u) => /revision=1(&|$)/.test(u)), `asked for revision 1: ${snapshots.join(' ')}`);
  const pastTriangles = await page.evaluate(() => window.meristem.lastLoad.triangles);
  assert.ok(pastTriangles < latestTriangles, `${pastTriangles} triangles at r1, ${latestTriangles} now`);
  assert.ok(await page.isVisible('#history-restore'));
  // Scrubbing changes nothing on the server.
  assert.equal((await api(d.url, 'GET', `/v1/sessions/${id}`)).body.revision, before.revision);
  await shot('history-scrubbed.png');

  await page.click('#history-restore');
  await settle(before.revision + 2);
  const restored = await summary();
  assert.equal(restored.revision, before.revision + 1);
  assert.equal(restored.step, 6);
  assert.ok((await glb(id)).equals(await glb(id, 1)), 'restored: the GLB of revision 1');
  assert.equal(await page.isVisible('#history-restore'), false);

  await page.click('#history-list li[data-revision="3"]');
  await settle(before.revision + 3);
  assert.ok((await glb(id)).equals(await glb(id, 3)), 'a click in the list: the GLB of revision 3');
  await shot('history-list.png');
  assert.deepEqual(errors, []);
});
