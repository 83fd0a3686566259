'use strict';
// The brush client (issue 6) in headless Chromium against a real meristemd: a session
// from a preset, growth, brush strokes with pen pressure, a stroke constrained to a
// bud, prune, bend, the apical schedule, a refused edit, and the snapshot load time.
const { test, before, after } = require('node:test');
const assert = require('node:assert/strict');
const path = require('node:path');
const { chromium } = require('playwright-core');
const { startDaemon, api } = require('../support/daemon.js');

const CHROMIUM_ARGS = ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
  '--disable-background-networking', '--disable-component-update', '--disable-sync',
  '--use-angle=swiftshader', '--enable-unsafe-swiftshader'];
const ARTIFACTS = process.env.MER_ARTIFACTS || '/tmp';

let d, browser, page, cdp, id;
const errors = [];
const expectedRefusals = [];   // statuses the tests provoke on purpose
const edits = [];              // every POST .../edits the page sent: {t, body}

const shot = (name) => page.screenshot({ path: path.join(ARTIFACTS, `brush-${name}.png`) });
const idle = () => page.evaluate(() => window.meristem.idle());
const summary = async () => (await api(d.url, 'GET', `/v1/sessions/${id}`)).body;
/** The dab objects of the edit requests sent since index `from`. */
function dabsSince(from) {
  const out = [];
  for (const { body } of edits.slice(from)) {
    for (const e of body.edits || [body]) if (e.op === 'add_markers' && e.center) out.push(e);
  }
  return out;
}
const markersOfDab = (e) => 1 + Math.round(((e.count ?? 50) - 1) * (e.pressure ?? 0.5) ** 2);
const dist = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);

/** A pen stroke through client points with a constant pressure, as real pointer events. */
async function penStroke(points, pressure, { stepMs = 25 } = {}) {
  const ev = (type, { x, y }, extra = {}) => cdp.send('Input.dispatchMouseEvent',
    { type, x, y, pointerType: 'pen', force: pressure, ...extra });
  await ev('mouseMoved', points[0], { force: 0 });
  await ev('mousePressed', points[0], { button: 'left', buttons: 1, clickCount: 1 });
  for (let i = 1; i < points.length; i++) {
    await ev('mouseMoved', points[i], { button: 'left', buttons: 1 });
    await new Promise((r) => setTimeout(r, stepMs));
  }
  await ev('mouseReleased', points[points.length - 1], { button: 'left', buttons: 0, clickCount: 1 });
}

/** `n` client points from a to b. */
function line(a, b, n) {
  return Array.from({ length: n }, (_, i) => ({ x: a.x + ((b.x - a.x) * i) / (n - 1), y: a.y + ((b.y - a.y) * i) / (n - 1) }));
}

const screenOf = (p) => page.evaluate((q) => window.meristem.viewer.screenOf(q), p);

before(async () => {
  if (!process.env.CHROMIUM) throw new Error('CHROMIUM is not set; configure found no chromium');
  d = await startDaemon(['--quiet']);
  browser = await chromium.launch({ executablePath: process.env.CHROMIUM, headless: true, args: CHROMIUM_ARGS });
  page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  cdp = await page.context().newCDPSession(page);
  page.on('pageerror', (e) => errors.push(String(e)));
  page.on('console', (m) => {
    const status = /status of (\d+)/.exec(m.text());
    if (m.type() === 'error' && !(status && expectedRefusals.includes(Number(status[1])))) errors.push(m.text());
  });
  page.on('requestfailed', (r) => errors.push(`request failed: ${r.url()}`));
  page.on('response', (r) => {
    if (r.status() >= 400 && !expectedRefusals.includes(r.status())) errors.push(`${r.status()} ${r.url()}`);
  });
  page.on('request', (r) => {
    if (r.method() === 'POST' && /\/edits$/.test(r.url())) edits.push({ t: Date.now(), body: JSON.parse(r.postData()) });
  });
  await page.goto(`${d.url}/`);
  await page.waitForFunction(() => window.meristem?.ready, null, { timeout: 30000 });
});
after(async () => { await browser?.close(); await d?.stop(); });

test('creates a session from a preset with its description and seed; the URL reopens it', async () => {
  await page.selectOption('#preset', 'fig15-brushed');
  assert.match(await page.textContent('#preset-description'), /Fig\. 15/);
  await page.fill('#seed', '7');
  await page.click('#new-session');
  await page.waitForFunction(() => window.meristem.sessionId && window.meristem.lastLoadMs !== null);
  id = await page.evaluate(() => window.meristem.sessionId);
  assert.match(id, /^[0-9a-f]{32}$/);
  assert.equal(new URL(page.url()).searchParams.get('session'), id);
  const s = await summary();
  assert.equal(s.preset, 'fig15-brushed');
  assert.equal(s.seed, 7);
  await page.reload();
  await page.waitForFunction(() => window.meristem?.ready);
  assert.equal(await page.evaluate(() => window.meristem.sessionId), id, 'reload returns to the same tree');
  assert.equal(await page.inputValue('#seed'), '7');
});

test('steps once and N times; the stats panel follows', async () => {
  await page.click('#step-once');
  await idle();
  assert.equal((await summary()).step, 1);
  await page.fill('#step-count', '11');
  await page.click('#step-n');
  await idle();
  const s = await summary();
  assert.equal(s.step, 12);
  assert.equal(await page.textContent('#stat-step'), '12');
  assert.equal(await page.textContent('#stat-internodes'), s.internodes.toLocaleString('en-US'));
  assert.ok(s.internodes > 5, `the seedling grew (${s.internodes} internodes)`);
});

test('play grows the tree at a rate and pause stops it', async () => {
  const s0 = (await summary()).step;
  await page.selectOption('#rate', '8');
  await page.click('#play');
  await page.waitForFunction((s) => window.meristem.summary.step >= s + 2, s0, { timeout: 20000 });
  await page.click('#play');
  await idle();
  const s1 = (await summary()).step;
  await new Promise((r) => setTimeout(r, 600));
  assert.equal((await summary()).step, s1, 'paused');
  assert.ok(s1 >= s0 + 2);
});

let strokes = {};
test('brush strokes at two pressures lay markers where the stroke went, batched', async () => {
  await page.click('[data-tool=brush]');
  await page.uncheck('#constrain');
  await page.fill('#radius', '3');
  await page.fill('#count', '60');
  const s0 = await summary();
  const h = s0.height;
  // Two vertical strokes beside the trunk, starting off the tree: the working plane
  // then runs through the tree's centre, facing the camera.
  for (const [name, x, pressure] of [['light', -3, 0.1], ['heavy', 3.5, 0.9]]) {
    const before = await summary();
    const markersBefore = await page.evaluate(() => window.meristem.markerPositions());
    const from = edits.length;
    const a = await screenOf([x, h * 0.25, 0]), b = await screenOf([x, h * 0.95, 0]);
    const pts = line(a, b, 40);
    const t0 = Date.now();
    await penStroke(pts, pressure);
    await idle();
    const ms = Date.now() - t0;
    const dabs = dabsSince(from);
    const requests = edits.length - from;
    assert.ok(dabs.length >= 3, `${name}: ${dabs.length} dabs`);
    for (const e of dabs) assert.ok(Math.abs(e.pressure - pressure) < 0.02, `pen pressure ${e.pressure} reached the dab`);
    assert.ok(requests < pts.length / 3, `${name}: ${requests} requests for ${pts.length} pointer events`);
    assert.ok(requests <= Math.ceil(ms / 250) + 2, `${name}: ${requests} requests in ${ms} ms: batched`);
    // Each dab centre lies on the stroke's screen path.
    for (const e of dabs) {
      const p = await screenOf(e.center);
      const t = Math.max(0, Math.min(1, ((p.x - a.x) * (b.x - a.x) + (p.y - a.y) * (b.y - a.y)) /
        ((b.x - a.x) ** 2 + (b.y - a.y) ** 2)));
      const off = Math.hypot(p.x - (a.x + t * (b.x - a.x)), p.y - (a.y + t * (b.y - a.y)));
      assert.ok(off < 6, `dab ${JSON.stringify(e.center)} is ${off.toFixed(1)} px off the stroke`);
    }
    const after = await summary();
    const added = dabs.reduce((n, e) => n + markersOfDab(e), 0);
    assert.equal(after.markers - before.markers, added, `${name}: the session gained the dabs' markers`);
    const all = await page.evaluate(() => window.meristem.markerPositions());
    assert.equal(all.length, after.markers, 'the ?markers=1 snapshot draws every marker');
    const key = (p) => p.map((v) => v.toFixed(3)).join();
    const old = new Set(markersBefore.map(key));
    const fresh = all.filter((p) => !old.has(key(p)));
    const spread = 3 * (0.1 + 0.9 * pressure);
    let far = 0;
    for (const p of fresh) {
      const nearest = Math.min(...dabs.map((e) => dist(p, e.center)));
      assert.ok(nearest <= spread * 1.02 + 0.01, `${name}: a marker ${nearest.toFixed(2)} from its dab (spread ${spread})`);
      if (nearest > 0.6) far++;
    }
    strokes[name] = { dabs, fresh, added, requests, events: pts.length };
    if (name === 'light') assert.equal(far, 0, 'light pressure: a tight line');
    else assert.ok(far > fresh.length / 2, 'heavy pressure: a wide cloud');
  }
  assert.ok(strokes.heavy.added / strokes.heavy.dabs.length > 5 * strokes.light.added / strokes.light.dabs.length,
    'heavy pressure lays many more markers per dab');
  await shot('strokes');
});

test('growth follows the brushed markers', async () => {
  const maxBefore = await page.evaluate(() => window.meristem.viewer.maxNodeId());
  const s0 = await summary();
  await page.fill('#step-count', '8');
  await page.click('#step-n');
  await idle();
  const s1 = await summary();
  assert.ok(s1.internodes > s0.internodes, 'the tree grew');
  assert.ok(s1.markers < s0.markers, 'buds consumed brushed markers');
  const heavy = strokes.heavy.dabs.map((e) => e.center);
  const grown = await page.evaluate((m) => [...window.meristem.viewer.nodes()].filter(([k]) => k > m).map(([, v]) => v.center), maxBefore);
  const near = grown.filter((c) => Math.min(...heavy.map((h) => dist(c, h))) < 3);
  assert.ok(near.length >= 3, `${near.length} of ${grown.length} new internodes grew into the heavy stroke's cloud`);
  assert.ok(s1.bounds.max[0] > s0.bounds.max[0] + 1, 'the crown widened towards the heavy stroke (+x)');
  await shot('grown');
});

test('a stroke that starts on a bud constrains growth to its descendants until released', async () => {
  await page.check('#constrain');
  // The top of the stem (the seedling grew straight up: the first ids are the stem).
  const top = await page.evaluate(() => {
    let best = null;
    for (const [k, v] of window.meristem.viewer.nodes()) {
      if (k < 15 && v.axis[1] > 0.9 && (!best || v.ymax > best.ymax)) best = { id: k, ...v };
    }
    return best;
  });
  assert.ok(top, 'the stem is in the snapshot');
  const h = (await summary()).height;
  // Markers low down, beside the stem but clear of every bud's occupancy zone (ρ = 2),
  // for buds outside the subtree to reach for.
  const centres = await page.evaluate(() => [...window.meristem.viewer.nodes().values()].map((v) => v.center));
  const low = [];
  for (let a = 0; a < 64 && low.length < 40; a++) {
    const ang = (a / 64) * 2 * Math.PI;
    for (const y of [2, 2.8, 3.6, 4.4]) {
      const p = [3.4 * Math.cos(ang), y, 3.4 * Math.sin(ang)].map((x) => Math.round(x * 1000) / 1000);
      if (centres.every((c) => dist(c, p) > 2.6) && low.length < 40) low.push(p);
    }
  }
  assert.ok(low.length >= 8, `room for ${low.length} low markers`);
  assert.equal((await api(d.url, 'POST', `/v1/sessions/${id}/edits`, { op: 'add_markers', points: low })).status, 200);
  await page.evaluate(() => window.meristem.refresh());
  await idle();
  const outside = (nodes, y) => nodes.filter(([, v]) => v.center[1] < y).length;
  const nodesBefore = await page.evaluate(() => [...window.meristem.viewer.nodes()]);
  const maxBefore = Math.max(...nodesBefore.map(([k]) => k));
  const from = edits.length;
  const start = await page.evaluate((n) => window.meristem.screenOfNode(n), top.id);
  const pick = await page.evaluate(({ x, y }) => window.meristem.viewer.pick(x, y), start);
  assert.ok(pick, 'the stroke starts on the tree');
  const end = await screenOf([top.center[0], top.ymax + 9, top.center[2]]);
  await penStroke(line(start, end, 24), 0.6);
  await idle();
  const first = dabsSince(from)[0];
  assert.deepEqual(first.constrain, { node: pick.node, bud: 0 }, 'the first dab names the bud');
  assert.ok(await page.isHidden('#problem'), `no refusal: ${await page.textContent('#problem')}`);
  assert.ok(await page.isVisible('#constraint'), 'the page shows the constraint');
  const picked = nodesBefore.find(([k]) => k === pick.node)[1];
  const s0 = await summary();
  await page.fill('#step-count', '6');
  await page.click('#step-n');
  await idle();
  const s1 = await summary();
  assert.ok(s1.internodes > s0.internodes, `the constrained bud grew (${s0.internodes} → ${s1.internodes})`);
  const nodesAfter = await page.evaluate(() => [...window.meristem.viewer.nodes()]);
  // Everything grown since is above the picked node: no internode appeared elsewhere.
  const ylim = picked.ymin - 0.5;
  assert.equal(outside(nodesAfter, ylim), outside(nodesBefore, ylim),
    'the count of internodes outside the subtree (below the bud) is unchanged');
  const fresh = nodesAfter.filter(([k]) => k > maxBefore);
  for (const [k, v] of fresh) assert.ok(v.center[1] > ylim, `new node ${k} grew above the bud`);
  const lowLeft = (ms) => ms.filter((p) => low.some((q) => dist(p, q) < 1e-3)).length;
  assert.equal(lowLeft(await page.evaluate(() => window.meristem.markerPositions())), low.length,
    'buds outside the subtree left the low markers alone');
  await shot('constrained');
  // Release: the rest of the tree may grow again.
  await page.click('#release');
  await idle();
  assert.ok(await page.isHidden('#constraint'));
  assert.deepEqual(edits[edits.length - 1].body, { op: 'release' });
  await page.click('#step-n');
  await idle();
  const released = await page.evaluate(() => [...window.meristem.viewer.nodes()]);
  const lowNow = lowLeft(await page.evaluate(() => window.meristem.markerPositions()));
  assert.ok(outside(released, ylim) > outside(nodesAfter, ylim) || lowNow < low.length,
    'after release, buds below grow towards the low markers');
});

test('bend: dragging a branch about its base turns it', async () => {
  await page.click('[data-tool=bend]');
  await page.click('#frame');
  await idle();
  // A trunk internode low on the stem, and one above it to watch.
  const nodes = await page.evaluate(() => [...window.meristem.viewer.nodes()]);
  // The seedling grew straight up the preset's column of markers: the first ids are the stem.
  const trunk = nodes.filter(([k, v]) => k < 12 && v.axis[1] > 0.9).sort((p, q) => p[0] - q[0]);
  assert.ok(trunk.length >= 6, `a stem of ${trunk.length} upright internodes`);
  const [bendId] = trunk.find(([, v]) => v.center[1] > 2.5);
  const [watchId, watch0] = trunk[trunk.length - 1];
  const s0 = await summary();
  const from = edits.length;
  const p = await page.evaluate((n) => window.meristem.screenOfNode(n), bendId);
  const pick = await page.evaluate(({ x, y }) => window.meristem.viewer.pick(x, y), p);
  assert.ok(pick, 'the drag starts on the stem');
  // Hovering highlights the node before anything is sent.
  await page.mouse.move(p.x, p.y);
  await page.waitForFunction((n) => window.meristem.viewer.highlights?.get('hover')?.ids.has(n), pick.node);
  await page.mouse.down();
  for (let i = 1; i <= 10; i++) await page.mouse.move(p.x + 6 * i, p.y);   // pull it sideways
  await page.mouse.up();
  await idle();
  const sent = edits.slice(from).map((e) => e.body).find((b) => b.op === 'bend');
  assert.ok(sent, 'a bend edit was sent');
  assert.equal(sent.node, pick.node);
  assert.ok(Math.abs(sent.angle) > 5, `bend angle ${sent.angle}°`);
  const s1 = await summary();
  assert.equal(s1.revision, s0.revision + 1);
  assert.notEqual(s1.hash, s0.hash, 'the tree changed');
  const watch1 = await page.evaluate((n) => window.meristem.nodeInfo(n), watchId);
  const cos = watch0.axis.reduce((s, a, k) => s + a * watch1.axis[k], 0);
  const turned = Math.acos(Math.min(1, Math.abs(cos))) * 180 / Math.PI;
  assert.ok(turned > 4 || dist(watch0.center, watch1.center) > 0.5,
    `node ${watchId} above the bend turned ${turned.toFixed(1)}° and moved ${dist(watch0.center, watch1.center).toFixed(2)}`);
  await shot('bent');
});

test('prune: clicking a branch highlights it, then cuts it', async () => {
  await page.click('[data-tool=prune]');
  const nodes = await page.evaluate(() => [...window.meristem.viewer.nodes()]);
  // A mid-height internode (not the trunk base, so a tree is left to look at).
  const sorted = nodes.sort((p, q) => p[1].center[1] - q[1].center[1]);
  const [nodeId] = sorted[Math.floor(sorted.length * 0.6)];
  const p = await page.evaluate((n) => window.meristem.screenOfNode(n), nodeId);
  const pick = await page.evaluate(({ x, y }) => window.meristem.viewer.pick(x, y), p);
  assert.ok(pick);
  await page.mouse.move(p.x, p.y);
  await page.waitForFunction((n) => {
    const h = window.meristem.viewer.highlights?.get('hover');
    return h && h.ids.has(n);
  }, pick.node);
  const s0 = await summary();
  const from = edits.length;
  await page.mouse.click(p.x, p.y);
  await idle();
  const sent = edits.slice(from).map((e) => e.body);
  assert.deepEqual(sent, [{ op: 'prune', node: pick.node }]);
  const s1 = await summary();
  assert.ok(s1.internodes < s0.internodes, `internodes ${s0.internodes} → ${s1.internodes}`);
  assert.equal(await page.textContent('#stat-internodes'), s1.internodes.toLocaleString('en-US'));
  assert.ok(!(await page.evaluate((n) => window.meristem.viewer.nodes().has(n), pick.node)), 'the node is gone from the snapshot');
  await shot('pruned');
});

test('the apical-control schedule editor sets the session schedule', async () => {
  await page.fill('#apical-off-0', '30');
  await page.fill('#apical-off-1', '18');
  await page.fill('#apical-off-2', '');
  await page.click('#add-lambda-key');
  await page.click('#add-lambda-key');
  const keys = page.locator('#lambda-keys .key');
  await keys.nth(0).locator('.key-step').fill('20');
  await keys.nth(0).locator('.key-value').fill('0.55');
  await keys.nth(1).locator('.key-step').fill('40');
  await keys.nth(1).locator('.key-value').fill('0.48');
  await page.click('#apply-schedule');
  await idle();
  const s = await summary();
  assert.deepEqual(s.schedule.apical_off.slice(0, 3), [30, 18, null]);
  assert.deepEqual(s.schedule.lambda_keys, [[20, 0.55], [40, 0.48]]);
  assert.equal(await page.inputValue('#apical-off-1'), '18');
});

test('parameters show the paper\'s symbols, and an edit changes the session', async () => {
  const symbols = await page.$$eval('#params .param:not([hidden]) .symbol', (els) => els.map((e) => e.textContent));
  for (const s of ['λ', 'α', 'ξ', 'η', 'θ', 'ρ', 'r']) assert.ok(symbols.includes(s), `${s} is shown (${symbols})`);
  assert.ok((await page.textContent('#params')).includes('Perception angle'));
  await page.fill('#param-xi', '0.45');
  await page.click('#apply-params');
  await idle();
  assert.equal((await summary()).params.xi, 0.45);
});

test('a refused edit shows the problem detail and the page keeps working', async () => {
  expectedRefusals.push(422);
  await page.fill('#param-lambda', '7');
  await page.click('#apply-params');
  await page.waitForSelector('#problem:not([hidden])');
  const direct = await api(d.url, 'POST', `/v1/sessions/${id}/edits`, { op: 'set_params', params: { lambda: 7 } });
  assert.equal(direct.status, 422);
  assert.equal(await page.textContent('#problem-detail'), direct.body.detail);
  assert.match(await page.textContent('#problem-title'), /422/);
  await shot('problem');
  await page.click('#problem-close');
  await page.fill('#param-lambda', '0.5');
  const s0 = await summary();
  await page.click('#step-once');
  await idle();
  assert.equal((await summary()).step, s0.step + 1, 'the page still steps the tree');
});

test('views: toggles, colour by order, grid, download link', async () => {
  await page.selectOption('#color', 'order');
  await idle();
  assert.match(await page.evaluate(() => window.meristem.viewer.url), /color=order/);
  assert.ok(await page.evaluate(() => Boolean(window.meristem.viewer.bark.geometry.attributes.color)));
  await page.uncheck('#show-leaves');
  await idle();
  assert.match(await page.evaluate(() => window.meristem.viewer.url), /leaves=0/);
  const href = await page.getAttribute('#download', 'href');
  const r = await api(d.url, 'GET', `/${href}`);
  assert.equal(r.status, 200);
  assert.equal(r.raw.subarray(0, 4).toString(), 'glTF');
  await shot('order');
  await page.check('#show-leaves');
  await page.selectOption('#color', 'none');
  await idle();
});

test('the canvas is not blank', async () => {
  await page.click('#frame');
  await idle();
  const variance = await page.evaluate(() => window.meristem.pixelVariance());
  assert.ok(variance > 20, `canvas luminance variance ${variance}`);
  await shot('final');
});

// The figure: loading a snapshot of a 10,000-internode tree and drawing it, in
// this headless Chromium (software WebGL). Timings are reported, not asserted: these
// machines are noisy (README, Performance). Each load is a new snapshot (the options
// change), so the daemon meshes and encodes every one. The page is a fresh one without
// this file's request listeners: with them, the DevTools protocol reports every
// request and the loads measure the harness as much as the page.
test('a 10,000-internode snapshot loads and draws (time reported, not asserted tightly)', async (t) => {
  const s = (await api(d.url, 'POST', '/v1/sessions', { preset: 'fig7-bh-0.52', seed: 3 })).body;
  let n = 0;
  while (n < 10000) {
    const r = await api(d.url, 'POST', `/v1/sessions/${s.id}/edits`, { op: 'step', count: 1 });
    n = r.body.internodes;
  }
  const clean = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  const cleanErrors = [];
  clean.on('pageerror', (e) => cleanErrors.push(String(e)));
  await clean.goto(`${d.url}/?session=${s.id}`);
  await clean.waitForFunction(() => window.meristem?.ready && window.meristem.lastLoadMs !== null, null, { timeout: 60000 });
  const first = await clean.evaluate(() => window.meristem.lastLoad);
  const loads = [];
  // Each colouring once, a plain load after each: the timings are a report
  // (tests/bench/page-load.js repeats them for a measure).
  for (const c of ['order', 'none', 'light', 'none', 'age', 'none']) {
    await clean.selectOption('#color', c);
    await clean.evaluate(() => window.meristem.idle());
    loads.push({ color: c, ...(await clean.evaluate(() => window.meristem.lastLoad)) });
  }
  const plain = loads.filter((l) => l.color === 'none');
  const ms = (xs) => xs.map((l) => l.ms).sort((a, b) => a - b);
  const median = (xs) => ms(xs)[Math.floor((xs.length - 1) / 2)];
  const fmt = (x) => x.toFixed(0);
  const part = (k) => fmt(plain.map((l) => l[k]).sort((a, b) => a - b)[Math.floor((plain.length - 1) / 2)]);
  const report = `snapshot of ${n} internodes (${plain[0].triangles} triangles, ${plain[0].bytes} bytes): ` +
    `load+draw median ${fmt(median(plain))} ms, best ${fmt(ms(plain)[0])} ms over ${plain.length} plain loads ` +
    `(median fetch ${part('fetchMs')}, parse ${part('parseMs')}, draw ${part('renderMs')} ms); ` +
    `coloured (${loads[0].bytes} bytes) median ${fmt(median(loads.filter((l) => l.color !== 'none')))} ms; ` +
    `on opening the page the tree was drawn ${fmt(first.drawnAt)} ms after navigation`;
  t.diagnostic(report);
  require('node:fs').writeFileSync(path.join(ARTIFACTS, 'brush-load-time.txt'), `${report}\n`);
  assert.ok(plain.every((l) => l.bytes < 1.2e6), 'the page asks for compact snapshots');
  assert.ok(first.prefetched, 'a reopened session\'s snapshot is asked for while the page starts');
  assert.ok(median(plain) < 5000, `median load ${median(plain)} ms`);
  await clean.screenshot({ path: path.join(ARTIFACTS, 'brush-10k.png') });
  // Level of detail (mesh.h, Twig lines): seen whole, the twigs are drawn as lines;
  // a twig is still picked on its prism; zoomed in, the prisms are drawn again.
  const lod = await clean.evaluate(() => {
    const v = window.meristem.viewer, info = () => ({ shown: v.twigLinesShown,
      lines: v.renderer.info.render.lines, triangles: v.renderer.info.render.triangles });
    v.render();
    const far = info();
    v.setVisible({ leaves: false });
    const twigs = new Set();
    for (const m of v.barkMeshes.filter((b) => b.userData.twig)) {
      const ids = m.geometry.userData.nodeIds;
      for (let i = 0; i < ids.count; i++) twigs.add(Math.round(ids.getX(i)));
    }
    let twig = null, nearest = Infinity;
    for (const id of twigs) {
      const [x, y, z] = v.nodes().get(id).center;
      const dist = Math.hypot(x - v.camera.position.x, y - v.camera.position.y, z - v.camera.position.z);
      if (dist < nearest) { nearest = dist; twig = id; }
    }
    const at = window.meristem.screenOfNode(twig);
    const picked = v.pick(at.x, at.y)?.node ?? null;
    v.setVisible({ leaves: true });
    v.camera.position.sub(v.controls.target).multiplyScalar(0.15).add(v.controls.target);
    v.controls.update();
    v.render();
    return { far, near: info(), twigs: twigs.size, twig, picked };
  });
  t.diagnostic(`twig LOD: ${JSON.stringify(lod)}`);
  assert.ok(lod.twigs > 1000, `${lod.twigs} twig internodes`);
  assert.equal(lod.far.shown, true);
  // One segment per twig internode (the rest of the lines are the ground grid's).
  assert.equal(lod.far.lines - lod.near.lines, lod.twigs, JSON.stringify(lod));
  assert.equal(lod.picked, lod.twig);
  assert.equal(lod.near.shown, false);
  assert.ok(lod.near.triangles > lod.far.triangles + 4 * lod.twigs, JSON.stringify(lod));
  await clean.close();
  assert.deepEqual(cleanErrors, []);
});

test('no script errors and no unexpected failed requests', () => {
  assert.deepEqual(errors, []);
});
