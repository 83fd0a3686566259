'use strict';
// What meristemd promises about work: acknowledged edits survive kill -9, a
// torn journal tail is dropped whole, damage anywhere else is quarantined and
// never cut, DELETE is durable, and long steps do not block others.
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
  // Kill once both streams are going (a busy machine may take a while to get
  // there), in the middle of the next edits.
  while ([...acked.values()].some((r) => r <= 2)) await new Promise((res) => setTimeout(res, 20));
  await new Promise((res) => setTimeout(res, 200));
  d.child.kill('SIGKILL');
  stop = true;
  await Promise.all(streams);
  await d.stop();

  d = await startDaemon([], { dataDir });
  t.after(() => d.stop());
  await d.waitForLog(/restored 2 sessions/);
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
  const s = await api(d.url, 'GET', `/v1/sessions/${id}`);
  await d.waitForLog(/dropped a torn last record/);  // stderr may lag: wait for the line
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
  // Both must be running at once, and health answers all the while.
  let both = false;
  let answered = 0;
  for (let i = 0; i < 400 && !both; i++) {
    const h = await fetch(`${d.url}/v1/health`);
    assert.equal(h.status, 200);
    answered++;
    const running = await Promise.all(ids.map(async (id) => (await api(d.url, 'GET', `/v1/sessions/${id}`)).body.running.active));
    both = running.every(Boolean);
    await new Promise((res) => setTimeout(res, 5));
  }
  assert.ok(both, 'both sessions were stepping at the same time');
  for (let i = 0; i < 5; i++) {
    assert.equal((await fetch(`${d.url}/v1/health`)).status, 200);
    answered++;
  }
  // Health answered while both steps still ran: it never waited for them.
  const still = await Promise.all(ids.map(async (id) => (await api(d.url, 'GET', `/v1/sessions/${id}`)).body.running.active));
  assert.ok(still.some(Boolean), `health answered ${answered} times before the steps ended`);
  const done = await Promise.all(steps);
  for (const r of done) assert.equal(r.body.step, 40);
});

/** The byte offsets of the records of a journal (u32 length, u32 CRC, payload). */
function records(file) {
  const bytes = fs.readFileSync(file);
  const at = [];
  for (let p = 0; p + 8 <= bytes.length; p += 8 + bytes.readUInt32LE(p)) at.push(p);
  return { bytes, at };
}

/** A session with 1 + `edits` journal records, and its acknowledged summaries. */
async function journaled(base, seed, edits) {
  const { body } = await api(base, 'POST', '/v1/sessions', { seed });
  const acked = [body];
  for (let i = 0; i < edits; i++)
    acked.push((await api(base, 'POST', `/v1/sessions/${body.id}/edits`, { op: 'step', count: 1 })).body);
  return { id: body.id, acked };
}

function assertQuarantined(r, id) {
  assert.equal(r.status, 503);
  assert.match(r.headers.get('content-type'), /application\/problem\+json/);
  assert.equal(r.body.type, 'urn:meristem:problem:quarantined');
  assert.ok(r.body.detail.includes(id), r.body.detail);
}

const damages = {
  'a flipped byte in': (bytes, at) => { bytes[at[2] + 8 + 5] ^= 0x20; return bytes; },
  'a corrupt length of': (bytes, at) => { bytes.writeUInt32LE(bytes.readUInt32LE(at[2]) + 40, at[2]); return bytes; },
  'a cut inside': (bytes, at) => Buffer.concat([bytes.subarray(0, at[2] + 12), bytes.subarray(at[2] + 20)]),
};

for (const [what, damage] of Object.entries(damages)) {
  test(`${what} record 3 of 8 quarantines the session and keeps every byte`, async (t) => {
    const dataDir = freshDir();
    t.after(() => fs.rmSync(dataDir, { recursive: true, force: true }));
    let d = await startDaemon([], { dataDir });
    const bad = await journaled(d.url, 3, 7);
    const good = await journaled(d.url, 4, 2);
    await d.stop();
    const file = path.join(dataDir, `${bad.id}.journal`);
    const { bytes, at } = records(file);
    assert.equal(at.length, 8);
    const damaged = damage(Buffer.from(bytes), at);
    fs.writeFileSync(file, damaged);

    d = await startDaemon([], { dataDir });
    t.after(() => d.stop());
    await d.waitForLog(/restored \d+ sessions/);  // in the background
    await d.waitForLog(/QUARANTINED/);  // stderr, which may be read after stdout
    // Moved aside byte for byte, not cut.
    assert.ok(!fs.existsSync(file));
    const kept = path.join(dataDir, 'quarantine', `${bad.id}.journal`);
    assert.ok(fs.readFileSync(kept).equals(damaged), 'the quarantined journal is byte for byte the same');
    assert.equal(d.log().match(/QUARANTINED/g).length, 1, d.log());
    assert.doesNotMatch(d.log(), /torn/);
    // Not served, for any request; the others are.
    assertQuarantined(await api(d.url, 'GET', `/v1/sessions/${bad.id}`), bad.id);
    assertQuarantined(await api(d.url, 'POST', `/v1/sessions/${bad.id}/edits`, { op: 'step', count: 1 }), bad.id);
    assertQuarantined(await api(d.url, 'GET', `/v1/sessions/${bad.id}/snapshot.glb`), bad.id);
    assertQuarantined(await api(d.url, 'DELETE', `/v1/sessions/${bad.id}`), bad.id);
    assert.equal((await api(d.url, 'GET', `/v1/sessions/${good.id}`)).body.hash, good.acked[2].hash);
    const list = (await api(d.url, 'GET', '/v1/sessions')).body.sessions;
    const item = list.find((s) => s.id === bad.id);
    assert.equal(item.state, 'quarantined');
    assert.match(item.reason, new RegExp(`^record 2 \\(byte \\d+\\) of ${bad.id}\\.journal is damaged`));
    assert.ok(!item.reason.includes(dataDir), 'the data folder is not shown to clients');
    assert.ok(list.some((s) => s.id === good.id && s.state === 'loaded'));
    // Still quarantined after another restart, without a second alarm.
    await d.stop();
    d = await startDaemon([], { dataDir });
    assertQuarantined(await api(d.url, 'GET', `/v1/sessions/${bad.id}`), bad.id);
    assert.doesNotMatch(d.log(), /QUARANTINED/);
    assert.ok(fs.readFileSync(kept).equals(damaged));
  });
}

test('a journal that is a FIFO or a symbolic link is refused, not opened', async (t) => {
  const dataDir = freshDir();
  const outside = freshDir();
  t.after(() => fs.rmSync(dataDir, { recursive: true, force: true }));
  t.after(() => fs.rmSync(outside, { recursive: true, force: true }));
  let d = await startDaemon([], { dataDir });
  const linked = await journaled(d.url, 5, 2);
  const good = await journaled(d.url, 6, 1);
  await d.stop();
  // The linked-to file has a torn tail, which a followed link would cut.
  const target = path.join(outside, 'elsewhere.journal');
  const whole = fs.readFileSync(path.join(dataDir, `${linked.id}.journal`));
  const torn = whole.subarray(0, whole.length - 5);
  fs.writeFileSync(target, torn);
  fs.rmSync(path.join(dataDir, `${linked.id}.journal`));
  fs.symlinkSync(target, path.join(dataDir, `${linked.id}.journal`));
  const fifo = 'f'.repeat(32);
  require('node:child_process').execFileSync('mkfifo', [path.join(dataDir, `${fifo}.journal`)]);

  d = await startDaemon([], { dataDir });
  t.after(() => d.stop());
  assert.ok(fs.readFileSync(target).equals(torn), 'the file a link points to is untouched');
  assertQuarantined(await api(d.url, 'GET', `/v1/sessions/${linked.id}`), linked.id);
  assertQuarantined(await api(d.url, 'GET', `/v1/sessions/${fifo}`), fifo);
  await d.waitForLog(/not a regular file/);  // stderr may lag: wait for the line
  assert.equal((await api(d.url, 'GET', `/v1/sessions/${good.id}`)).body.revision, 1);
  const r = await api(d.url, 'POST', `/v1/sessions/${good.id}/edits`, { op: 'step', count: 1 });
  assert.equal(r.body.revision, 2);
  assert.ok(fs.readFileSync(target).equals(torn));
});

test('DELETE during a running edit removes the journal before answering 204', async (t) => {
  const dataDir = freshDir();
  t.after(() => fs.rmSync(dataDir, { recursive: true, force: true }));
  let d = await startDaemon([], { dataDir });
  const { body: { id } } = await api(d.url, 'POST', '/v1/sessions', { preset: 'fig7-bh-0.54', seed: 1 });
  const file = path.join(dataDir, `${id}.journal`);
  const edit = api(d.url, 'POST', `/v1/sessions/${id}/edits`, { op: 'step', count: 200 }).catch(() => null);
  let running = false;
  for (let i = 0; i < 400 && !running; i++) {
    running = (await api(d.url, 'GET', `/v1/sessions/${id}`)).body.running.active;
    if (!running) await new Promise((res) => setTimeout(res, 5));
  }
  assert.ok(running, 'the edit was running');
  assert.equal((await api(d.url, 'DELETE', `/v1/sessions/${id}`)).status, 204);
  assert.ok(!fs.existsSync(file), 'the journal is gone when DELETE answers');
  d.child.kill('SIGKILL');
  await edit;
  await d.stop();
  d = await startDaemon([], { dataDir });
  t.after(() => d.stop());
  assert.equal((await api(d.url, 'GET', `/v1/sessions/${id}`)).status, 404);
  assert.ok(!fs.existsSync(file), 'the running edit did not write the journal back');
  assert.equal((await api(d.url, 'GET', '/v1/sessions')).body.sessions.length, 0);
});

test('an edit that ends after its session was deleted does not write the journal back', async (t) => {
  const d = await startDaemon([]);
  t.after(() => d.stop());
  const { body: { id } } = await api(d.url, 'POST', '/v1/sessions', { preset: 'fig7-bh-0.54', seed: 2 });
  const file = path.join(d.dataDir, `${id}.journal`);
  const edit = api(d.url, 'POST', `/v1/sessions/${id}/edits`, { op: 'step', count: 200 });
  let running = false;
  for (let i = 0; i < 400 && !running; i++) {
    running = (await api(d.url, 'GET', `/v1/sessions/${id}`)).body.running.active;
    if (!running) await new Promise((res) => setTimeout(res, 5));
  }
  assert.equal((await api(d.url, 'DELETE', `/v1/sessions/${id}`)).status, 204);
  const r = await edit;
  assert.equal(r.status, 404);
  assert.ok(!fs.existsSync(file));
  assert.equal(fs.readdirSync(d.dataDir).filter((f) => f.endsWith('.journal')).length, 0);
});

test('a journal cut short in its creation record is dropped: it was never acknowledged', async (t) => {
  const dataDir = freshDir();
  t.after(() => fs.rmSync(dataDir, { recursive: true, force: true }));
  let d = await startDaemon([], { dataDir });
  const { id } = await journaled(d.url, 7, 0);
  await d.stop();
  const file = path.join(dataDir, `${id}.journal`);
  const whole = fs.readFileSync(file);
  const empty = path.join(dataDir, `${'e'.repeat(32)}.journal`);
  fs.writeFileSync(empty, '');
  fs.writeFileSync(file, whole.subarray(0, whole.length - 3));
  d = await startDaemon([], { dataDir });
  t.after(() => d.stop());
  await d.waitForLog(/restored 0 sessions/);  // in the background
  // Those lines go to stderr and may be read after stdout's: wait for both.
  await d.waitForLog(/dropped a torn first record[\s\S]*dropped a torn first record/);
  assert.equal(d.log().match(/dropped a torn first record/g).length, 2, d.log());
  assert.doesNotMatch(d.log(), /QUARANTINED/);
  assert.ok(!fs.existsSync(file) && !fs.existsSync(empty));
  assert.equal((await api(d.url, 'GET', `/v1/sessions/${id}`)).status, 404);
  assert.deepEqual((await api(d.url, 'GET', '/v1/sessions')).body.sessions, []);
});

test('an edit whose record cannot be written (a full disk) answers 503 journal and is not kept', async (t) => {
  const dataDir = freshDir();
  let d = null;
  t.after(async () => { if (d) await d.stop(); fs.rmSync(dataDir, { recursive: true, force: true }); });
  // The third write fails: the creation and one edit are written, the next is not.
  process.env.MERISTEMD_TEST_FAIL_WRITE = '3';
  try {
    d = await startDaemon(['--checkpoint-every', '0'], { dataDir });
  } finally {
    delete process.env.MERISTEMD_TEST_FAIL_WRITE;
  }
  const { body: { id } } = await api(d.url, 'POST', '/v1/sessions', { seed: 4 });
  const edit = { op: 'step', count: 2 };
  const first = await api(d.url, 'POST', `/v1/sessions/${id}/edits`, edit);
  assert.equal(first.status, 200);
  const refused = await api(d.url, 'POST', `/v1/sessions/${id}/edits`, edit);
  assert.equal(refused.status, 503, JSON.stringify(refused.body));
  assert.match(refused.headers.get('content-type'), /application\/problem\+json/);
  assert.equal(refused.body.type, 'urn:meristem:problem:journal');
  const after = (await api(d.url, 'GET', `/v1/sessions/${id}`)).body;
  assert.equal(after.revision, first.body.revision, 'nothing acknowledged');
  assert.equal(after.hash, first.body.hash, 'the tree put back');
  // The disk has room again: the same edit takes the revision the refused one did not.
  const again = await api(d.url, 'POST', `/v1/sessions/${id}/edits`, edit);
  assert.equal(again.status, 200);
  assert.equal(again.body.revision, first.body.revision + 1);
  d = await d.restart(['--checkpoint-every', '0']);
  const restored = (await api(d.url, 'GET', `/v1/sessions/${id}`)).body;
  assert.equal(restored.revision, again.body.revision);
  assert.equal(restored.hash, again.body.hash);
});
