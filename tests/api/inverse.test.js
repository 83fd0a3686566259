'use strict';
// Inverse-model sessions (Galbraith et al. 2004) over HTTP: the Populus preset grown
// year by year, its functions replaced (an .fset that does not read is a 422 with
// line and column that changes nothing; a valid one regrows the tree), the
// functions downloaded and uploaded again, snapshots at a fractional year, and
// the session restored from its journal after kill -9 to the same GLB bytes.
const test = require('node:test');
const assert = require('node:assert/strict');
const fs = require('node:fs');
const os = require('node:os');
const path = require('node:path');
const http = require('node:http');
const { validates } = require('../support/gltf.js');
const { startDaemon, api, sessionState, assertRestored } = require('../support/daemon.js');

const artifact = (name, bytes) => fs.writeFileSync(path.join(process.env.MER_ARTIFACTS, name), bytes);

async function edit(base, id, body) {
  return api(base, 'POST', `/v1/sessions/${id}/edits`, body);
}

async function glbOf(base, id, query = '') {
  const r = await api(base, 'GET', `/v1/sessions/${id}/snapshot.glb${query}`);
  assert.equal(r.status, 200, JSON.stringify(r.body));
  return r.raw;
}

// GET as text, with its Content-Type.
function getText(base, p) {
  return new Promise((resolve, reject) => {
    http.get(`${base}${p}`, (res) => {
      const chunks = [];
      res.on('data', (c) => chunks.push(c));
      res.on('end', () => resolve({ status: res.statusCode, type: res.headers['content-type'],
        text: Buffer.concat(chunks).toString('utf8') }));
    }).on('error', reject);
  });
}

// A trunk that reaches its height in the first half of the tree's life.
const EARLY_TRUNK = `funcgalleryver 1 1
items: 1
fver 1 1
name: G_h
samples: 64
flip: off
points: 4
0 0.05
0.2 0.7
0.5 1
1 1
`;

test('an inverse session: the Populus over 27 years, functions replaced, fractional years, kill -9', async (t) => {
  const dataDir = fs.mkdtempSync(path.join(os.tmpdir(), 'meristem-inverse-'));
  t.after(() => fs.rmSync(dataDir, { recursive: true, force: true }));
  let d = await startDaemon([], { dataDir });
  t.after(() => d.stop());

  const presets = await api(d.url, 'GET', '/v1/presets');
  const names = JSON.stringify(presets.body);
  for (const n of ['populus-deltoides', 'inverse-conifer', 'inverse-weeping']) assert.ok(names.includes(n), n);

  const c = await api(d.url, 'POST', '/v1/sessions', { model: 'inverse', preset: 'populus-deltoides', seed: 5 });
  assert.equal(c.status, 201, JSON.stringify(c.body));
  const id = c.body.id;
  assert.equal(c.body.model, 'inverse');
  assert.equal(c.body.inverse.year, 0);
  assert.equal(c.body.inverse.y_max, 27);

  let r = await edit(d.url, id, { op: 'step', count: 12 });
  assert.equal(r.status, 200, JSON.stringify(r.body));
  assert.equal(r.body.inverse.year, 12);
  const young = r.body.inverse.branches.order1;
  assert.ok(young > 0, JSON.stringify(r.body.inverse));

  // Snapshots at a fractional year: between whole years, and the session unchanged.
  const at12 = await glbOf(d.url, id, '?t=12');
  const at1225 = await glbOf(d.url, id, '?t=12.25');
  const at13 = await glbOf(d.url, id, '?t=13');
  assert.ok(Buffer.compare(at1225, at12) !== 0, 't=12.25 is not year 12');
  assert.ok(Buffer.compare(at1225, at13) !== 0, 't=12.25 is not year 13');
  await validates(at1225);
  artifact('api-inverse-12.25.glb', at1225);
  const still = await api(d.url, 'GET', `/v1/sessions/${id}`);
  assert.equal(still.body.revision, r.body.revision);
  assert.equal(still.body.hash, r.body.hash);
  assert.equal(still.body.inverse.year, 12);
  // A bad t names it.
  const bad = await api(d.url, 'GET', `/v1/sessions/${id}/snapshot.glb?t=soon`);
  assert.equal(bad.status, 400);
  assert.equal(bad.body.field, 't');
  const late = await api(d.url, 'GET', `/v1/sessions/${id}/snapshot.glb?t=40`);
  assert.equal(late.status, 400);
  assert.equal(late.body.field, 't');

  r = await edit(d.url, id, { op: 'step', count: 15 });
  assert.equal(r.status, 200, JSON.stringify(r.body));
  assert.equal(r.body.inverse.year, 27);
  r = await edit(d.url, id, { op: 'step' });
  assert.equal(r.status, 409, 'past y_max');

  // The functions as .fset text.
  const fn = await getText(d.url, `/v1/sessions/${id}/functions`);
  assert.equal(fn.status, 200);
  assert.match(fn.type, /^text\/plain/);
  assert.match(fn.text, /^funcgalleryver 1 1\nitems: 14\n/);
  assert.ok(fn.text.includes('name: G_s2'));
  const js = await api(d.url, 'GET', `/v1/sessions/${id}/functions?format=json`);
  assert.equal(js.status, 200);
  assert.equal(js.body.functions.length, 14);
  assert.ok(js.body.functions.some((f) => f.name === 'G_r'), 'the radius along a branch');
  const gh = js.body.functions.find((f) => f.name === 'G_h');
  assert.equal(gh.kind, 'bspline');
  assert.ok(gh.samples > 0 && gh.points.length >= 4, JSON.stringify(gh));
  for (const p of gh.points) assert.equal(p.length, 3);
  assert.equal(gh.points[0][0], 0);
  assert.equal(gh.points[gh.points.length - 1][0], 1);

  // An .fset that does not read: 422 at its line and column, nothing changes.
  const before = (await api(d.url, 'GET', `/v1/sessions/${id}`)).body;
  r = await edit(d.url, id, { op: 'set_functions', fset: EARLY_TRUNK.replace('0.2 0.7', '0.2 zero') });
  assert.equal(r.status, 422, JSON.stringify(r.body));
  assert.equal(r.body.field, 'fset', JSON.stringify(r.body));
  assert.equal(r.body.line, 9);
  assert.ok(Number.isInteger(r.body.column) && r.body.column > 0, JSON.stringify(r.body));
  let same = await api(d.url, 'GET', `/v1/sessions/${id}`);
  assert.equal(same.body.revision, before.revision);
  assert.equal(same.body.hash, before.hash);

  // A valid change: the tree regrows from it, the text shows it.
  const old = await glbOf(d.url, id);
  r = await edit(d.url, id, { op: 'set_functions', fset: EARLY_TRUNK });
  assert.equal(r.status, 200, JSON.stringify(r.body));
  assert.notEqual(r.body.hash, before.hash);
  const changed = await glbOf(d.url, id);
  assert.ok(Buffer.compare(changed, old) !== 0, 'the tree regrew');
  const fn2 = await getText(d.url, `/v1/sessions/${id}/functions`);
  assert.match(fn2.text, /\n0\.2\d* 0\.(7|69)\d*\n/);

  // Round trip: the downloaded functions, uploaded again, change nothing.
  const regrown = (await api(d.url, 'GET', `/v1/sessions/${id}`)).body;
  r = await edit(d.url, id, { op: 'set_functions', fset: fn2.text });
  assert.equal(r.status, 200, JSON.stringify(r.body));
  assert.deepEqual(r.body.inverse, regrown.inverse, 'the same tree after the round trip');
  assert.equal(r.body.internodes, regrown.internodes);
  assert.equal((await getText(d.url, `/v1/sessions/${id}/functions`)).text, fn2.text);

  // P09's and L-systems' edits are not this model's; nor is t another model's.
  r = await edit(d.url, id, { op: 'set_apical_schedule', apical_off: [3] });
  assert.equal(r.status, 422);
  const sk = await api(d.url, 'GET', `/v1/sessions/${id}/skeleton?alive=1`);
  const branch = sk.body.nodes.find((n) => n.order === 1);
  assert.ok(branch, 'a live branch to prune');
  r = await edit(d.url, id, { op: 'prune', node: branch.id });
  assert.equal(r.status, 200, JSON.stringify(r.body));

  const saved = await sessionState(d.url, id);
  await validates(saved.glb);
  artifact('api-inverse.glb', saved.glb);

  // kill -9, restart on the same folder: the journal replays to the same bytes.
  d = await d.restart();
  await assertRestored(d.url, id, saved, ['inverse']);
});

test('inverse sessions from an uploaded .fset; t and functions refused for other models', async (t) => {
  const d = await startDaemon();
  t.after(() => d.stop());
  const c = await api(d.url, 'POST', '/v1/sessions', { model: 'inverse', inverse: { fset: EARLY_TRUNK } });
  assert.equal(c.status, 201, JSON.stringify(c.body));
  let r = await edit(d.url, c.body.id, { op: 'step', count: 3 });
  assert.equal(r.status, 200, JSON.stringify(r.body));
  const fn = await getText(d.url, `/v1/sessions/${c.body.id}/functions`);
  assert.match(fn.text, /\n0\.2\d* 0\.(7|69)\d*\n/);
  // The functions as JSON, as GET functions?format=json gives them: the same change.
  const js = (await api(d.url, 'GET', `/v1/sessions/${c.body.id}/functions?format=json`)).body.functions;
  const gh = js.find((f) => f.name === 'G_h');
  gh.points = [[0, 0.05, 1], [0.3, 0.8, 1], [0.6, 1, 1], [1, 1, 1]];
  r = await edit(d.url, c.body.id, { op: 'set_functions', functions: [gh] });
  assert.equal(r.status, 200, JSON.stringify(r.body));
  const fnj = await getText(d.url, `/v1/sessions/${c.body.id}/functions`);
  assert.match(fnj.text, /\n0\.3\d* 0\.8\d*\n/);
  r = await edit(d.url, c.body.id, { op: 'set_functions', functions: [{ ...gh, points: [[0], [1, 1]] }] });
  assert.equal(r.status, 422, JSON.stringify(r.body));
  assert.equal(r.body.field, 'functions[0].points[0]');
  r = await edit(d.url, c.body.id, { op: 'set_functions', functions: [{ ...gh, name: 'G_zz' }] });
  assert.equal(r.status, 422, JSON.stringify(r.body));
  assert.equal(r.body.field, 'functions');
  r = await edit(d.url, c.body.id, { op: 'set_functions', functions: [gh], fset: EARLY_TRUNK });
  assert.equal(r.status, 422, JSON.stringify(r.body));
  const broken = await api(d.url, 'POST', '/v1/sessions', { model: 'inverse', inverse: { fset: 'funcgalleryver 1 1\nitems: x\n' } });
  assert.equal(broken.status, 422, JSON.stringify(broken.body));
  assert.equal(broken.body.line, 2);

  const p = await api(d.url, 'POST', '/v1/sessions', { seed: 1 });
  r = await edit(d.url, p.body.id, { op: 'step', count: 2 });
  const refused = await api(d.url, 'GET', `/v1/sessions/${p.body.id}/snapshot.glb?t=1.5`);
  assert.equal(refused.status, 400);
  assert.equal(refused.body.field, 't');
  const none = await api(d.url, 'GET', `/v1/sessions/${p.body.id}/functions`);
  assert.equal(none.status, 422);
  r = await edit(d.url, p.body.id, { op: 'set_functions', fset: EARLY_TRUNK });
  assert.equal(r.status, 422);
  const wrong = await api(d.url, 'POST', '/v1/sessions', { inverse: { fset: EARLY_TRUNK } });
  assert.equal(wrong.status, 422);

  for (const preset of ['inverse-conifer', 'inverse-weeping']) {
    const s = await api(d.url, 'POST', '/v1/sessions', { preset, seed: 2 });
    assert.equal(s.status, 201, JSON.stringify(s.body));
    assert.equal(s.body.model, 'inverse');
    r = await edit(d.url, s.body.id, { op: 'step', count: 10 });
    assert.equal(r.status, 200, JSON.stringify(r.body));
    const g = await glbOf(d.url, s.body.id, '?t=9.5');
    await validates(g);
  }
});

// One function as .fset text: the line from (0, y0) to (1, y1).
const lineFset = (name, y0, y1) => `funcgalleryver 1 1
items: 1
fver 1 1
name: ${name}
samples: 64
flip: off
kind: linear
points: 2
0 ${y0}
1 ${y1}
`;

const dirOf = (n) => {
  const v = n.tip.map((x, k) => x - n.base[k]);
  const l = Math.hypot(...v);
  return v.map((x) => x / l);
};

test('inverse: a bend outlives set_functions, a prune of a node the new functions lack is dropped, the journal replays', async (t) => {
  const dataDir = fs.mkdtempSync(path.join(os.tmpdir(), 'meristem-inverse-edits-'));
  t.after(() => fs.rmSync(dataDir, { recursive: true, force: true }));
  let d = await startDaemon([], { dataDir });
  t.after(() => d.stop());
  const make = async () => {
    const c = await api(d.url, 'POST', '/v1/sessions', { model: 'inverse', preset: 'populus-deltoides', seed: 3 });
    assert.equal(c.status, 201, JSON.stringify(c.body));
    const r = await edit(d.url, c.body.id, { op: 'step', count: 10 });
    assert.equal(r.status, 200, JSON.stringify(r.body));
    return c.body.id;
  };
  const id = await make();
  const twin = await make();
  const nodes = (await api(d.url, 'GET', `/v1/sessions/${id}/skeleton?alive=1`)).body.nodes;
  const byId = new Map(nodes.map((n) => [n.id, n]));
  const size = new Map();
  for (const n of [...nodes].sort((a, b) => b.id - a.id)) {
    size.set(n.id, (size.get(n.id) || 0) + 1);
    if (n.parent !== null) size.set(n.parent, (size.get(n.parent) || 0) + size.get(n.id));
  }
  const bases = nodes.filter((n) => n.order === 1 && byId.get(n.parent).order === 0);
  const branch = bases.reduce((a, b) => (size.get(b.id) > size.get(a.id) ? b : a));

  const h = dirOf(branch); // bend it about h × up: its heading turns by the whole angle
  let r = await edit(d.url, id, { op: 'bend', node: branch.id, axis: [-h[2], 0, h[0]], angle: 30, spread: 1 });
  assert.equal(r.status, 200, JSON.stringify(r.body));
  assert.equal(r.body.inverse.edits.bends, 1);
  const silhouette = lineFset('G_s2', 0.55, 0.1);
  for (const s of [id, twin]) {
    r = await edit(d.url, s, { op: 'set_functions', fset: silhouette });
    assert.equal(r.status, 200, JSON.stringify(r.body));
  }
  assert.equal(r.body.inverse.edits.bends, 0, 'the twin has none');
  const after = (await api(d.url, 'GET', `/v1/sessions/${id}`)).body;
  assert.equal(after.inverse.edits.bends, 1);
  assert.equal(after.inverse.edits.dropped, 0);
  const bent = (await api(d.url, 'GET', `/v1/sessions/${id}/skeleton?alive=1`)).body.nodes.find((n) => n.id === branch.id);
  const plain = (await api(d.url, 'GET', `/v1/sessions/${twin}/skeleton?alive=1`)).body.nodes.find((n) => n.id === branch.id);
  assert.ok(bent && plain, 'the branch keeps its id through the regrowth');
  const a = dirOf(bent), b = dirOf(plain);
  const angle = Math.acos(Math.min(1, a[0] * b[0] + a[1] * b[1] + a[2] * b[2])) * 180 / Math.PI;
  assert.ok(Math.abs(angle - 30) < 1, `the bend is still there: ${angle}°`);

  // A prune of a metamer past the first of its shoot; with one metamer a shoot
  // (G_m = 0) it no longer exists: the regrowth drops the prune and says so.
  const again = (await api(d.url, 'GET', `/v1/sessions/${id}/skeleton?alive=1`)).body.nodes;
  const at = new Map(again.map((n) => [n.id, n]));
  const inner = again.find((n) => n.order === 1 && n.parent !== null && at.get(n.parent).order === 1 &&
    at.get(n.parent).age === n.age && n.id !== branch.id);
  assert.ok(inner, 'a metamer inside a shoot');
  r = await edit(d.url, id, { op: 'prune', node: inner.id });
  assert.equal(r.status, 200, JSON.stringify(r.body));
  assert.equal(r.body.inverse.edits.prunes, 1);
  r = await edit(d.url, id, { op: 'set_functions', fset: lineFset('G_m', 0, 0) });
  assert.equal(r.status, 200, JSON.stringify(r.body));
  assert.equal(r.body.inverse.edits.prunes, 0);
  assert.ok(r.body.inverse.edits.dropped >= 1, JSON.stringify(r.body.inverse));
  r = await edit(d.url, id, { op: 'step', count: 2 });
  assert.equal(r.status, 200, JSON.stringify(r.body));

  const saved = await sessionState(d.url, id, '?leaves=1');
  await validates(saved.glb);
  d = await d.restart();
  await assertRestored(d.url, id, saved, ['inverse'], 'after replay');
});
