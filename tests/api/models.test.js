'use strict';
// Growth models chosen by name over HTTP: POST /v1/sessions {"model": ...} runs
// the model (mer_model_parse), /v1/presets lists its presets and parameters with
// the model that reads them, and a session's summary lists only the parameters
// its model reads (and Perlin noise's only while it is on).
const { test, before, after } = require('node:test');
const assert = require('node:assert/strict');
const fs = require('node:fs');
const path = require('node:path');
const { validates } = require('../support/gltf.js');
const { startDaemon, api } = require('../support/daemon.js');

let d;
const J = (method, p, body) => api(d.url, method, p, body);
const artifact = (name, bytes) => fs.writeFileSync(path.join(process.env.MER_ARTIFACTS, name), bytes);

before(async () => { d = await startDaemon(['--max-markers', '30000']); });
after(() => d.stop());

test('/v1/presets lists the runions model, its preset and its parameters', async () => {
  const r = await J('GET', '/v1/presets');
  assert.equal(r.status, 200);
  const preset = r.body.presets.find((p) => p.name === 'runions-2007');
  assert.ok(preset, 'runions-2007 listed');
  assert.equal(preset.model, 'runions');
  assert.equal(preset.params.d_i, 6);
  assert.equal(preset.params.d_k, 2);
  assert.equal(preset.params.D, 1);
  assert.equal(preset.params.lambda, undefined, 'no P09 rows in a runions preset');
  const p09 = r.body.presets.find((p) => p.name === 'fig4-colonization');
  assert.equal(p09.model, 'p09');
  assert.equal(p09.params.d_i, undefined, 'no runions rows in a P09 preset');
  const rows = Object.fromEntries(r.body.parameters.map((f) => [f.name, f]));
  for (const name of ['d_i', 'd_k', 'D']) {
    assert.equal(rows[name].model, 'runions');
    assert.equal(rows[name].symbol, name);
  }
  assert.equal(rows.lambda.model, 'p09');
  assert.equal(rows.marker_count.model, '');
});

test('POST /v1/sessions {"model": "runions"} grows by space colonization', async () => {
  const c = await J('POST', '/v1/sessions', { model: 'runions', params: { environment: 1, d_i: 7 }, seed: 3 });
  assert.equal(c.status, 201, JSON.stringify(c.body));
  const id = c.body.id;
  assert.equal(c.body.params.d_i, 7);
  assert.equal(c.body.params.xi, undefined);
  const e = await J('POST', `/v1/sessions/${id}/edits`, { op: 'step', count: 8 });
  assert.equal(e.status, 200, JSON.stringify(e.body));
  const s = await J('GET', `/v1/sessions/${id}`);
  assert.ok(s.body.internodes > 20, `grew ${s.body.internodes}`);
  assert.ok(s.body.markers < 20000);
  const g = await J('GET', `/v1/sessions/${id}/snapshot.glb`);
  assert.equal(g.status, 200);
  artifact('runions-model.glb', g.raw);
  await J('DELETE', `/v1/sessions/${id}`);
});

test('the preset runs its model; the model refuses what it cannot grow with', async () => {
  const c = await J('POST', '/v1/sessions', { preset: 'runions-2007' });
  assert.equal(c.status, 201, JSON.stringify(c.body));
  assert.equal(c.body.params.D, 1);
  await J('DELETE', `/v1/sessions/${c.body.id}`);
  const shade = await J('POST', '/v1/sessions', { model: 'runions' });
  assert.equal(shade.status, 422);
  assert.equal(shade.body.field, 'params.environment');
  assert.match(shade.body.detail, /runions-2007/);
  const bad = await J('POST', '/v1/sessions', { model: 'runions', params: { environment: 1, d_k: 9 } });
  assert.equal(bad.status, 422);
  assert.equal(bad.body.field, 'params.d_k');
  const unknown = await J('POST', '/v1/sessions', { model: 'nope' });
  assert.equal(unknown.status, 422);
  assert.match(unknown.body.detail, /p09, runions/);
});

test('Perlin noise: its parameters are listed while it is on, and it changes the tree', async () => {
  const plain = await J('POST', '/v1/sessions', { seed: 5 });
  assert.equal(plain.body.params.noise_amplitude, undefined);
  const noisy = await J('POST', '/v1/sessions', { seed: 5, params: { noise_amplitude: 0.5, noise_octaves: 4 } });
  assert.equal(noisy.status, 201, JSON.stringify(noisy.body));
  assert.equal(noisy.body.params.noise_amplitude, 0.5);
  assert.equal(noisy.body.params.noise_octaves, 4);
  assert.equal(noisy.body.params.noise_targets, 7);
  const hashes = [];
  for (const s of [plain, noisy]) {
    hashes.push((await J('POST', `/v1/sessions/${s.body.id}/edits`, { op: 'step', count: 6 })).body.hash);
  }
  assert.notEqual(hashes[0], hashes[1]);
  const g = await J('GET', `/v1/sessions/${noisy.body.id}/snapshot.glb`);
  assert.equal(g.status, 200);
  artifact('noise-model.glb', g.raw);
  const p = await J('GET', '/v1/presets');
  const row = p.body.parameters.find((f) => f.name === 'noise_amplitude');
  assert.deepEqual([row.model, row.min, row.max, row.default], ['', 0, 2, 0]);
});

test('guiding-vector trees: presets, one iteration a step, a GLB that validates', async () => {
  const r = await J('GET', '/v1/presets');
  const names = r.body.presets.filter((p) => p.model === 'guiding').map((p) => p.name);
  for (const n of ['gv-fig2-small-2', 'gv-fig2-large-5', 'gv-fig3-sphere', 'gv-fig4-1000', 'gv-fig4-2000', 'gv-fig4-4000']) {
    assert.ok(names.includes(n), `${n} listed`);
  }
  const rows = Object.fromEntries(r.body.parameters.map((f) => [f.name, f]));
  for (const name of ['gv_density', 'gv_cones', 'gv_rotation', 'gv_k_hops', 'gv_t', 'gv_epsilon', 'gv_p']) {
    assert.equal(rows[name].model, 'guiding', name);
  }
  assert.equal(rows.gv_epsilon.symbol, 'ε');

  const c = await J('POST', '/v1/sessions', { preset: 'gv-fig3-sphere', seed: 4 });
  assert.equal(c.status, 201, JSON.stringify(c.body));
  const id = c.body.id;
  assert.equal(c.body.model, 'guiding');
  assert.equal(c.body.params.gv_bound, 1);
  assert.equal(c.body.params.lambda, undefined, 'no P09 rows in a guiding session');
  const one = await J('POST', `/v1/sessions/${id}/edits`, { op: 'step' });
  assert.equal(one.status, 200, JSON.stringify(one.body));
  assert.equal(one.body.guiding.iteration, 1);
  assert.ok(one.body.guiding.graph_nodes > 1000);
  const trunk = one.body.internodes;
  const more = await J('POST', `/v1/sessions/${id}/edits`, { op: 'step', count: 3 });
  assert.equal(more.body.guiding.iteration, 4);
  assert.ok(more.body.internodes > trunk * 5, `${trunk} then ${more.body.internodes}`);
  const pruned = await J('POST', `/v1/sessions/${id}/edits`, { op: 'prune', node: 3 });
  assert.equal(pruned.status, 200, JSON.stringify(pruned.body));
  const g = await J('GET', `/v1/sessions/${id}/snapshot.glb`);
  assert.equal(g.status, 200);
  artifact('guiding-model.glb', g.raw);
  await validates(g.raw);
  await J('DELETE', `/v1/sessions/${id}`);
});

test('guiding-vector parameters out of range are problems naming the field', async () => {
  // Out of a row's range is 422; a graph too large for the limits is 409 (as any limit).
  for (const [params, field, status] of [[{ gv_epsilon: 0 }, 'params.gv_epsilon', 422],
    [{ gv_cones: 100 }, 'params.gv_cones', 422], [{ gv_t: 0 }, 'params.gv_t', 422],
    [{ gv_density: 900 }, 'params.gv_density', 409], [{ marker_volume: 0 }, 'params.marker_volume', 422]]) {
    const bad = await J('POST', '/v1/sessions', { preset: 'gv-fig2-small-2', params });
    assert.equal(bad.status, status, JSON.stringify(params));
    assert.match(bad.headers.get('content-type'), /application\/problem\+json/);
    assert.equal(bad.body.field, field);
  }
});


test('a guiding tree is the same whatever the worker count', async () => {
  const grow = async (url) => {
    const c = await api(url, 'POST', '/v1/sessions', { preset: 'gv-shrub', seed: 9 });
    assert.equal(c.status, 201, JSON.stringify(c.body));
    const s = await api(url, 'POST', `/v1/sessions/${c.body.id}/edits`, { op: 'step', count: 3 });
    const g = await api(url, 'GET', `/v1/sessions/${c.body.id}/snapshot.glb?quantize=0`);
    await api(url, 'DELETE', `/v1/sessions/${c.body.id}`);
    return [s.body.hash, s.body.internodes, g.raw.length];
  };
  const one = await startDaemon(['--workers', '1', '--threads', '1']);
  const many = await startDaemon(['--workers', '4', '--threads', '4']);
  try {
    const [a, b, c] = await Promise.all([grow(one.url), grow(many.url), grow(d.url)]);
    assert.deepEqual(a, b);
    assert.deepEqual(a, c);
  } finally {
    await one.stop();
    await many.stop();
  }
});
