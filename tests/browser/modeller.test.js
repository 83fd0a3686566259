'use strict';
// The brush client as a modeller expects it (issue 14, items 4 and 5), in headless
// Chromium against a real meristemd: a plain stroke never constrains growth, Shift+drag
// does, and the constrained branch is drawn at any zoom; a step that grows nothing says
// why and offers Release; hovering with Prune names the node and what would go; Bend
// shows a ghost of the bent branch while dragging and sends a spread bend.
const { test, before, after } = require('node:test');
const assert = require('node:assert/strict');
const path = require('node:path');
const { startDaemon, api } = require('../support/daemon.js');
const { openPage } = require('../support/chromium.js');
const ARTIFACTS = process.env.MER_ARTIFACTS || '/tmp';

let d, browser, page, cdp, id;
const errors = [];
const edits = [];   // every POST .../edits the page sent: body

const shot = (name) => page.screenshot({ path: path.join(ARTIFACTS, `modeller-${name}.png`) });
const idle = () => page.evaluate(() => window.meristem.idle());
const summary = async () => (await api(d.url, 'GET', `/v1/sessions/${id}`)).body;
const firstDabSince = (from) => edits.slice(from).flatMap((b) => b.edits || [b]).find((e) => e.op === 'add_markers');

/** A mouse drag through client points, as real pointer events; `modifiers` 8 is Shift. */
async function drag(points, modifiers = 0) {
  const ev = (type, { x, y }, extra = {}) => cdp.send('Input.dispatchMouseEvent', { type, x, y, modifiers, ...extra });
  await ev('mouseMoved', points[0]);
  await ev('mousePressed', points[0], { button: 'left', buttons: 1, clickCount: 1 });
  for (const p of points.slice(1)) {
    await ev('mouseMoved', p, { button: 'left', buttons: 1 });
    await new Promise((r) => setTimeout(r, 20));
  }
  await ev('mouseReleased', points[points.length - 1], { button: 'left', buttons: 0, clickCount: 1 });
}
const line = (a, b, n) => Array.from({ length: n }, (_, i) => ({ x: a.x + ((b.x - a.x) * i) / (n - 1), y: a.y + ((b.y - a.y) * i) / (n - 1) }));

/** The stem's internodes (the first ids, upright), bottom first. */
const stem = () => page.evaluate(() => [...window.meristem.viewer.nodes()]
  .filter(([k, v]) => k < 12 && v.axis[1] > 0.85).sort((a, b) => a[0] - b[0]));

before(async () => {
  d = await startDaemon(['--quiet']);
  ({ browser, page, cdp } = await openPage());
  page.on('pageerror', (e) => errors.push(String(e)));
  page.on('response', (r) => { if (r.status() >= 400) errors.push(`${r.status()} ${r.url()}`); });
  page.on('request', (r) => {
    if (r.method() === 'POST' && /\/edits$/.test(r.url())) edits.push(JSON.parse(r.postData()));
  });
  await page.goto(`${d.url}/`);
  await page.waitForFunction(() => window.meristem?.ready, null, { timeout: 30000 });
  await page.selectOption('#preset', 'fig15-brushed');
  await page.fill('#seed', '3');
  await page.click('#new-session');
  await page.waitForFunction(() => window.meristem.sessionId && window.meristem.lastLoadMs !== null);
  id = await page.evaluate(() => window.meristem.sessionId);
  await page.fill('#step-count', '10');
  await page.click('#step-n');
  await idle();
  await page.click('#frame');
  await idle();
});
after(async () => { await browser?.close(); await d?.stop(); });

test('a plain stroke from a branch lays markers only; Shift+drag constrains, drawn at any zoom', async () => {
  await page.click('[data-tool=brush]');
  assert.match(await page.textContent('#hint'), /Shift\+drag/);
  assert.equal(await page.isChecked('#constrain'), false, '"grow only from here" is off by default');
  const [[topId]] = (await stem()).slice(-1);
  const start = await page.evaluate((n) => window.meristem.screenOfNode(n), topId);
  const pick = await page.evaluate(({ x, y }) => window.meristem.viewer.pick(x, y), start);
  assert.ok(pick, 'the stroke starts on the tree');
  let from = edits.length;
  await drag(line(start, { x: start.x + 80, y: start.y - 120 }, 10));
  await idle();
  assert.ok(firstDabSince(from), 'the stroke laid markers');
  assert.equal(firstDabSince(from).constrain, undefined, 'a plain stroke constrains nothing');
  assert.ok(await page.isHidden('#constraint'));

  from = edits.length;
  await drag(line(start, { x: start.x - 80, y: start.y - 120 }, 10), 8);
  await idle();
  assert.deepEqual(firstDabSince(from).constrain, { node: pick.node, bud: 0 }, 'Shift+drag constrains to the bud');
  assert.ok(await page.isVisible('#constraint'));
  const marks = () => page.evaluate(() => window.meristem.session.constraint.marks.children
    .map((o) => ({ type: o.type, n: o.geometry.attributes.position.count, depthTest: o.material.depthTest,
      size: o.material.size, attenuated: o.material.sizeAttenuation })));
  const m = await marks();
  const pin = m.find((o) => o.type === 'Points');
  assert.ok(pin && pin.n === 1 && pin.attenuated === false && pin.size >= 10, 'a pin of fixed pixel size on the bud');
  assert.ok(m.some((o) => o.type === 'LineSegments' && o.depthTest === false), 'the branch drawn as lines over everything');
  await shot('constrained');
  // Far away the tree is a few pixels tall; the pin still covers its size in pixels.
  await page.evaluate(() => {
    const v = window.meristem.viewer;
    v.camera.position.multiplyScalar(12);
    v.camera.updateMatrixWorld();
    v.render();
  });
  await shot('constrained-far');
  const pinPx = await page.evaluate(() => {
    const v = window.meristem.viewer, n = v.nodes().get(window.meristem.constraint.node);
    return v.screenOf(n.center);
  });
  const png = await page.screenshot({ clip: { x: pinPx.x - 4, y: pinPx.y - 4, width: 8, height: 8 } });
  assert.ok(png.length > 0);
  await page.click('#frame');
  await idle();
});

test('a step that grows nothing says why, and Release lifts the constraint', async () => {
  // A session whose buds have no marker to grow towards, opened in the page.
  const bare = (await api(d.url, 'POST', '/v1/sessions', { preset: 'fig4-colonization', seed: 1, params: { marker_count: 0 } })).body;
  await api(d.url, 'POST', `/v1/sessions/${bare.id}/edits`,
    { op: 'add_markers', center: [0, 40, 0], radius: 0.5, pressure: 0.1, constrain: { node: 0, bud: 1 } });
  await page.goto(`${d.url}/?session=${bare.id}`);
  await page.waitForFunction(() => window.meristem?.ready && window.meristem.sessionId);
  id = bare.id;
  await page.click('#step-once');
  await idle();
  assert.ok(await page.isVisible('#stalled'), 'the page says the step grew nothing');
  assert.equal(await page.getAttribute('#stalled', 'data-reason'), 'constrained');
  assert.match(await page.textContent('#stalled-reason'), /constrained to node 0/);
  assert.ok(await page.isVisible('#stalled-release'));
  await shot('stalled');
  await page.click('#stalled-release');
  await idle();
  assert.deepEqual(edits[edits.length - 1], { op: 'release' });
  assert.ok(await page.isHidden('#stalled'));
  assert.equal((await summary()).constraint, null);
  await page.click('#step-once');
  await idle();
  assert.equal(await page.getAttribute('#stalled', 'data-reason'), 'no-markers');
  assert.ok(await page.isHidden('#stalled-release'), 'Release only for a constraint');
});

test('hovering with Prune names the node and the subtree that would go', async () => {
  const grown = (await api(d.url, 'POST', '/v1/sessions', { preset: 'default', seed: 2 })).body;
  await api(d.url, 'POST', `/v1/sessions/${grown.id}/edits`, { op: 'step', count: 8 });
  await page.goto(`${d.url}/?session=${grown.id}`);
  await page.waitForFunction(() => window.meristem?.ready && window.meristem.lastLoadMs !== null);
  id = grown.id;
  await page.click('[data-tool=prune]');
  const s = await stem();
  const [nodeId] = s[Math.floor(s.length / 2)];
  const p = await page.evaluate((n) => window.meristem.screenOfNode(n), nodeId);
  const hit = await page.evaluate(({ x, y }) => window.meristem.viewer.pick(x, y), p);
  await page.mouse.move(p.x, p.y);
  await page.waitForFunction(() => window.meristem.prune.hoverInfo?.internodes > 0);
  const info = await page.evaluate(() => window.meristem.prune.hoverInfo);
  assert.equal(info.node, hit.node);
  const text = await page.textContent('#node-info');
  assert.match(text, new RegExp(`node ${hit.node} · order ${info.order} · ${info.internodes} internodes? would go`));
  assert.ok(await page.isVisible('#node-info'));
  await shot('prune-hover');
  const before = await summary();
  await page.mouse.down();
  await page.mouse.up();
  await idle();
  const after = await summary();
  assert.equal(before.internodes - after.internodes, info.internodes, 'the label said what went');
});

test('Bend shows the bent branch while dragging and sends a spread bend', async () => {
  await page.click('[data-tool=bend]');
  assert.match(await page.textContent('#hint'), /curving its first 3 internodes/);
  const s = await stem();
  const [nodeId] = s[1];
  const p = await page.evaluate((n) => window.meristem.screenOfNode(n), nodeId);
  const from = edits.length;
  await page.mouse.move(p.x, p.y);
  await page.mouse.down();
  for (let i = 1; i <= 8; i++) await page.mouse.move(p.x + 8 * i, p.y);
  await page.waitForFunction(() => window.meristem.bend.ghost !== null);
  const moved = await page.evaluate(() => {
    const g = window.meristem.bend.ghost, pos = g.geometry.attributes.position, rest = g.userData.rest;
    let most = 0;
    for (let i = 0; i < pos.count; i++) {
      most = Math.max(most, Math.hypot(pos.getX(i) - rest[3 * i], pos.getY(i) - rest[3 * i + 1], pos.getZ(i) - rest[3 * i + 2]));
    }
    return { most, vertices: pos.count, visible: g.visible };
  });
  assert.ok(moved.vertices > 0 && moved.visible, 'a ghost of the branch');
  assert.ok(moved.most > 0.2, `the ghost turned while dragging (${moved.most.toFixed(2)})`);
  assert.equal(edits.length, from, 'nothing sent while dragging');
  await shot('bend-preview');
  await page.mouse.up();
  await idle();
  const sent = edits.slice(from).flatMap((b) => b.edits || [b]).find((e) => e.op === 'bend');
  assert.ok(sent, 'a bend was sent');
  assert.equal(sent.spread, 3);
  assert.equal(await page.evaluate(() => window.meristem.bend.ghost), null, 'the ghost goes with the drag');
});

test('no script errors and no failed requests', () => {
  assert.deepEqual(errors, []);
});
