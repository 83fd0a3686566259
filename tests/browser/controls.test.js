'use strict';
// The brush client's symmetric brushing, its progress bar and Cancel button, and a
// tree too big for one glTF primitive, in headless Chromium against a real meristemd.
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

// A big tree's bark comes as several glTF primitives (at most 65,535 vertices each):
// every one of them is drawn, picked, highlighted and pruned, not only one.
test('a tree whose bark spans several primitives is picked and pruned in any of them', async () => {
  const s = (await api(d.url, 'POST', '/v1/sessions', { preset: 'fig7-bh-0.52', seed: 3 })).body;
  let n = 0;
  while (n < 20000) n = (await api(d.url, 'POST', `/v1/sessions/${s.id}/edits`, { op: 'step', count: 1 })).body.internodes;
  await page.goto(`${d.url}/?session=${s.id}`);
  await page.waitForFunction(() => window.meristem?.ready && window.meristem.lastLoadMs !== null, null, { timeout: 60000 });
  const chunks = await page.evaluate(() => window.meristem.viewer.barkMeshes.length);
  assert.ok(chunks >= 2, `${chunks} bark primitives for ${n} internodes`);
  // Every living internode has bark in the snapshot.
  assert.equal(await page.evaluate(() => window.meristem.nodeIds().length), n);
  // An internode of the last primitive, picked where it is drawn and pruned by a click.
  const target = await page.evaluate(() => {
    const v = window.meristem.viewer, last = v.barkMeshes[v.barkMeshes.length - 1];
    const ids = new Set();
    const a = last.geometry.userData.nodeIds;
    for (let i = 0; i < a.count; i++) ids.add(Math.round(a.getX(i)));
    const nodes = [...v.nodes()].filter(([id]) => ids.has(id));
    nodes.sort((p, q) => q[1].count - p[1].count || p[1].center[1] - q[1].center[1]);
    return nodes.slice(0, 40).map(([id]) => id);
  });
  await page.click('[data-tool=prune]');
  let pick = null, at = null;
  for (const id of target) {
    at = await page.evaluate((k) => window.meristem.screenOfNode(k), id);
    pick = await page.evaluate(({ x, y }) => window.meristem.viewer.pick(x, y, 0), at);
    if (pick && target.includes(pick.node)) break;
    pick = null;
  }
  assert.ok(pick, 'an internode of the last primitive is picked where it is drawn');
  await page.mouse.move(at.x, at.y);
  await page.waitForFunction((k) => window.meristem.viewer.highlights?.get('hover')?.ids.has(k) &&
    window.meristem.viewer.overlay.children.length > 0, pick.node);
  const from = edits.length;
  await page.mouse.click(at.x, at.y);
  const after = await page.evaluate(() => window.meristem.idle());
  assert.deepEqual(edits.slice(from), [{ op: 'prune', node: pick.node }]);
  assert.ok(after.internodes < n, `internodes ${n} → ${after.internodes}`);
  assert.ok(!(await page.evaluate((k) => window.meristem.viewer.nodes().has(k), pick.node)));
});

test('a link to a session that does not exist shows why, and the page carries on', async () => {
  const gone = 'f'.repeat(32);
  await page.goto(`${d.url}/?session=${gone}`);
  await page.waitForFunction(() => window.meristem?.ready, null, { timeout: 30000 });
  assert.match(await page.textContent('#problem-detail'), /session/i);
  assert.ok(!new URL(page.url()).searchParams.has('session'), 'the dead id left the address');
  assert.equal(await page.evaluate(() => window.meristem.sessionId), null);
});

test('no script errors', () => {
  assert.deepEqual(errors, []);
});
