'use strict';
// What meristemd promises about work: acknowledged edits survive kill -9, a
// torn journal tail is dropped whole, and long steps do not block others.
const test = require('node:test');
const assert = require('node:assert/strict');
const fs = require('node:fs');
const os = require('node:os');
const path = require('node:path');
const { startDaemon, api } = require('../support/daemon.js');

const freshDir = () => fs.mkdtempSync(path.join(os.tmpdir(), 'meristem-durable-'));

async function snapshot(base, id) {
  const r = await fetch(`${base}/v1/sessions/${id}/snapshot.glb?leaves=1`);
  assert.equal(r.status, 200);
  return Buffer.from(await r.arrayBuffer());
}

test('kill -9 during a stream of edits loses no acknowledged edit', async (t) => {
  const dataDir = freshDir();
  t.after(() => fs.rmSync(dataDir, { recursive: true, force: true }));
  let d = await startDaemon([], { dataDir });
  const ids = [];
  for (const seed of [1, 2])
    ids.push((await api(d.url, 'POST', '/v1/sessions', { preset: 'fig9-priority-k0.5', seed })).body.id);
  // A stream of edits on both sessions; remember what was acknowledged.
  const acked = new Map(ids.map((id) => [id, 0]));
  let stop = false;
  const streams = ids.map(async (id, k) => {
    for (let i = 0; !stop; i++) {
      const edit = i % 3 === 2 ? { op: 'add_markers', points: [[k, 5 + i, 0]] } : { op: 'step', count: 1 };
      try {
        const r = await api(d.url, 'POST', `/v1/sessions/${id}/edits`, edit);
        if (r.status === 200) acked.set(id, r.body.revision);
      } catch { return; }  // the connection died with the daemon
    }
  });
  await new Promise((res) => setTimeout(res, 700));
  d.child.kill('SIGKILL');
  stop = true;
  await Promise.all(streams);
  await d.stop();

  d = await startDaemon([], { dataDir });
  t.after(() => d.stop());
  assert.match(d.log(), /restored 2 sessions/);
  for (const id of ids) {
    const s = await api(d.url, 'GET', `/v1/sessions/${id}`);
    assert.equal(s.status, 200);
    // Every acknowledged revision is there; at most the one in flight beyond it.
    assert.ok(s.body.revision >= acked.get(id) && s.body.revision <= acked.get(id) + 1,
      `${id}: revision ${s.body.revision}, acknowledged ${acked.get(id)}`);
    assert.ok(acked.get(id) > 2, `the stream got going (${acked.get(id)} revisions)`);
  }
  // And a restart without a crash reproduces every byte of every session.
  const before = await Promise.all(ids.map((id) => snapshot(d.url, id)));
  const hashes = await Promise.all(ids.map(async (id) => (await api(d.url, 'GET', `/v1/sessions/${id}`)).body.hash));
  await d.stop();
  d = await startDaemon([], { dataDir });
  for (const [k, id] of ids.entries()) {
    const s = await api(d.url, 'GET', `/v1/sessions/${id}`);
    assert.equal(s.body.hash, hashes[k]);
    assert.ok(before[k].equals(await snapshot(d.url, id)), 'byte-identical GLB after restart');
  }
});

test('a torn last journal record is dropped whole on restart', async (t) => {
  const dataDir = freshDir();
  t.after(() => fs.rmSync(dataDir, { recursive: true, force: true }));
  let d = await startDaemon([], { dataDir });
  const { body: { id } } = await api(d.url, 'POST', '/v1/sessions', { seed: 9 });
  await api(d.url, 'POST', `/v1/sessions/${id}/edits`, { op: 'step', count: 4 });
  const two = await api(d.url, 'POST', `/v1/sessions/${id}/edits`, { op: 'step', count: 3 });
  await api(d.url, 'POST', `/v1/sessions/${id}/edits`, { op: 'step', count: 2 });
  await d.stop();
  // A power cut in the middle of writing the third batch's record.
  const file = path.join(dataDir, `${id}.journal`);
  const size = fs.statSync(file).size;
  fs.truncateSync(file, size - 7);
  d = await startDaemon([], { dataDir });
  t.after(() => d.stop());
  assert.match(d.log(), /dropped a torn last record/);
  const s = await api(d.url, 'GET', `/v1/sessions/${id}`);
  assert.equal(s.body.revision, 2);
  assert.equal(s.body.step, 7);
  assert.equal(s.body.hash, two.body.hash);
  // The journal goes on from the last whole record.
  const r = await api(d.url, 'POST', `/v1/sessions/${id}/edits`, { op: 'step', count: 1 });
  assert.equal(r.body.revision, 3);
  assert.equal(r.body.step, 8);
});

test('two sessions step at once while a third request answers fast', async (t) => {
  const d = await startDaemon(['--workers', '2', '--threads', '2']);
  t.after(() => d.stop());
  const ids = [];
  for (const seed of [1, 2])
    ids.push((await api(d.url, 'POST', '/v1/sessions', { preset: 'fig7-bh-0.54', seed })).body.id);
  const steps = ids.map((id) => api(d.url, 'POST', `/v1/sessions/${id}/edits`, { op: 'step', count: 40 }));
  // Both must be running at once.
  let both = false;
  const latencies = [];
  for (let i = 0; i < 400 && !both; i++) {
    const t0 = performance.now();
    const h = await fetch(`${d.url}/v1/health`);
    latencies.push(performance.now() - t0);
    assert.equal(h.status, 200);
    const running = await Promise.all(ids.map(async (id) => (await api(d.url, 'GET', `/v1/sessions/${id}`)).body.running.active));
    both = running.every(Boolean);
    await new Promise((res) => setTimeout(res, 5));
  }
  assert.ok(both, 'both sessions were stepping at the same time');
  for (let i = 0; i < 5; i++) {
    const t0 = performance.now();
    assert.equal((await fetch(`${d.url}/v1/health`)).status, 200);
    latencies.push(performance.now() - t0);
  }
  const worst = Math.max(...latencies);
  assert.ok(worst < 100, `health took ${worst.toFixed(1)} ms at worst while two trees stepped`);
  const done = await Promise.all(steps);
  for (const r of done) assert.equal(r.body.step, 40);
});
