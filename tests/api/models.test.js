'use strict';
// Growth models chosen by name over HTTP: POST /v1/sessions {"model": ...} runs
// the model (mer_model_parse), /v1/presets lists its presets and parameters with
// the model that reads them, and a session's summary lists only the parameters
// its model reads (and Perlin noise's only while it is on).
const { test, before, after } = require('node:test');
const assert = require('node:assert/strict');
const fs = require('node:fs');
const path = require('node:path');
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
