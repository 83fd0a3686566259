'use strict';
// Checkpoints: restore loads a session's checkpoint and replays only the journal
// after it, to the same bytes as a replay of the whole journal; a damaged or
// missing checkpoint falls back to the journal.
const { test } = require('node:test');
const assert = require('node:assert/strict');
const fs = require('node:fs');
const os = require('node:os');
const path = require('node:path');
const { startDaemon, api } = require('../support/daemon.js');

async function look(d, id) {
  const s = await api(d.url, 'GET', `/v1/sessions/${id}`);
  assert.equal(s.status, 200, JSON.stringify(s.body));
  const g = await fetch(`${d.url}/v1/sessions/${id}/snapshot.glb?leaves=1`);
  assert.equal(g.status, 200);
  return { revision: s.body.revision, hash: s.body.hash, glb: Buffer.from(await g.arrayBuffer()) };
}

function same(a, b, what) {
  assert.equal(a.revision, b.revision, what);
  assert.equal(a.hash, b.hash, what);
  assert.ok(a.glb.equals(b.glb), `${what}: byte-identical GLB`);
}

test('restore starts from the checkpoint, to the same bytes; a damaged one falls back', async (t) => {
  const dataDir = fs.mkdtempSync(path.join(os.tmpdir(), 'meristem-checkpoint-'));
  let d = null;
  t.after(async () => {
    if (d) await d.stop();
    fs.rmSync(dataDir, { recursive: true, force: true });
  });
  const args = ['--checkpoint-every', '3'];
  d = await startDaemon(args, { dataDir });
  const id = (await api(d.url, 'POST', '/v1/sessions', { preset: 'fig4-colonization', seed: 2 })).body.id;
  const E = (edit) => api(d.url, 'POST', `/v1/sessions/${id}/edits`, edit);
  for (let i = 0; i < 7; i++) {
    const edit = i === 4 ? { op: 'add_markers', points: [[1, 6, 0], [-1, 7, 1]] } : { op: 'step', count: 2 };
    assert.equal((await E(edit)).status, 200);
  }
  const grown = await look(d, id);
  assert.equal(grown.revision, 7);
  const checkpoint = path.join(dataDir, `${id}.checkpoint`);
  assert.ok(fs.existsSync(checkpoint), 'a checkpoint at revision 6');
  await d.stop();

  d = await startDaemon(args, { dataDir });
  same(await look(d, id), grown, 'from the checkpoint');
  await d.waitForLog(new RegExp(`${id}: restored from its checkpoint at revision 6 and 1 journal records`));  // stderr may lag: wait for the line
  // It grows on as the original would have: compare with a replay of the whole journal.
  assert.equal((await E({ op: 'step', count: 2 })).status, 200);
  const more = await look(d, id);
  await d.stop();

  // Damage the checkpoint (still revision 6: 8 is not a multiple of 3).
  const bytes = fs.readFileSync(checkpoint);
  bytes[bytes.length >> 1] ^= 0x40;
  fs.writeFileSync(checkpoint, bytes);
  d = await startDaemon(args, { dataDir });
  same(await look(d, id), more, 'from the journal, past a damaged checkpoint');
  await d.waitForLog(/the checkpoint is not used/);  // stderr may lag: wait for the line
  await d.stop();

  fs.rmSync(checkpoint);
  d = await startDaemon(args, { dataDir });
  same(await look(d, id), more, 'from the journal alone');
  // Deleting the session removes its checkpoint too.
  assert.equal((await E({ op: 'step', count: 1 })).status, 200);
  assert.ok(fs.existsSync(checkpoint), 'a checkpoint at revision 9');
  assert.equal((await api(d.url, 'DELETE', `/v1/sessions/${id}`)).status, 204);
  assert.ok(!fs.existsSync(checkpoint), 'the checkpoint goes with the session');
});
