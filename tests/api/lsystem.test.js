'use strict';
// L-system sessions over HTTP: created from a cpfg source or a preset, stepped one
// derivation at a time, their source replaced (a parse error is a 422 with line
// and column that changes nothing), pruned and bent, and restored from their
// journal after kill -9 to the same GLB bytes; every GLB validates.
const test = require('node:test');
const assert = require('node:assert/strict');
const fs = require('node:fs');
const os = require('node:os');
const path = require('node:path');
const { validates } = require('../support/gltf.js');
const { startDaemon, api, sessionState, assertRestored } = require('../support/daemon.js');

const artifact = (name, bytes) => fs.writeFileSync(path.join(process.env.MER_ARTIFACTS, name), bytes);

// ABOP Fig. 2.6a, Honda's monopodial tree: 2^n - 1 segments after n steps.
const HONDA = `#define r1 0.9
#define r2 0.6
#define a0 45
#define a2 45
#define d 137.5
#define wr 0.707
derivation length: 10
axiom: A(1,10)
A(l,w) : * -> !(w)F(l)[&(a0)B(l*r2,w*wr)]/(d)A(l*r1,w*wr)
B(l,w) : * -> !(w)F(l)[-(a2)$C(l*r2,w*wr)]C(l*r1,w*wr)
C(l,w) : * -> !(w)F(l)[+(a2)$B(l*r2,w*wr)]B(l*r1,w*wr)
`;

async function edit(base, id, body) {
  return api(base, 'POST', `/v1/sessions/${id}/edits`, body);
}

async function glbOf(base, id) {
  const r = await api(base, 'GET', `/v1/sessions/${id}/snapshot.glb`);
  assert.equal(r.status, 200);
  return r.raw;
}

test('an L-system session: create, step, a refused source, prune, bend; restored after kill -9', async (t) => {
  const dataDir = fs.mkdtempSync(path.join(os.tmpdir(), 'meristem-lsystem-'));
  t.after(() => fs.rmSync(dataDir, { recursive: true, force: true }));
  let d = await startDaemon([], { dataDir });
  t.after(() => d.stop());

  const c = await api(d.url, 'POST', '/v1/sessions',
    { model: 'lsystem', seed: 3, lsystem: { source: HONDA }, params: { ls_width_scale: 0.01 } });
  assert.equal(c.status, 201, JSON.stringify(c.body));
  const id = c.body.id;
  assert.equal(c.body.model, 'lsystem');
  assert.deepEqual(c.body.lsystem, { derivation_step: 0, derivation_length: 10, string_length: 1, segments: 0,
    modules: { A: 1 } });
  assert.equal(c.body.params.ls_width_scale, 0.01);
  assert.equal(c.body.params.lambda, undefined, 'P09 rows are not an L-system\'s');

  let r = await edit(d.url, id, { op: 'step', count: 4 });
  assert.equal(r.status, 200, JSON.stringify(r.body));
  assert.equal(r.body.lsystem.derivation_step, 4);
  assert.equal(r.body.lsystem.segments, 15);
  assert.equal(r.body.lsystem.modules.F, 15);
  assert.equal(r.body.internodes, 15);

  // A source that does not parse: 422 at its line and column, nothing changes.
  const before = r.body;
  r = await edit(d.url, id, { op: 'set_lsystem', source: 'axiom: A(1,10)\nA(l,w) -> F(l*)[+(45)A(l,w)]\n' });
  assert.equal(r.status, 422, JSON.stringify(r.body));
  assert.equal(r.body.type, 'urn:meristem:problem:invalid-field');
  assert.equal(r.body.field, 'source');
  assert.equal(r.body.line, 2);
  assert.ok(Number.isInteger(r.body.column) && r.body.column > 0, JSON.stringify(r.body));
  const same = await api(d.url, 'GET', `/v1/sessions/${id}`);
  assert.equal(same.body.revision, before.revision);
  assert.equal(same.body.hash, before.hash);
  // In a batch the field names the edit.
  r = await edit(d.url, id, { edits: [{ op: 'step' }, { op: 'set_lsystem', source: 'A -> F(' }] });
  assert.equal(r.status, 422);
  assert.equal(r.body.field, 'edits[1].source');
  assert.equal(r.body.line, 1);

  // Prune the first branch (node 1, 7 segments now): it stays pruned as the tree grows.
  r = await edit(d.url, id, { op: 'prune', node: 1 });
  assert.equal(r.status, 200, JSON.stringify(r.body));
  r = await edit(d.url, id, { op: 'bend', node: 0, axis: [0, 0, 1], angle: 20 });
  assert.equal(r.status, 200, JSON.stringify(r.body));
  r = await edit(d.url, id, { op: 'step' });
  assert.equal(r.body.lsystem.segments, 31 - 15);
  // New productions from the next step on, the string kept.
  r = await edit(d.url, id, { op: 'set_lsystem', source: HONDA.replace('#define r2 0.6', '#define r2 0.8') });
  assert.equal(r.status, 200, JSON.stringify(r.body));
  assert.equal(r.body.lsystem.derivation_step, 5);
  r = await edit(d.url, id, { op: 'step', count: 2 });
  assert.equal(r.body.lsystem.derivation_step, 7);
  // P09's schedule is not an L-system's.
  r = await edit(d.url, id, { op: 'set_apical_schedule', apical_off: [3] });
  assert.equal(r.status, 422);

  const skeleton = await api(d.url, 'GET', `/v1/sessions/${id}/skeleton`);
  assert.equal(skeleton.status, 200);
  const saved = await sessionState(d.url, id);
  artifact('api-lsystem.glb', saved.glb);
  await validates(saved.glb);

  // kill -9, restart on the same folder: the journal replays to the same bytes.
  d = await d.restart();
  await assertRestored(d.url, id, saved, ['lsystem']);
  const s2 = await api(d.url, 'GET', `/v1/sessions/${id}/skeleton`);
  assert.deepEqual(s2.body, skeleton.body);
});

// cpfg's tier 2: a decomposition into whorls, a homomorphism that draws the
// internodes I, ?P bounding the height and ?E asking the environment (a box).
const TIER2 = `derivation length: 12
axiom: A?P(0,0,0)?E(0,0)
A > ?P(x,y,z) ?E(q,o) : y < 6 && o == 0 -> I(0.5)W/(137.5)A
decomposition
maximum depth: 2
W -> [&(40)V][^(40)V]
V -> I(0.3)[+(30)I(0.2)]
homomorphism
I(l) -> F(l)
endlsystem
`;

test('cpfg tier 2: decomposition, homomorphism, ?P and ?E; restored from the journal byte for byte', async (t) => {
  const dataDir = fs.mkdtempSync(path.join(os.tmpdir(), 'meristem-lsystem2-'));
  t.after(() => fs.rmSync(dataDir, { recursive: true, force: true }));
  let d = await startDaemon([], { dataDir });
  t.after(() => d.stop());
  const c = await api(d.url, 'POST', '/v1/sessions', { model: 'lsystem', seed: 2, lsystem: { source: TIER2 },
    scene: { obstacles: [{ box: { min: [-3, 4.2, -3], max: [3, 5, 3] } }] } });
  assert.equal(c.status, 201, JSON.stringify(c.body));
  const id = c.body.id;
  let r = await edit(d.url, id, { op: 'step', count: 3 });
  assert.equal(r.status, 200, JSON.stringify(r.body));
  // Three steps: 3 I on the axis and 3 whorls of 2 x (I [I]) decomposed into the string;
  // the homomorphism draws every I as an F, and the string holds none.
  assert.equal(r.body.lsystem.modules.I, 3 + 3 * 4);
  assert.equal(r.body.lsystem.modules.F, undefined);
  assert.equal(r.body.lsystem.segments, 15);
  // Node 2 is the first whorl's I(0.2): its module is cut from the string.
  r = await edit(d.url, id, { op: 'prune', node: 2 });
  assert.equal(r.status, 200, JSON.stringify(r.body));
  r = await edit(d.url, id, { op: 'step', count: 9 });
  // The apex grows 0.5 a step until ?E finds it inside the box (at y 4.5, after the 9th
  // step): 9 I on the axis, 9 whorls of 4 I, less the pruned one.
  assert.equal(r.body.lsystem.derivation_step, 12);
  assert.equal(r.body.lsystem.modules.A, 1);
  assert.equal(r.body.lsystem.modules.W, undefined);
  assert.equal(r.body.lsystem.modules.I, 9 + 9 * 4 - 1);
  assert.equal(r.body.lsystem.segments, 44);
  const saved = await sessionState(d.url, id);
  await validates(saved.glb);

  d = await d.restart();
  await assertRestored(d.url, id, saved, ['lsystem']);
});

test('L-system presets: listed with their model and source, and grown from their name', async (t) => {
  const d = await startDaemon();
  t.after(() => d.stop());
  const presets = (await api(d.url, 'GET', '/v1/presets')).body.presets;
  const byName = Object.fromEntries(presets.map((p) => [p.name, p]));
  for (const name of ['abop-1.2-algae', 'abop-1.24a', 'abop-1.24f', 'abop-1.27', 'abop-1.31a', 'abop-2.6a',
    'abop-2.7', 'abop-2.8a', 'lsystem-topiary']) {
    assert.equal(byName[name].model, 'lsystem', name);
    assert.match(byName[name].lsystem.source, /axiom:/, name);
  }
  assert.equal(byName.default.model, 'p09');
  assert.equal(byName.default.lsystem, undefined);

  const c = await api(d.url, 'POST', '/v1/sessions', { preset: 'abop-1.24a', seed: 1 });
  assert.equal(c.status, 201, JSON.stringify(c.body));
  assert.equal(c.body.model, 'lsystem');
  const r = await edit(d.url, c.body.id, { op: 'step', count: 9 });
  assert.equal(r.body.lsystem.derivation_step, 5, 'a step past the derivation length derives nothing');
  assert.equal(r.body.lsystem.segments, 3125);
  const glb = await glbOf(d.url, c.body.id);
  artifact('api-lsystem-1.24a.glb', glb);
  await validates(glb);

  // The same seed, the same stochastic plant; another seed, another.
  const hashes = [];
  for (const seed of [4, 4, 5]) {
    const s = await api(d.url, 'POST', '/v1/sessions', { preset: 'abop-1.27', seed });
    hashes.push((await edit(d.url, s.body.id, { op: 'step', count: 5 })).body.hash);
  }
  assert.equal(hashes[0], hashes[1]);
  assert.notEqual(hashes[0], hashes[2]);
});

test('unbalanced brackets are accepted, as cpfg does, with a warning saying where', async (t) => {
  const d = await startDaemon();
  t.after(() => d.stop());
  const c = await api(d.url, 'POST', '/v1/sessions', { model: 'lsystem', seed: 1, lsystem: { source: 'axiom: F\nF -> FF\n' } });
  assert.equal(c.status, 201, JSON.stringify(c.body));
  let r = await edit(d.url, c.body.id, { op: 'set_lsystem', source: 'axiom: F\nF -> F[+F\n' });
  assert.equal(r.status, 200, JSON.stringify(r.body));
  assert.equal(r.body.warnings.length, 1);
  assert.deepEqual({ ...r.body.warnings[0], message: undefined }, { field: 'source', line: 2, column: 7, message: undefined });
  assert.match(r.body.warnings[0].message, /never closed/);
  r = await edit(d.url, c.body.id, { edits: [{ op: 'step' }, { op: 'set_lsystem', source: 'axiom: F\nF -> F]F\n' }] });
  assert.equal(r.status, 200, JSON.stringify(r.body));
  assert.deepEqual(r.body.warnings.map((w) => [w.field, w.line, w.column]), [['edits[1].source', 2, 7]]);
  r = await edit(d.url, c.body.id, { op: 'set_lsystem', source: 'axiom: F\nF -> F[+F]\n' });
  assert.equal(r.status, 200);
  assert.equal(r.body.warnings, undefined, 'no warnings key when there is nothing to say');
  r = await edit(d.url, c.body.id, { op: 'step' });
  assert.equal(r.body.warnings, undefined, 'a later edit does not repeat them');
});

test('refusals: a source that does not parse, a missing source, set_lsystem on P09', async (t) => {
  const d = await startDaemon();
  t.after(() => d.stop());
  let r = await api(d.url, 'POST', '/v1/sessions', { model: 'lsystem', lsystem: { source: 'axiom: F\nF -> F(2*x)\n' } });
  assert.equal(r.status, 422, JSON.stringify(r.body));
  assert.equal(r.body.field, 'lsystem.source');
  assert.equal(r.body.line, 2);
  r = await api(d.url, 'POST', '/v1/sessions', { model: 'lsystem' });
  assert.equal(r.status, 422);
  assert.equal(r.body.field, 'lsystem.source');
  r = await api(d.url, 'POST', '/v1/sessions', { lsystem: { source: 'axiom: F' } });
  assert.equal(r.status, 422);
  assert.equal(r.body.field, 'lsystem');
  const p09 = await api(d.url, 'POST', '/v1/sessions', {});
  r = await edit(d.url, p09.body.id, { op: 'set_lsystem', source: 'axiom: F' });
  assert.equal(r.status, 422);
  assert.equal(p09.body.model, undefined, 'a P09 summary is as it was');
});

test('GET …/lsystem: the source a session derives with, after set_lsystem too; 422 for other models', async (t) => {
  const d = await startDaemon();
  t.after(() => d.stop());
  const c = await api(d.url, 'POST', '/v1/sessions', { model: 'lsystem', seed: 1, lsystem: { source: HONDA } });
  assert.equal(c.status, 201, JSON.stringify(c.body));
  let r = await api(d.url, 'GET', `/v1/sessions/${c.body.id}/lsystem`);
  assert.equal(r.status, 200, JSON.stringify(r.body));
  assert.deepEqual(r.body, { source: HONDA });
  const wider = HONDA.replace('#define a0 45', '#define a0 60');
  assert.equal((await edit(d.url, c.body.id, { op: 'set_lsystem', source: wider })).status, 200);
  assert.equal((await edit(d.url, c.body.id, { op: 'set_lsystem', source: 'axiom: F(' })).status, 422);
  r = await api(d.url, 'GET', `/v1/sessions/${c.body.id}/lsystem`);
  assert.deepEqual(r.body, { source: wider }, 'the accepted source, not the refused one');
  const preset = await api(d.url, 'POST', '/v1/sessions', { preset: 'abop-1.24a' });
  const listed = (await api(d.url, 'GET', '/v1/presets')).body.presets.find((p) => p.name === 'abop-1.24a');
  r = await api(d.url, 'GET', `/v1/sessions/${preset.body.id}/lsystem`);
  assert.equal(r.body.source, listed.lsystem.source);
  const p09 = await api(d.url, 'POST', '/v1/sessions', { seed: 1 });
  r = await api(d.url, 'GET', `/v1/sessions/${p09.body.id}/lsystem`);
  assert.equal(r.status, 422);
  assert.equal(r.body.field, 'model');
});
