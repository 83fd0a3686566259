'use strict';
// The skeleton for scripts: every internode with its parent, ends, diameter,
// order, age, whether it lives and its light Q; ?alive=1 leaves out the dead.
const { test, before, after } = require('node:test');
const assert = require('node:assert/strict');
const { startDaemon, api } = require('../support/daemon.js');

let d;
const J = (method, p, body) => api(d.url, method, p, body);
before(async () => { d = await startDaemon(); });
after(async () => { await d.stop(); });

test('the skeleton lists every node, and ?alive=1 only the living', async () => {
  const id = (await J('POST', '/v1/sessions', { preset: 'default', seed: 4 })).body.id;
  const stepped = await J('POST', `/v1/sessions/${id}/edits`, { op: 'step', count: 6 });
  const all = await J('GET', `/v1/sessions/${id}/skeleton`);
  assert.equal(all.status, 200);
  assert.equal(all.body.revision, stepped.body.revision);
  const nodes = all.body.nodes;
  assert.equal(nodes.filter((n) => n.alive).length, stepped.body.internodes);
  const byId = new Map(nodes.map((n) => [n.id, n]));
  for (const n of nodes) {
    assert.deepEqual(Object.keys(n).sort(),
      ['age', 'alive', 'base', 'diameter', 'id', 'order', 'parent', 'q', 'tip'].sort());
    assert.equal(n.base.length, 3);
    assert.equal(n.tip.length, 3);
    assert.ok(n.diameter > 0 && n.age >= 0 && n.q >= 0);
    if (n.parent === null) continue;
    const p = byId.get(n.parent);
    assert.ok(p, `node ${n.id}'s parent exists`);
    // A child starts where its parent ends.
    for (let k = 0; k < 3; k++) assert.ok(Math.abs(n.base[k] - p.tip[k]) < 1e-4);
  }
  assert.equal(nodes.filter((n) => n.parent === null).length, 1, 'one plant, one root');

  // Prune a branch picked from the skeleton, as the README's pipeline does.
  const branch = nodes.find((n) => n.order === 1 && n.alive);
  const pruned = await J('POST', `/v1/sessions/${id}/edits`, { op: 'prune', node: branch.id });
  assert.equal(pruned.status, 200, JSON.stringify(pruned.body));
  const after = (await J('GET', `/v1/sessions/${id}/skeleton`)).body;
  assert.equal(after.nodes.find((n) => n.id === branch.id).alive, false);
  const alive = (await J('GET', `/v1/sessions/${id}/skeleton?alive=1`)).body;
  assert.equal(alive.revision, pruned.body.revision);
  assert.ok(alive.nodes.every((n) => n.alive));
  assert.equal(alive.nodes.length, pruned.body.internodes);
  assert.ok(alive.nodes.length < after.nodes.length);
  for (const q of ['?alive=2', '?alive=yes']) {
    assert.equal((await J('GET', `/v1/sessions/${id}/skeleton${q}`)).status, 422, q);
  }
  assert.equal((await J('GET', '/v1/sessions/0123456789abcdef0123456789abcdef/skeleton')).status, 404);
});
