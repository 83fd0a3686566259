'use strict';
// Undo, redo and history: a revert makes the tree of a past revision again, as
// a new revision, byte for byte; the revisions are listed in pages; a past
// snapshot is served by revision; a restart replays reverts to the same tree.
const { test, before, after } = require('node:test');
const assert = require('node:assert/strict');
const fs = require('node:fs');
const os = require('node:os');
const path = require('node:path');
const { startDaemon, api } = require('../support/daemon.js');

let d;
const J = (method, p, body) => api(d.url, method, p, body);
const dataDir = fs.mkdtempSync(path.join(os.tmpdir(), 'meristem-history-'));
before(async () => { d = await startDaemon(['--checkpoint-every', '3'], { dataDir }); });
after(async () => {
  await d.stop();
  fs.rmSync(dataDir, { recursive: true, force: true });
});

async function glb(id, query = '') {
  const r = await fetch(`${d.url}/v1/sessions/${id}/snapshot.glb?leaves=1${query}`);
  assert.equal(r.status, 200, await r.clone().text());
  return Buffer.from(await r.arrayBuffer());
}

async function look(id) {
  const s = await J('GET', `/v1/sessions/${id}`);
  assert.equal(s.status, 200);
  return { revision: s.body.revision, hash: s.body.hash, glb: await glb(id) };
}

async function edit(id, body) {
  const r = await J('POST', `/v1/sessions/${id}/edits`, body);
  assert.equal(r.status, 200, JSON.stringify(r.body));
  return r.body;
}

const stroke = {
  op: 'add_markers', center: [2, 11, 0], radius: 2.5, pressure: 0.8, count: 80,
  symmetry: { rotational: 3, center: [0, 0, 0] },
};

test('undo after a brush stroke and after a prune gives the earlier GLB byte for byte', async () => {
  const id = (await J('POST', '/v1/sessions', { preset: 'default', seed: 5 })).body.id;
  await edit(id, { op: 'step', count: 6 });
  const grown = await look(id);
  await edit(id, { edits: [stroke, { op: 'step', count: 2 }] });
  const brushed = await look(id);
  assert.notEqual(brushed.hash, grown.hash);

  // Undo the stroke: a new revision with the tree, hash and GLB of the one before.
  const undone = await edit(id, { op: 'revert', revision: grown.revision });
  assert.equal(undone.revision, brushed.revision + 1);
  const now = await look(id);
  assert.equal(now.hash, grown.hash);
  assert.ok(now.glb.equals(grown.glb), 'undo of a stroke: byte-identical GLB');

  // Redo is a revert to the later revision.
  await edit(id, { op: 'revert', revision: brushed.revision });
  const redone = await look(id);
  assert.equal(redone.hash, brushed.hash);
  assert.ok(redone.glb.equals(brushed.glb), 'redo: byte-identical GLB');

  // Undo of a prune.
  const before = redone;
  const skel = (await J('GET', `/v1/sessions/${id}/skeleton?alive=1`)).body;
  const twig = skel.nodes.find((n) => n.parent !== null && n.order === 1);
  await edit(id, { op: 'prune', node: twig.id });
  const pruned = await look(id);
  assert.notEqual(pruned.hash, before.hash);
  await edit(id, { op: 'revert', revision: before.revision });
  const back = await look(id);
  assert.equal(back.hash, before.hash);
  assert.ok(back.glb.equals(before.glb), 'undo of a prune: byte-identical GLB');

  // Every past revision is served by number, byte for byte as it was.
  assert.ok((await glb(id, `&revision=${grown.revision}`)).equals(grown.glb));
  assert.ok((await glb(id, `&revision=${pruned.revision}`)).equals(pruned.glb));
  assert.ok((await glb(id, `&revision=${pruned.revision}`)).equals(pruned.glb), 'kept: the same again');

  // A restart replays the journal, reverts and all, to the same tree.
  await d.stop();
  d = await startDaemon(['--checkpoint-every', '3'], { dataDir });
  const restored = await look(id);
  assert.equal(restored.hash, back.hash);
  assert.ok(restored.glb.equals(back.glb), 'restored: byte-identical GLB');
  assert.ok((await glb(id, `&revision=${brushed.revision}`)).equals(brushed.glb),
    'a past revision after a restart');
});

test('a revert to a revision the session does not have is refused naming revision', async () => {
  const id = (await J('POST', '/v1/sessions', { preset: 'default', seed: 1 })).body.id;
  await edit(id, { op: 'step', count: 2 });
  const was = await look(id);
  for (const body of [{ op: 'revert', revision: 2 }, { op: 'revert', revision: 99 }]) {
    const r = await J('POST', `/v1/sessions/${id}/edits`, body);
    assert.equal(r.status, 422, JSON.stringify(r.body));
    assert.equal(r.headers.get('content-type'), 'application/problem+json');
    assert.equal(r.body.field, 'revision');
  }
  const inBatch = await J('POST', `/v1/sessions/${id}/edits`,
    { edits: [{ op: 'step', count: 1 }, { op: 'revert', revision: 7 }] });
  assert.equal(inBatch.status, 422);
  assert.equal(inBatch.body.field, 'edits[1].revision');
  const bad = await J('POST', `/v1/sessions/${id}/edits`, { op: 'revert', revision: -1 });
  assert.equal(bad.status, 422);
  assert.equal(bad.body.field, 'revision');
  const now = await look(id);
  assert.equal(now.revision, was.revision);
  assert.ok(now.glb.equals(was.glb));
  const past = await fetch(`${d.url}/v1/sessions/${id}/snapshot.glb?revision=5`);
  assert.equal(past.status, 422);
  assert.equal((await past.json()).field, 'revision');
});

test('revisions are listed oldest first, in pages, with their edits, step and internodes', async () => {
  const id = (await J('POST', '/v1/sessions', { preset: 'default', seed: 2 })).body.id;
  for (let i = 0; i < 4; i++) await edit(id, { op: 'step', count: 1 });
  await edit(id, { op: 'revert', revision: 2 });
  const all = await J('GET', `/v1/sessions/${id}/revisions`);
  assert.equal(all.status, 200);
  assert.deepEqual(all.body.revisions.map((r) => r.revision), [0, 1, 2, 3, 4, 5]);
  assert.equal(all.body.next_after, null);
  assert.deepEqual(all.body.revisions[0].edits, []);
  assert.deepEqual(all.body.revisions[1].edits, [{ op: 'step', count: 1 }]);
  assert.deepEqual(all.body.revisions[5].edits, [{ op: 'revert', revision: 2 }]);
  assert.deepEqual(all.body.revisions.map((r) => r.step), [0, 1, 2, 3, 4, 2]);
  assert.equal(all.body.revisions[5].internodes, all.body.revisions[2].internodes);
  const s = (await J('GET', `/v1/sessions/${id}`)).body;
  assert.equal(all.body.revisions[5].internodes, s.internodes);

  const seen = [];
  let after = null;
  for (;;) {
    const q = after === null ? '?limit=2' : `?limit=2&after=${after}`;
    const page = await J('GET', `/v1/sessions/${id}/revisions${q}`);
    assert.equal(page.status, 200);
    assert.ok(page.body.revisions.length <= 2);
    seen.push(...page.body.revisions.map((r) => r.revision));
    if (page.body.next_after === null) break;
    after = page.body.next_after;
  }
  assert.deepEqual(seen, [0, 1, 2, 3, 4, 5]);
  for (const q of ['?limit=0', '?limit=x', '?after=-1']) {
    const r = await J('GET', `/v1/sessions/${id}/revisions${q}`);
    assert.equal(r.status, 422, q);
  }
});
