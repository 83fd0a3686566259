'use strict';
// Refused edits are undone in memory: a refused batch leaves the session
// byte-identical (hash and GLB) without reading its journal back. The journal is
// moved aside while the batches are refused, so an undo that replays it fails.
const { test, before, after } = require('node:test');
const assert = require('node:assert/strict');
const fs = require('node:fs');
const os = require('node:os');
const path = require('node:path');
const { startDaemon, api } = require('../support/daemon.js');

let d;
const J = (method, p, body) => api(d.url, method, p, body);

const dataDir = fs.mkdtempSync(path.join(os.tmpdir(), 'meristem-undo-'));
before(async () => { d = await startDaemon([], { dataDir }); });
after(async () => {
  await d.stop();
  fs.rmSync(dataDir, { recursive: true, force: true });
});

async function snapshot(id) {
  const r = await fetch(`${d.url}/v1/sessions/${id}/snapshot.glb?leaves=1`);
  assert.equal(r.status, 200);
  return Buffer.from(await r.arrayBuffer());
}

async function look(id) {
  const s = await J('GET', `/v1/sessions/${id}`);
  assert.equal(s.status, 200, JSON.stringify(s.body));
  return { revision: s.body.revision, hash: s.body.hash, step: s.body.step, glb: await snapshot(id) };
}

test('refused edits and batches leave the session byte-identical without a replay', async () => {
  const c = await J('POST', '/v1/sessions', { preset: 'default', seed: 3 });
  assert.equal(c.status, 201);
  const id = c.body.id;
  assert.equal((await J('POST', `/v1/sessions/${id}/edits`, { op: 'step', count: 6 })).status, 200);
  const was = await look(id);
  const journal = path.join(dataDir, `${id}.journal`);
  const aside = `${journal}.aside`;
  fs.renameSync(journal, aside);
  try {
    const refused = [
      { op: 'prune', node: 999999 },
      { edits: [{ op: 'step', count: 2 }, { op: 'prune', node: 999999 }] },
      { edits: [{ op: 'prune', node: 3 }, { op: 'bend', node: 999999, axis: [0, 0, 1], angle: 10 }] },
    ];
    for (const body of refused) {
      const r = await J('POST', `/v1/sessions/${id}/edits`, body);
      assert.equal(r.status, 404, JSON.stringify(r.body));
      assert.equal(r.body.type, 'urn:meristem:problem:unknown-node');
      const now = await look(id);
      assert.equal(now.revision, was.revision);
      assert.equal(now.hash, was.hash);
      assert.equal(now.step, was.step);
      assert.ok(now.glb.equals(was.glb), 'byte-identical GLB after a refusal');
    }
  } finally {
    fs.renameSync(aside, journal);
  }
  // The session still takes edits, and they are journaled as before.
  assert.equal((await J('POST', `/v1/sessions/${id}/edits`, { op: 'step', count: 1 })).status, 200);
  const grown = await look(id);
  assert.equal(grown.revision, was.revision + 1);
  await d.stop();
  d = await startDaemon([], { dataDir });
  const back = await look(id);
  assert.equal(back.hash, grown.hash);
  assert.ok(back.glb.equals(grown.glb), 'byte-identical GLB after a restart');
});
