'use strict';
// SIGTERM while sessions step and edits are in flight: meristemd stops in
// order (no new connections, running batches stop at a whole step and are
// journaled, every waiting request is answered) and exits 0, and every edit it
// acknowledged is there after a restart.
const test = require('node:test');
const assert = require('node:assert/strict');
const fs = require('node:fs');
const os = require('node:os');
const path = require('node:path');
const { startDaemon, api } = require('../support/daemon.js');

const SESSIONS = 4;

/** Keeps one session busy with steps and prunes until `stopped` says so,
 * remembering the highest revision (and its hash) acknowledged with a 200. */
async function stream(url, id, acked, stopped) {
  for (let i = 0; !stopped(); i++) {
    const body = i % 3 === 2
      ? { edits: [{ op: 'step', count: 2 }, { op: 'prune', node: 3 + i }] }
      : { op: 'step', count: 3 };
    let r;
    try {
      r = await api(url, 'POST', `/v1/sessions/${id}/edits`, body);
    } catch {
      return;  // the daemon went away mid-request: not acknowledged
    }
    if (r.status === 200 && r.body.revision >= (acked.get(id)?.revision ?? -1))
      acked.set(id, { revision: r.body.revision, hash: r.body.hash });
  }
}

test('SIGTERM under load exits 0 and keeps every acknowledged edit', async (t) => {
  const dataDir = fs.mkdtempSync(path.join(os.tmpdir(), 'meristem-sigterm-'));
  t.after(() => fs.rmSync(dataDir, { recursive: true, force: true }));
  const d = await startDaemon(['--quiet', '--workers', '2'], { dataDir });
  const ids = [];
  for (let i = 0; i < SESSIONS; i++) {
    const r = await api(d.url, 'POST', '/v1/sessions', { preset: 'default', seed: i });
    assert.equal(r.status, 201);
    ids.push(r.body.id);
  }
  const acked = new Map();
  let stop = false;
  const streams = ids.map((id) => stream(d.url, id, acked, () => stop));
  // Wait until every session has had edits accepted and the trees are big
  // enough that steps take a while, then stop the daemon mid-stream.
  while (ids.some((id) => (acked.get(id)?.revision ?? 0) < 4))
    await new Promise((resolve) => setTimeout(resolve, 20));
  const running = await api(d.url, 'GET', '/v1/sessions');
  assert.equal(running.status, 200);
  const exit = await d.stop('SIGTERM');
  stop = true;
  await Promise.all(streams);
  assert.deepEqual(exit, { code: 0, signal: null }, d.log());
  assert.match(d.log(), /SIGTERM, shutting down/);

  const again = await startDaemon(['--quiet'], { dataDir });
  t.after(() => again.stop());
  for (const id of ids) {
    const r = await api(again.url, 'GET', `/v1/sessions/${id}`);
    assert.equal(r.status, 200, `session ${id} after restart`);
    const want = acked.get(id);
    assert.ok(r.body.revision >= want.revision,
      `session ${id}: revision ${r.body.revision} after restart, ${want.revision} was acknowledged`);
    if (r.body.revision === want.revision) assert.equal(r.body.hash, want.hash);
  }
});
