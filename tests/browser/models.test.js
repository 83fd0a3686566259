'use strict';
// The page for each growth model, in headless Chromium against a real meristemd: an
// L-system session made from the page (its source in the editor, a syntax error shown
// at its line, a derivation step changing the summary); an inverse session (dragging a
// control point regrows the tree, the time slider asks for a fractional year); P09's
// controls only for P09 sessions.
const { test, before, after } = require('node:test');
const assert = require('node:assert/strict');
const path = require('node:path');
const { openPage } = require('../support/chromium.js');
const { startDaemon, api } = require('../support/daemon.js');

let d, browser, page;
const errors = [];
const edits = [];
const snapshots = [];
const shot = (name) => page.screenshot({ path: path.join(process.env.MER_ARTIFACTS, name) });
const summary = () => page.evaluate(() => window.meristem.summary);
const idle = () => page.evaluate(() => window.meristem.idle());
const visible = (sel) => page.isVisible(sel);

before(async () => {
  d = await startDaemon(['--quiet']);
  ({ browser, page } = await openPage());
  page.on('pageerror', (e) => errors.push(String(e)));
  page.on('request', (r) => {
    if (r.method() === 'POST' && /\/edits$/.test(r.url())) edits.push(JSON.parse(r.postData()));
    if (r.url().includes('/snapshot.glb')) snapshots.push(r.url());
  });
  await page.goto(`${d.url}/`, { timeout: 120000 });   // a loaded machine is slow to start Chromium's first page
  await page.waitForFunction(() => window.meristem?.ready, null, { timeout: 30000 });
});
after(async () => { await browser?.close(); await d?.stop(); });

async function newTree(model, preset, seed = 1) {
  await page.selectOption('#model', model);
  await page.selectOption('#preset', preset);
  await page.fill('#seed', String(seed));
  await page.click('#new-session');
  await page.waitForFunction((p) => window.meristem.summary?.preset === p, preset, { timeout: 20000 });
  await idle();
}

test('P09 first: its schedule, brush and parameters; no model panel of another', async () => {
  assert.equal(await page.inputValue('#model'), 'p09');
  await newTree('p09', 'fig15-brushed');
  assert.ok(await visible('#schedule-panel'));
  assert.ok(await visible('[data-tool="brush"]'));
  assert.ok(await visible('#param-lambda'));
  for (const sel of ['#lsystem-panel', '#inverse-panel', '#time-panel']) assert.ok(!(await visible(sel)), sel);
  for (const sel of ['#stat-buds', '#stat-markers']) assert.ok(await visible(sel), sel);
});

test('an L-system from the page: its source, an error at its line, derive steps the summary', async () => {
  await page.selectOption('#model', 'lsystem');
  const offered = await page.$$eval('#preset option', (os) => os.map((o) => o.value));
  const listed = await page.evaluate(async () => (await (await fetch('/v1/presets')).json()).presets);
  const lsystems = listed.filter((p) => p.model === 'lsystem').map((p) => p.name);
  assert.ok(offered.includes('abop-2.6a'), offered.join(' '));
  assert.deepEqual([...offered].sort(), [...lsystems].sort());
  await newTree('lsystem', 'abop-2.6a');
  const s0 = await summary();
  assert.equal(s0.model, 'lsystem');
  // P09's controls are not an L-system's; the shared tools stay.
  for (const sel of ['#schedule-panel', '[data-tool="brush"]', '#brush-panel', '#param-lambda', '#inverse-panel']) {
    assert.ok(!(await visible(sel)), `${sel} hidden`);
  }
  for (const sel of ['#lsystem-panel', '[data-tool="prune"]', '[data-tool="bend"]', '#view-panel', '#param-ls_delta']) {
    assert.ok(await visible(sel), `${sel} shown`);
  }
  // The Growth panel's figures: no buds or markers, which an L-system has not.
  assert.deepEqual(await page.$$eval('#stats dt', (ts) => ts.filter((t) => !t.hidden).map((t) => t.textContent)),
    ['step', 'internodes', 'height', 'revision', 'snapshot']);
  const source = await page.inputValue('#ls-source');
  assert.match(source, /axiom:/);
  assert.equal(await page.$$eval('#ls-gutter span', (s) => s.length), source.split('\n').length);

  // Derive: the summary's derivation step and string length change, and the panel shows them.
  await page.click('#ls-derive');
  await page.waitForFunction(() => window.meristem.summary?.lsystem?.derivation_step === 1);
  await idle();
  const s1 = await summary();
  assert.ok(s1.lsystem.string_length > s0.lsystem.string_length, JSON.stringify(s1.lsystem));
  assert.match(await page.textContent('#ls-step'), /^1 \/ \d+/);
  assert.equal(await page.textContent('#ls-length'), s1.lsystem.string_length.toLocaleString('en-US'));
  assert.ok(await page.$$eval('#ls-modules tr', (r) => r.length) > 0);
  await page.click('#ls-derive');
  await page.click('#ls-derive');
  await page.waitForFunction(() => window.meristem.summary?.lsystem?.derivation_step === 3);
  await idle();
  await shot('models-lsystem.png');

  // A syntax error on line 3: shown there, in the gutter and below the editor; nothing changes.
  const lines = source.split('\n');
  const at = lines.findIndex((l) => /->/.test(l));
  lines[at] = lines[at].replace(/\)\s*$/, '*)');
  const broken = lines.join('\n');
  await page.fill('#ls-source', broken);
  const before = await summary();
  await page.click('#ls-apply');
  await page.waitForSelector('#ls-error:not([hidden])');
  const problem = await page.evaluate(() => window.meristem.state.lastProblem);
  assert.equal(problem.line, at + 1, JSON.stringify(problem));
  assert.match(await page.textContent('#ls-error'), new RegExp(`^line ${at + 1}, column \\d+`));
  assert.deepEqual(await page.$$eval('#ls-gutter span.error', (s) => s.map((x) => x.textContent)), [String(at + 1)]);
  assert.ok(await visible('#ls-mark'));
  assert.equal((await summary()).revision, before.revision);
  await shot('models-lsystem-error.png');

  // Fixed and applied: the error goes; the session's source is the new one.
  const wider = source.replace(/#define a0 45/, '#define a0 60');
  await page.fill('#ls-source', wider);
  await page.click('#ls-apply');
  await page.waitForSelector('#ls-error', { state: 'hidden' });
  const id = await page.evaluate(() => window.meristem.sessionId);
  assert.equal((await api(d.url, 'GET', `/v1/sessions/${id}/lsystem`)).body.source, wider);
});

test('an inverse tree: a dragged control point regrows it; the time slider draws a fractional year', async () => {
  await newTree('inverse', 'populus-deltoides', 5);
  for (const sel of ['#schedule-panel', '[data-tool="brush"]', '#lsystem-panel', '#params-panel']) {
    assert.ok(!(await visible(sel)), `${sel} hidden`);
  }
  // Its buds (the year's growing tips) shown, no markers: it has no environment.
  assert.ok(await visible('#stat-buds'));
  assert.ok(!(await visible('#stat-markers')) && !(await visible('#stats dt:nth-of-type(4)')));
  await page.fill('#step-count', '8');
  await page.click('#step-n');
  await page.waitForFunction(() => window.meristem.summary?.inverse?.year === 8, null, { timeout: 30000 });
  await idle();
  await page.waitForFunction(() => document.querySelectorAll('#inv-functions .fn').length === 14);
  const names = await page.$$eval('#inv-functions .fn', (fs) => fs.map((f) => f.dataset.name));
  assert.ok(names.includes('G_s2') && names.includes('G_h'), names.join(' '));
  assert.match(await page.textContent('.fn[data-name="G_s2"] figcaption'), /mature silhouette/);

  // Drag G_h's second point up: one set_functions edit (or a few), and the tree regrows.
  const s0 = await summary();
  const sent = edits.length;
  await page.locator('.fn[data-name="G_h"]').scrollIntoViewIfNeeded();
  const dot = await page.locator('.fn[data-name="G_h"] .point[data-index="1"] .dot').boundingBox();
  const from = { x: dot.x + dot.width / 2, y: dot.y + dot.height / 2 };
  await page.mouse.move(from.x, from.y);
  await page.mouse.down();
  for (let i = 1; i <= 6; i++) await page.mouse.move(from.x, from.y - 4 * i);
  await page.mouse.up();
  await page.waitForFunction((r) => window.meristem.summary.revision > r, s0.revision);
  await idle();
  const s1 = await summary();
  const fnEdits = edits.slice(sent).flatMap((b) => b.edits || [b]).filter((e) => e.op === 'set_functions');
  assert.ok(fnEdits.length >= 1, 'set_functions sent');
  assert.match(fnEdits.at(-1).fset, /name: G_h\n/);
  assert.notEqual(s1.hash, s0.hash, 'the tree regrew');
  assert.ok(s1.height > s0.height, `a taller trunk: ${s0.height} → ${s1.height}`);
  const id = await page.evaluate(() => window.meristem.sessionId);
  const served = (await api(d.url, 'GET', `/v1/sessions/${id}/functions?format=json`)).body.functions;
  const gh = served.find((f) => f.name === 'G_h');
  const shown = await page.evaluate(() => window.meristem.panels.inverse.cards.find((c) => c.f.name === 'G_h').f.points);
  assert.ok(Math.abs(gh.points[1][1] - shown[1][1]) < 1e-4, 'the served function is the one drawn');
  await shot('models-inverse.png');

  // The time slider: a fractional year, drawn without changing the session.
  const loads = await page.evaluate(() => window.meristem.session.state.loads);
  const drawn = await page.evaluate(() => window.meristem.lastLoad.drawnAt);
  await page.locator('#time-slider').fill('3.25');
  await page.waitForFunction((t) => window.meristem.lastLoad.drawnAt > t, drawn, { timeout: 20000 });
  assert.ok(snapshots.some((u) => new URL(u).searchParams.get('t') === '3.25'), snapshots.slice(-3).join('\n'));
  assert.match(await page.textContent('#time-at'), /year 3\.25 of 8/);
  assert.equal((await summary()).revision, s1.revision);
  assert.equal(await page.evaluate(() => window.meristem.session.state.loads), loads, 'not the session\'s own tree');
  await shot('models-inverse-time.png');
  // Back to the latest year: the session's tree again.
  await page.locator('#time-slider').fill('8');
  await page.waitForFunction((n) => window.meristem.session.state.loads > n, loads, { timeout: 20000 });
  assert.match(await page.textContent('#time-at'), /^year 8$/);

  // .fset out and in: the download is the session's text; an upload replaces G_h and the
  // panel draws the new curve.
  const href = await page.getAttribute('#inv-download', 'href');
  assert.equal(href, `v1/sessions/${id}/functions`);
  const r = await page.evaluate(() => window.meristem.summary.revision);
  await page.setInputFiles('#inv-upload', { name: 'early.fset', mimeType: 'text/plain', buffer: Buffer.from(
    'funcgalleryver 1 1\nitems: 1\nfver 1 1\nname: G_h\nsamples: 64\nflip: off\npoints: 4\n0 0.05\n0.2 0.7\n0.5 1\n1 1\n') });
  await page.waitForFunction((n) => window.meristem.summary.revision > n, r);
  await page.waitForFunction(() => window.meristem.panels.inverse.cards
    .find((c) => c.f.name === 'G_h')?.f.points.map((p) => Math.abs(p[0] - 0.2) < 1e-6)[1], null, { timeout: 20000 });
});

test('a stale fractional year is cancelled: the last one asked for is drawn', async () => {
  const time = await page.evaluate(async () => {
    const p = window.meristem.panels.time;
    const asked = p.requested.length;
    const a = p.scrub(1.5);
    p.scrub(2.5);
    p.scrub(4.75);
    p.settle();   // let go at 4.75
    await a;
    return { asked: p.requested.slice(asked), url: window.meristem.viewer.url };
  });
  assert.equal(time.asked[0], 1.5);
  assert.equal(time.asked.at(-1), 4.75);
  assert.ok(!time.asked.includes(2.5), 'a year the slider passed is never asked for');
  assert.equal(new URL(time.url, d.url).searchParams.get('t'), '4.75');
});

test('runions: its parameters and the brush, no P09 schedule; no page errors', async () => {
  await newTree('runions', 'runions-2007');
  assert.ok(!(await visible('#schedule-panel')));
  assert.ok(await visible('[data-tool="brush"]'));
  assert.ok(await visible('#param-d_k'));
  assert.ok(!(await visible('#param-lambda')));
  assert.deepEqual(errors, []);
});

test('guiding: its parameters, no brush and no P09 schedule; no page errors', async () => {
  await newTree('guiding', 'gv-shrub');
  assert.ok(!(await visible('#schedule-panel')));
  assert.ok(!(await visible('[data-tool="brush"]')));
  assert.ok(await visible('#param-gv_rotation'));
  assert.ok(await visible('#param-gv_endpoints'));
  assert.ok(!(await visible('#param-d_k')));
  assert.ok(!(await visible('#param-lambda')));
  assert.deepEqual(errors, []);
});
