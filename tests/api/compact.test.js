'use strict';
// Compaction (--compact): once a checkpoint is on disk, the journal keeps only
// its first record (marked with the checkpoint's revision) and the records
// after it. Every crash state of the rewrite restores every acknowledged
// revision, to the bytes of a session replayed from scratch without
// checkpoints; a journal whose records skip revisions that no checkpoint holds
// is quarantined, never served short.
const test = require('node:test');
const assert = require('node:assert/strict');
const fs = require('node:fs');
const os = require('node:os');
const path = require('node:path');
const { startDaemon, api } = require('../support/daemon.js');

const freshDir = () => fs.mkdtempSync(path.join(os.tmpdir(), 'meristem-compact-'));
const SPEC = { preset: 'fig4-colonization', seed: 5 };
const edit = (i) => (i % 4 === 3 ? { op: 'add_markers', points: [[1, 5 + i, 0], [-1, 6, 1]] } : { op: 'step', count: 2 });

/** The records of a journal as parsed JSON. */
function journal(file) {
  const bytes = fs.readFileSync(file);
  const out = [];
  for (let p = 0; p + 8 <= bytes.length; p += 8 + bytes.readUInt32LE(p))
    out.push(JSON.parse(bytes.subarray(p + 8, p + 8 + bytes.readUInt32LE(p)).toString('utf8')));
  return out;
}

/** Revision, hash and GLB of a session; the GLB with its id put as `asId`
 * (the GLB names its session). */
async function look(base, id, asId = id) {
  const s = await api(base, 'GET', `/v1/sessions/${id}`);
  assert.equal(s.status, 200, JSON.stringify(s.body));
  const g = await fetch(`${base}/v1/sessions/${id}/snapshot.glb?leaves=1`);
  assert.equal(g.status, 200);
  const glb = Buffer.from(await g.arrayBuffer());
  for (let at = glb.indexOf(id); at >= 0; at = glb.indexOf(id, at + id.length)) glb.write(asId, at, 'latin1');
  return { revision: s.body.revision, hash: s.body.hash, glb };
}

function same(a, b, what) {
  assert.equal(a.revision, b.revision, what);
  assert.equal(a.hash, b.hash, what);
  assert.ok(a.glb.equals(b.glb), `${what}: byte-identical GLB`);
}

/** Each revision 0..n of SPEC with edit(i), replayed from scratch without checkpoints. */
async function fromScratch(n, asId) {
  const d = await startDaemon(['--checkpoint-every', '0']);
  try {
    const { body: { id } } = await api(d.url, 'POST', '/v1/sessions', SPEC);
    const out = [await look(d.url, id, asId)];
    for (let i = 0; i < n; i++) {
      assert.equal((await api(d.url, 'POST', `/v1/sessions/${id}/edits`, edit(i))).status, 200);
      out.push(await look(d.url, id, asId));
    }
    return out;
  } finally {
    await d.stop();
  }
}

test('the journal keeps only the records after the last checkpoint, and restores to the same bytes', async (t) => {
  const dataDir = freshDir();
  let d = null;
  t.after(async () => { if (d) await d.stop(); fs.rmSync(dataDir, { recursive: true, force: true }); });
  const args = ['--checkpoint-every', '3', '--compact'];
  d = await startDaemon(args, { dataDir });
  const { body: { id } } = await api(d.url, 'POST', '/v1/sessions', SPEC);
  for (let i = 0; i < 8; i++) assert.equal((await api(d.url, 'POST', `/v1/sessions/${id}/edits`, edit(i))).status, 200);
  const file = path.join(dataDir, `${id}.journal`);
  const records = journal(file);
  assert.equal(records[0].checkpoint, 6, 'the first record names the checkpoint it relies on');
  assert.deepEqual(records.slice(1).map((r) => r.revision), [7, 8]);
  const scratch = await fromScratch(9, id);
  same(await look(d.url, id), scratch[8], 'compacted, live');
  d = await d.restart(args);
  same(await look(d.url, id), scratch[8], 'compacted, restored after kill -9');
  await d.waitForLog(new RegExp(`${id}: restored from its checkpoint at revision 6 and 2 journal records`));  // stderr may lag: wait for the line
  assert.equal((await api(d.url, 'POST', `/v1/sessions/${id}/edits`, edit(8))).body.revision, 9);
  assert.deepEqual(journal(file).map((r) => r.revision), [undefined], 'compacted again at 9');
  assert.equal(journal(file)[0].checkpoint, 9);
  same(await look(d.url, id), scratch[9], 'after the next compaction');
  d = await d.restart(args);
  same(await look(d.url, id), scratch[9], 'a journal of its first record alone');
});

test('every crash state of a compaction restores every acknowledged revision', async (t) => {
  const dataDir = freshDir();
  let d = null;
  t.after(async () => { if (d) await d.stop(); fs.rmSync(dataDir, { recursive: true, force: true }); });
  const ZERO = '0'.repeat(32);
  const scratch = await fromScratch(13, ZERO);
  // Without --compact, then kill -9: the state a crash leaves after the
  // checkpoint of 9 and before the rewritten journal is renamed in; with a
  // half-written temporary file beside it.
  d = await startDaemon(['--checkpoint-every', '3'], { dataDir });
  const { body: { id } } = await api(d.url, 'POST', '/v1/sessions', SPEC);
  for (let i = 0; i < 9; i++) await api(d.url, 'POST', `/v1/sessions/${id}/edits`, edit(i));
  await d.stop('SIGKILL');
  const file = path.join(dataDir, `${id}.journal`);
  const checkpoint = path.join(dataDir, `${id}.checkpoint`);
  const whole = fs.readFileSync(file);
  fs.writeFileSync(`${file}.tmp`, whole.subarray(0, 20));
  const args = ['--checkpoint-every', '3', '--compact'];
  const at = async (rev, what) => same(await look(d.url, id, ZERO), scratch[rev], what);
  d = await startDaemon(args, { dataDir });
  await at(9, 'the old journal and the new checkpoint');
  // Edits go on, and at 12 it compacts (the stale temporary file goes).
  for (let i = 9; i < 12; i++) await api(d.url, 'POST', `/v1/sessions/${id}/edits`, edit(i));
  assert.equal(journal(file).length, 1);
  assert.equal(journal(file)[0].checkpoint, 12);
  assert.ok(!fs.existsSync(`${file}.tmp`));
  await at(12, 'compacted');
  // After the rename: the new journal and its checkpoint.
  d = await d.restart(args);
  await at(12, 'the new journal after kill -9');
  assert.equal((await api(d.url, 'POST', `/v1/sessions/${id}/edits`, edit(12))).body.revision, 13);
  await at(13, 'an edit after it');
  let compacted = null;
  d = await d.restart(args, { whileDown: () => { compacted = fs.readFileSync(file); } });
  await at(13, 'and after another kill -9');
  await d.stop();

  // A journal that starts at revision 1 behind a later checkpoint (a power cut
  // took its tail) is trusted whole; a compacted one behind an older
  // checkpoint than it relies on is quarantined.
  const ckpt12 = fs.readFileSync(checkpoint);
  fs.writeFileSync(file, whole);
  d = await startDaemon(args, { dataDir });
  await at(9, 'an uncompacted journal behind its checkpoint');
  await d.stop();
  fs.writeFileSync(file, compacted);
  fs.writeFileSync(checkpoint, ckpt12);
  d = await startDaemon(args, { dataDir });
  await at(13, 'the compacted journal and its checkpoint put back');
});

test('a journal that skips revisions no checkpoint holds is quarantined, not served short', async (t) => {
  const dataDir = freshDir();
  let d = null;
  t.after(async () => { if (d) await d.stop(); fs.rmSync(dataDir, { recursive: true, force: true }); });
  d = await startDaemon(['--checkpoint-every', '3', '--compact'], { dataDir });
  const a = (await api(d.url, 'POST', '/v1/sessions', SPEC)).body.id;
  const b = (await api(d.url, 'POST', '/v1/sessions', SPEC)).body.id;
  for (let i = 0; i < 4; i++) {
    await api(d.url, 'POST', `/v1/sessions/${a}/edits`, edit(i));
    await api(d.url, 'POST', `/v1/sessions/${b}/edits`, edit(i));
  }
  await d.stop();
  // a: compacted at 3, its checkpoint lost. b: a journal whose first record is 4, no checkpoint.
  fs.rmSync(path.join(dataDir, `${a}.checkpoint`));
  const fileB = path.join(dataDir, `${b}.journal`);
  const [header] = journal(fileB);
  delete header.checkpoint;
  const payload = Buffer.from(JSON.stringify(header));
  const head = Buffer.alloc(8);
  head.writeUInt32LE(payload.length, 0);
  head.writeUInt32LE(require('node:zlib').crc32(payload), 4);
  const bytes = fs.readFileSync(fileB);
  const rest = bytes.subarray(8 + bytes.readUInt32LE(0));
  fs.writeFileSync(fileB, Buffer.concat([head, payload, rest]));
  fs.rmSync(path.join(dataDir, `${b}.checkpoint`));
  const kept = fs.readFileSync(fileB);

  d = await startDaemon(['--checkpoint-every', '3', '--compact'], { dataDir });
  for (const id of [a, b]) {
    const r = await api(d.url, 'GET', `/v1/sessions/${id}`);
    assert.equal(r.status, 503, `${id}: ${JSON.stringify(r.body)}`);
    assert.equal(r.body.type, 'urn:meristem:problem:quarantined');
  }
  const list = (await api(d.url, 'GET', '/v1/sessions')).body.sessions;
  assert.match(list.find((s) => s.id === a).reason, /compacted to revision 3 and no checkpoint holds it/);
  assert.match(list.find((s) => s.id === b).reason, /revision 4 follows revision 0/);
  assert.ok(fs.readFileSync(path.join(dataDir, 'quarantine', `${b}.journal`)).equals(kept), 'kept byte for byte');
});

test('a quarantined compacted journal takes its checkpoint with it', async (t) => {
  const dataDir = freshDir();
  let d = null;
  t.after(async () => { if (d) await d.stop(); fs.rmSync(dataDir, { recursive: true, force: true }); });
  const args = ['--checkpoint-every', '3', '--compact'];
  d = await startDaemon(args, { dataDir });
  const id = (await api(d.url, 'POST', '/v1/sessions', SPEC)).body.id;
  for (let i = 0; i < 6; i++)
    assert.equal((await api(d.url, 'POST', `/v1/sessions/${id}/edits`, edit(i))).status, 200);
  await d.stop();
  const file = path.join(dataDir, `${id}.journal`);
  const checkpoint = path.join(dataDir, `${id}.checkpoint`);
  const records = journal(file);
  assert.equal(records[0].checkpoint, 6, 'compacted');
  // One more edit after the compaction, then a byte flipped inside the
  // record before the last: damage with a whole record after it.
  d = await startDaemon(args, { dataDir });
  assert.equal((await api(d.url, 'POST', `/v1/sessions/${id}/edits`, edit(6))).status, 200);
  assert.equal((await api(d.url, 'POST', `/v1/sessions/${id}/edits`, edit(7))).status, 200);
  await d.stop();
  const bytes = fs.readFileSync(file);
  const second = 8 + bytes.readUInt32LE(0);
  bytes[second + 8 + 2] ^= 0x20;
  fs.writeFileSync(file, bytes);
  const ckpt = fs.readFileSync(checkpoint);

  d = await startDaemon(args, { dataDir });
  const r = await api(d.url, 'GET', `/v1/sessions/${id}`);
  assert.equal(r.status, 503, JSON.stringify(r.body));
  assert.equal(r.body.type, 'urn:meristem:problem:quarantined');
  const aside = path.join(dataDir, 'quarantine');
  assert.ok(fs.readFileSync(path.join(aside, `${id}.journal`)).equals(bytes), 'journal kept byte for byte');
  assert.ok(fs.readFileSync(path.join(aside, `${id}.checkpoint`)).equals(ckpt), 'its checkpoint beside it');
  assert.ok(!fs.existsSync(checkpoint), 'no checkpoint left behind for a session that is not served');
});
