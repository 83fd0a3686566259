'use strict';
// The crash loop: edits stream to several sessions (with deletes and new
// sessions as they go), meristemd is killed with SIGKILL at a random moment and
// restarted on the same data folder, and every acknowledged revision must be
// there with a byte-identical GLB; a 204 DELETE must stay deleted. At the end
// each session is replayed in a fresh session and every revision's GLB is
// compared with the one fetched when it was acknowledged. Checkpoints are
// written often and journals compacted behind them, so restores go through
// them, and a kill may land in a compaction. Restores are lazy: every other
// cycle loads each session on its first request only (--warm-up=off), the
// others race the background loader with the first requests.
//
// CRASH_CYCLES (default 24) sets the cycles, CRASH_SEED the seed (printed, so
// a failure can be replayed: CRASH_SEED=... make check TESTS=...). `make
// crash-loop` runs a thousand cycles.
const test = require('node:test');
const assert = require('node:assert/strict');
const crypto = require('node:crypto');
const fs = require('node:fs');
const os = require('node:os');
const path = require('node:path');
const { startDaemon, api } = require('../support/daemon.js');

const CYCLES = Number(process.env.CRASH_CYCLES || 24);
const SEED = Number(process.env.CRASH_SEED || crypto.randomInt(2 ** 31));
const SESSIONS = 3;
const MAX_REVISION = 10;  // then the session is deleted and another made
// Checkpoints every 3 revisions, so restores in the loop load checkpoints and
// replay the records after them, and a kill may land while one is written or
// while the journal is compacted behind it.
const DAEMON_ARGS = ['--checkpoint-every', '3', '--compact'];
const warmUp = (cycle) => ['--warm-up', cycle % 2 ? 'background' : 'off'];

/** mulberry32: a small seeded generator of numbers in [0, 1). */
function generator(seed) {
  let a = seed >>> 0;
  return () => {
    a = (a + 0x6d2b79f5) >>> 0;
    let t = a;
    t = Math.imul(t ^ (t >>> 15), t | 1);
    t ^= t + Math.imul(t ^ (t >>> 7), t | 61);
    return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
  };
}

const sha = (bytes) => crypto.createHash('sha256').update(bytes).digest('hex');

/** The GLB of the session now and the revision its ETag names; null if it
 * failed. The GLB names its session: `asId` (same length) is put in its place. */
async function glb(base, id, asId = id) {
  const r = await fetch(`${base}/v1/sessions/${id}/snapshot.glb?leaves=1`);
  if (r.status !== 200) return null;
  const bytes = Buffer.from(await r.arrayBuffer());
  for (let at = bytes.indexOf(id); at >= 0; at = bytes.indexOf(id, at + id.length))
    bytes.write(asId, at, 'latin1');
  const m = /^"r(\d+)-/.exec(r.headers.get('etag') || '');
  return m ? { revision: Number(m[1]), sha: sha(bytes) } : null;
}

/** One tracked session: what was acknowledged and the GLB of each revision. */
function slot(k, spec) {
  return { k, spec, id: null, acked: -1, edits: [], inflight: null, deleting: false, glbs: new Map() };
}

function nextEdit(random, k) {
  const r = random();
  if (r < 0.7) return { op: 'step', count: 1 + Math.floor(random() * 2) };
  return { op: 'add_markers', points: [[k + random(), 2 + 6 * random(), random() - 0.5]] };
}

async function remember(base, s) {
  const g = await glb(base, s.id).catch(() => null);
  if (g && g.revision === s.acked && !s.glbs.has(g.revision)) s.glbs.set(g.revision, g.sha);
}

/** Creates the slot's session; an unanswered create leaves the slot empty. */
async function create(base, s) {
  const r = await api(base, 'POST', '/v1/sessions', s.spec);
  if (r.status !== 201) throw new Error(`create answered ${r.status}`);
  Object.assign(s, { id: r.body.id, acked: 0, edits: [], inflight: null, deleting: false, glbs: new Map() });
  await remember(base, s);
}

/** Streams edits to one slot until the daemon dies. */
async function stream(base, s, random, state) {
  for (;;) {
    if (s.id === null) {
      await create(base, s);
      continue;
    }
    if (s.acked >= MAX_REVISION) {
      s.deleting = true;
      const r = await api(base, 'DELETE', `/v1/sessions/${s.id}`);
      assert.equal(r.status, 204);
      state.deleted.push(s.id);
      state.retired.push({ ...s, glbs: s.glbs });
      s.id = null;
      continue;
    }
    const edit = nextEdit(random, s.k);
    s.inflight = edit;
    const r = await api(base, 'POST', `/v1/sessions/${s.id}/edits`, edit);
    assert.equal(r.status, 200, JSON.stringify(r.body));
    assert.equal(r.body.revision, s.acked + 1);
    s.acked = r.body.revision;
    s.edits.push(edit);
    state.acks++;
    s.inflight = null;
    await remember(base, s);
  }
}

/** After a restart: what was acknowledged is there, byte for byte. */
async function verify(base, slots, state, d) {
  // Listed before anything is asked of them: loaded or not, never lost.
  const listed = new Set((await api(base, 'GET', '/v1/sessions')).body.sessions.map((x) => x.id));
  for (const s of slots)
    if (s.id !== null && !s.deleting) assert.ok(listed.has(s.id), `session ${s.id} is not listed`);
  for (const id of state.deleted)
    assert.equal((await api(base, 'GET', `/v1/sessions/${id}`)).status, 404, `deleted ${id} came back`);
  for (const s of slots) {
    if (s.id === null) continue;
    const r = await api(base, 'GET', `/v1/sessions/${s.id}`);
    if (s.deleting && r.status === 404) {  // a DELETE cut short that took effect
      s.id = null;
      continue;
    }
    assert.equal(r.status, 200, `session ${s.id} (acknowledged revision ${s.acked}) is missing`);
    const rev = r.body.revision;
    // Every acknowledged revision is there; at most the edit in flight beyond it.
    if (rev === s.acked + 1 && s.inflight) {
      s.edits.push(s.inflight);
      s.acked = rev;
    }
    assert.equal(rev, s.acked, `session ${s.id}: revision ${rev}, acknowledged ${s.acked}`);
    s.inflight = null;
    s.deleting = false;
    const g = await glb(base, s.id);
    assert.equal(g.revision, rev);
    if (s.glbs.has(rev)) assert.equal(g.sha, s.glbs.get(rev), `session ${s.id} r${rev}: GLB differs`);
    else s.glbs.set(rev, g.sha);
  }
  assert.doesNotMatch(d.log(), /QUARANTINED/);
}

/** Replays a session's acknowledged edits in a fresh session: each revision's GLB as acknowledged. */
async function replay(base, s) {
  const fresh = (await api(base, 'POST', '/v1/sessions', s.spec)).body.id;
  const check = async (rev) => {
    if (!s.glbs.has(rev)) return;
    const g = await glb(base, fresh, s.id);
    assert.equal(g.sha, s.glbs.get(rev), `session ${s.id} r${rev}: GLB differs from a fresh replay`);
  };
  await check(0);
  for (const [i, edit] of s.edits.entries()) {
    const r = await api(base, 'POST', `/v1/sessions/${fresh}/edits`, edit);
    assert.equal(r.body.revision, i + 1);
    await check(i + 1);
  }
  await api(base, 'DELETE', `/v1/sessions/${fresh}`);
}

test(`crash loop: ${CYCLES} kill -9 cycles, CRASH_SEED=${SEED}`, async (t) => {
  console.log(`crash loop: CRASH_SEED=${SEED} CRASH_CYCLES=${CYCLES}`);
  const dataDir = fs.mkdtempSync(path.join(os.tmpdir(), 'meristem-crashloop-'));
  t.after(() => fs.rmSync(dataDir, { recursive: true, force: true }));
  const random = generator(SEED);
  const slots = Array.from({ length: SESSIONS }, (_, k) => slot(k, { seed: k + 1 }));
  const state = { deleted: [], retired: [], acks: 0 };
  for (let cycle = 0; cycle < CYCLES; cycle++) {
    const d = await startDaemon([...DAEMON_ARGS, ...warmUp(cycle)], { dataDir });
    try {
      await verify(d.url, slots, state, d);
    } catch (e) {
      await d.stop('SIGKILL');
      e.message = `cycle ${cycle} (CRASH_SEED=${SEED}): ${e.message}\n${d.log()}`;
      throw e;
    }
    const streams = slots.map((s) => stream(d.url, s, generator(SEED + cycle * 31 + s.k), state)
      .catch((e) => { if (e instanceof assert.AssertionError) throw e; }));
    // A random moment once this cycle's streams are going (on a busy machine the
    // first acknowledgement may take longer than the whole window).
    const acks = state.acks;
    for (let waited = 0; state.acks === acks && waited < 5000; waited += 10)
      await new Promise((res) => setTimeout(res, 10));
    await new Promise((res) => setTimeout(res, random() * 400));
    d.child.kill('SIGKILL');
    await Promise.all(streams);
    await d.stop();
  }
  const d = await startDaemon(DAEMON_ARGS, { dataDir });
  t.after(() => d.stop());
  await verify(d.url, slots, state, d);
  for (const s of [...state.retired, ...slots.filter((x) => x.id !== null)]) await replay(d.url, s);
  console.log(`${CYCLES} cycles: ${state.acks} edits acknowledged, ${state.deleted.length} ` +
    `sessions deleted, ${state.retired.length + SESSIONS} replayed`);
  assert.ok(state.acks >= CYCLES, `the streams got going (${state.acks} edits acknowledged)`);
});
