'use strict';
// Lazy restore: meristemd listens before it reads any journal. Sessions of the
// data folder are listed as "not loaded" until their first request (or the
// background loader) loads them, once; a journal found damaged then is
// quarantined as at start-up; SIGTERM while the loader runs exits cleanly.
const test = require('node:test');
const assert = require('node:assert/strict');
const fs = require('node:fs');
const os = require('node:os');
const path = require('node:path');
const { startDaemon, api } = require('../support/daemon.js');

/** Edits (of 5 steps) in the journal of the slow-loading session: a tree of
 * about 250,000 internodes, whose replay takes seconds. */
const SLOW_EDITS = 8;

const freshDir = () => fs.mkdtempSync(path.join(os.tmpdir(), 'meristem-restore-'));

/** {id: state} of GET /v1/sessions. */
async function states(base) {
  const r = await api(base, 'GET', '/v1/sessions');
  assert.equal(r.status, 200);
  return Object.fromEntries(r.body.sessions.map((s) => [s.id, s.state]));
}

/** A data folder with `n` small sessions (3 edits each, checkpoints every 2)
 * and one with a journal of several megabytes; their summaries. */
async function dataFolder(dataDir, n) {
  const d = await startDaemon(['--checkpoint-every', '2'], { dataDir });
  const small = [];
  for (let k = 0; k < n; k++) {
    const { body } = await api(d.url, 'POST', '/v1/sessions', { seed: k + 1 });
    let last = body;
    for (let i = 0; i < 3; i++)
      last = (await api(d.url, 'POST', `/v1/sessions/${body.id}/edits`, { op: 'step', count: 2 })).body;
    small.push(last);
  }
  const { body: big } = await api(d.url, 'POST', '/v1/sessions', { seed: 99 });
  const points = Array.from({ length: 120000 }, (_, i) => [(i % 97) / 9 - 5, 2 + (i % 89) / 11, (i % 83) / 9 - 4.5]);
  const r = await api(d.url, 'POST', `/v1/sessions/${big.id}/edits`, { op: 'add_markers', points });
  assert.equal(r.status, 200, JSON.stringify(r.body));
  await d.stop();
  assert.ok(fs.statSync(path.join(dataDir, `${big.id}.journal`)).size > 2e6, 'a journal of megabytes');
  return { small, big: r.body };
}

/** dataFolder(…, 3) copied into `dataDir`: made once (it takes a daemon, three
 * sessions and a journal of megabytes), for the tests that only read it. */
let made = null;
async function copyOfDataFolder(dataDir) {
  if (!made) {
    const dir = freshDir();
    process.on('exit', () => fs.rmSync(dir, { recursive: true, force: true }));
    made = { dir, ...(await dataFolder(dir, 3)) };
  }
  fs.cpSync(made.dir, dataDir, { recursive: true });
  return { small: made.small, big: made.big };
}

test('health and the list answer before any session is loaded; a request loads its session once', async (t) => {
  const dataDir = freshDir();
  t.after(() => fs.rmSync(dataDir, { recursive: true, force: true }));
  const { small, big } = await copyOfDataFolder(dataDir);

  const d = await startDaemon(['--warm-up', 'off', '--checkpoint-every', '2'], { dataDir });
  t.after(() => d.stop());
  assert.equal((await api(d.url, 'GET', '/v1/health')).status, 200);
  // Nothing read yet, not even the big journal: all are listed, none loaded.
  const before = await states(d.url);
  for (const s of [...small, big]) assert.equal(before[s.id], 'not loaded', JSON.stringify(before));
  assert.doesNotMatch(d.log(), /restored from its checkpoint/);

  // A GET loads its session, and only that one.
  const one = await api(d.url, 'GET', `/v1/sessions/${small[0].id}`);
  assert.equal(one.status, 200);
  assert.equal(one.body.revision, 3);
  assert.equal(one.body.hash, small[0].hash);
  const after = await states(d.url);
  assert.equal(after[small[0].id], 'loaded');
  assert.equal(after[small[1].id], 'not loaded');
  assert.equal(after[big.id], 'not loaded');

  // Eight first requests at once load the session once and agree.
  const id = small[1].id;
  const answers = await Promise.all(Array.from({ length: 8 }, (_, i) =>
    (i % 2 ? api(d.url, 'GET', `/v1/sessions/${id}`) : fetch(`${d.url}/v1/sessions/${id}/snapshot.glb`))));
  for (const a of answers) assert.equal(a.status, 200);
  await d.waitForLog(new RegExp(`${id}: restored from its checkpoint`));  // stderr may lag
  const loads = d.log().match(new RegExp(`${id}: restored from its checkpoint`, 'g'));
  assert.equal(loads.length, 1, d.log());
  // An edit to a session not loaded loads it and goes on from its revision.
  const e = await api(d.url, 'POST', `/v1/sessions/${small[2].id}/edits`, { op: 'step', count: 1 });
  assert.equal(e.body.revision, 4);
  const b = await api(d.url, 'GET', `/v1/sessions/${big.id}`);
  assert.equal(b.body.hash, big.hash);
});

test('DELETE of a session not loaded yet removes it for good', async (t) => {
  const dataDir = freshDir();
  t.after(() => fs.rmSync(dataDir, { recursive: true, force: true }));
  let d = await startDaemon(['--checkpoint-every', '1'], { dataDir });
  const { body: { id } } = await api(d.url, 'POST', '/v1/sessions', { seed: 4 });
  await api(d.url, 'POST', `/v1/sessions/${id}/edits`, { op: 'step', count: 2 });
  await d.stop();
  d = await startDaemon(['--warm-up', 'off'], { dataDir });
  assert.equal((await states(d.url))[id], 'not loaded');
  assert.equal((await api(d.url, 'DELETE', `/v1/sessions/${id}`)).status, 204);
  assert.deepEqual(fs.readdirSync(dataDir).filter((f) => f.startsWith(id)), []);
  d = await d.restart(['--warm-up', 'off']);
  t.after(() => d.stop());
  assert.equal((await api(d.url, 'GET', `/v1/sessions/${id}`)).status, 404);
});

test('the background loader loads every session, and SIGTERM while it runs exits cleanly', async (t) => {
  const dataDir = freshDir();
  t.after(() => fs.rmSync(dataDir, { recursive: true, force: true }));
  const { small, big } = await copyOfDataFolder(dataDir);
  let d = await startDaemon(['--checkpoint-every', '2'], { dataDir });
  await d.waitForLog(/restored 4 sessions in the background/);
  const all = await states(d.url);
  for (const s of [...small, big]) assert.equal(all[s.id], 'loaded');
  await d.stop();
  // Stopped while it loads (or just after): exit status 0, every session whole.
  d = await startDaemon([], { dataDir });
  assert.deepEqual(await d.stop('SIGTERM'), { code: 0, signal: null }, d.log());
  d = await startDaemon(['--warm-up', 'off'], { dataDir });
  t.after(() => d.stop());
  for (const s of [...small, big])
    assert.equal((await api(d.url, 'GET', `/v1/sessions/${s.id}`)).body.hash, s.hash);
});

/** The byte offsets of the records of a journal (u32 length, u32 CRC, payload). */
function records(file) {
  const bytes = fs.readFileSync(file);
  const at = [];
  for (let p = 0; p + 8 <= bytes.length; p += 8 + bytes.readUInt32LE(p)) at.push(p);
  return { bytes, at };
}

test('a journal found damaged when first requested is quarantined, once, not cut', async (t) => {
  const dataDir = freshDir();
  t.after(() => fs.rmSync(dataDir, { recursive: true, force: true }));
  let d = await startDaemon(['--checkpoint-every', '0'], { dataDir });
  const { body: { id } } = await api(d.url, 'POST', '/v1/sessions', { seed: 3 });
  for (let i = 0; i < 7; i++) await api(d.url, 'POST', `/v1/sessions/${id}/edits`, { op: 'step', count: 1 });
  await d.stop();
  const file = path.join(dataDir, `${id}.journal`);
  const { bytes, at } = records(file);
  bytes[at[2] + 8 + 5] ^= 0x20;
  fs.writeFileSync(file, bytes);

  d = await startDaemon(['--warm-up', 'off'], { dataDir });
  t.after(() => d.stop());
  assert.equal((await states(d.url))[id], 'not loaded');
  assert.ok(fs.existsSync(file), 'not read before its first request');
  const answers = await Promise.all([1, 2, 3, 4].map(() => api(d.url, 'GET', `/v1/sessions/${id}`)));
  for (const r of answers) {
    assert.equal(r.status, 503);
    assert.equal(r.body.type, 'urn:meristem:problem:quarantined');
    assert.ok(r.body.detail.includes(id));
  }
  await d.waitForLog(/QUARANTINED/);  // stderr may lag behind the answers
  assert.equal(d.log().match(/QUARANTINED/g).length, 1, d.log());
  assert.ok(!fs.existsSync(file));
  assert.ok(fs.readFileSync(path.join(dataDir, 'quarantine', `${id}.journal`)).equals(bytes), 'kept byte for byte');
  const list = (await api(d.url, 'GET', '/v1/sessions')).body.sessions;
  assert.deepEqual(list.map((s) => [s.id, s.state]), [[id, 'quarantined']]);
  assert.equal((await api(d.url, 'POST', `/v1/sessions/${id}/edits`, { op: 'step', count: 1 })).status, 503);
  assert.equal((await api(d.url, 'DELETE', `/v1/sessions/${id}`)).status, 503);
});

test('a slow first load runs on a worker: health answers on the same HTTP thread meanwhile', async (t) => {
  const dataDir = freshDir();
  let d = null;
  t.after(async () => { if (d) await d.stop(); fs.rmSync(dataDir, { recursive: true, force: true }); });
  // No checkpoints: the first request replays every step of the journal.
  d = await startDaemon(['--checkpoint-every', '0'], { dataDir });
  const { body: { id } } = await api(d.url, 'POST', '/v1/sessions', { preset: 'fig7-bh-0.54', seed: 3 });
  let last = null;
  for (let i = 0; i < SLOW_EDITS; i++)
    last = (await api(d.url, 'POST', `/v1/sessions/${id}/edits`, { op: 'step', count: 5 })).body;
  await d.stop();

  // One HTTP thread serves both connections.
  d = await startDaemon(['--warm-up', 'off', '--threads', '1', '--checkpoint-every', '0'], { dataDir });
  const order = [];
  const session = api(d.url, 'GET', `/v1/sessions/${id}`).then((r) => { order.push('session'); return r; });
  // Only so that the load has begun: the replay takes far longer.
  await new Promise((r) => setTimeout(r, 300));
  const health = await api(d.url, 'GET', '/v1/health');
  order.push('health');
  assert.equal(health.status, 200);
  const r = await session;
  assert.equal(r.status, 200, JSON.stringify(r.body));
  assert.equal(r.body.revision, last.revision);
  assert.equal(r.body.hash, last.hash);
  assert.deepEqual(order, ['health', 'session'], 'health did not wait for the load');
});
