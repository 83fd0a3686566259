'use strict';
// Sown forests over HTTP (scene.sow): plants of several presets and models placed
// by Poisson-disk sampling in one session, each in its Voronoi cell; a count the
// area cannot hold and bad input refused as problem+json with nothing created; the
// same request gives the same hash and GLB bytes whatever the worker count; prune
// and bend reach the plants; kill -9 restores the forest by checkpoint and journal.
const test = require('node:test');
const assert = require('node:assert/strict');
const fs = require('node:fs');
const os = require('node:os');
const path = require('node:path');
const { validates } = require('../support/gltf.js');
const { startDaemon, api, sessionState, assertRestored } = require('../support/daemon.js');

const artifact = (name, bytes) => fs.writeFileSync(path.join(process.env.MER_ARTIFACTS, name), bytes);

const SOW = {
  scene: { sow: { area: [[-20, -20], [20, 20]], count: 8, min_distance: 9, seed: 4,
    presets: ['fig4-colonization', 'runions-2007', 'default', 'abop-1.24b'] } },
};

async function glbOf(base, id) {
  const r = await api(base, 'GET', `/v1/sessions/${id}/snapshot.glb`);
  assert.equal(r.status, 200);
  return r.raw;
}

// A snapshot names its session in asset.extras (random by design): zeroed, same
// length, before two daemons' bytes are compared.
function anonymous(glb, id) {
  const out = Buffer.from(glb);
  const needle = Buffer.from(id, 'latin1');
  for (let at = out.indexOf(needle); at >= 0; at = out.indexOf(needle, at + 1)) out.fill('0', at, at + needle.length);
  return out;
}

async function grown(base) {
  const c = await api(base, 'POST', '/v1/sessions', SOW);
  assert.equal(c.status, 201, JSON.stringify(c.body));
  const r = await api(base, 'POST', `/v1/sessions/${c.body.id}/edits`, { op: 'step', count: 6 });
  assert.equal(r.status, 200, JSON.stringify(r.body));
  return { id: c.body.id, summary: r.body, glb: await glbOf(base, c.body.id) };
}

test('a sown forest of mixed models: spacing, the same bytes whatever the workers', async (t) => {
  const one = await startDaemon(['--workers', '1']);
  t.after(() => one.stop());
  const four = await startDaemon(['--workers', '4', '--threads', '4']);
  t.after(() => four.stop());
  const a = await grown(one.url);
  const b = await grown(four.url);
  assert.equal(a.summary.model, 'forest');
  assert.equal(a.summary.plants, 8);
  assert.equal(a.summary.forest.plants, 8);
  assert.ok(a.summary.internodes > 300, `a forest grew: ${a.summary.internodes}`);
  assert.equal(b.summary.hash, a.summary.hash);
  assert.ok(Buffer.compare(anonymous(a.glb, a.id), anonymous(b.glb, b.id)) === 0, 'the same GLB bytes');
  await validates(a.glb);
  artifact('api-sow.glb', a.glb);

  // The plants' first internodes: no two closer than min_distance.
  const sk = await api(one.url, 'GET', `/v1/sessions/${a.id}/skeleton`);
  assert.equal(sk.status, 200);
  const roots = sk.body.nodes.filter((n) => n.parent === null || n.parent === undefined || n.parent < 0);
  assert.equal(roots.length, 8, JSON.stringify(sk.body.nodes.slice(0, 2)));
  for (const p of roots)
    for (const q of roots)
      if (p !== q) assert.ok(Math.hypot(p.base[0] - q.base[0], p.base[2] - q.base[2]) >= 9);
});

test('sow refusals are problem+json and create nothing', async (t) => {
  const d = await startDaemon();
  t.after(() => d.stop());
  const sow = (over) => ({ scene: { sow: { ...SOW.scene.sow, ...over } } });
  const cases = [
    [sow({ count: 500, presets: ['default'] }), 422, 'scene.sow.count', /only \d+ plants/],
    [sow({ count: 500 }), 422, 'scene.sow.count', /at most \d+ markers/],
    [sow({ min_distance: 0 }), 422, 'scene.sow.min_distance', /min_distance/],
    [sow({ presets: ['no-such'] }), 422, 'scene.sow.presets[0]', /preset/],
    [sow({ presets: [] }), 422, 'scene.sow.presets', /array/],
    [sow({ area: [[0, 0], [1]] }), 422, 'scene.sow.area', /\[\[x0, z0\], \[x1, z1\]\]/],
    [sow({ colour: 1 }), 400, 'scene.sow.colour', /./],
    [{ model: 'lsystem', ...sow({}) }, 422, 'scene.sow', /presets/],
    [{ scene: { ...sow({}).scene, plants: [[0, 0, 0]] } }, 422, 'scene.sow', /plants/],
    [{ model: 'forest' }, 422, 'scene.sow', /sow/],
  ];
  for (const [body, status, field, detail] of cases) {
    const r = await api(d.url, 'POST', '/v1/sessions', body);
    assert.equal(r.status, status, `${JSON.stringify(body)}: ${JSON.stringify(r.body)}`);
    assert.match(r.headers.get('content-type'), /application\/problem\+json/);
    assert.equal(r.body.field, field, JSON.stringify(r.body));
    assert.match(r.body.detail, detail);
  }
  const list = await api(d.url, 'GET', '/v1/sessions');
  assert.equal(list.body.sessions.length, 0, 'nothing created');
});

test('prune and bend a forest; kill -9 restores the same bytes', async (t) => {
  const dataDir = fs.mkdtempSync(path.join(os.tmpdir(), 'meristem-sow-'));
  let d = await startDaemon(['--checkpoint-every', '2'], { dataDir });
  t.after(() => { d.stop(); fs.rmSync(dataDir, { recursive: true, force: true }); });
  const { id } = await grown(d.url);
  const sk = (await api(d.url, 'GET', `/v1/sessions/${id}/skeleton?alive=1`)).body.nodes;
  const branch = sk.find((n) => n.order === 1);
  const trunk = sk.find((n) => n.parent !== null && n.parent !== undefined && n.parent >= 0 && n.order === 0);
  let r = await api(d.url, 'POST', `/v1/sessions/${id}/edits`, { edits: [
    { op: 'prune', node: branch.id }, { op: 'bend', node: trunk.id, axis: [0, 0, 1], angle: 25 }] });
  assert.equal(r.status, 200, JSON.stringify(r.body));
  r = await api(d.url, 'POST', `/v1/sessions/${id}/edits`, { op: 'step', count: 2 });
  assert.equal(r.status, 200, JSON.stringify(r.body));
  const after = (await api(d.url, 'GET', `/v1/sessions/${id}/skeleton`)).body.nodes;
  assert.equal(after.find((n) => n.id === branch.id).alive, false, 'the pruned branch stays gone');
  r = await api(d.url, 'POST', `/v1/sessions/${id}/edits`, { op: 'add_markers', points: [[0, 5, 0]] });
  assert.equal(r.status, 422, 'the brush is not a forest\'s');
  const saved = await sessionState(d.url, id);
  await validates(saved.glb);

  d = await d.restart([]);
  await assertRestored(d.url, id, saved);
  // Without the checkpoint, the journal alone replays to the same forest.
  const dropCheckpoints = () => {
    for (const f of fs.readdirSync(dataDir)) if (f.endsWith('.checkpoint')) fs.rmSync(path.join(dataDir, f));
  };
  d = await d.restart([], { whileDown: dropCheckpoints });
  await assertRestored(d.url, id, saved, [], 'after replay');
});
