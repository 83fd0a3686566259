'use strict';
// A step that grows nothing says why (the summary's `stalled`), and a bend's `spread`:
// new bends get the default written into their journal record, and a record without it
// (written before `spread` existed) still replays as the elbow it was.
const { test, before, after } = require('node:test');
const assert = require('node:assert/strict');
const fs = require('node:fs');
const os = require('node:os');
const path = require('node:path');
const zlib = require('node:zlib');
const { startDaemon, api } = require('../support/daemon.js');

let d;
const J = (method, p, body) => api(d.url, method, p, body);
const dataDir = fs.mkdtempSync(path.join(os.tmpdir(), 'meristem-stall-'));
before(async () => { d = await startDaemon(['--quiet'], { dataDir }); });
after(async () => {
  await d.stop();
  fs.rmSync(dataDir, { recursive: true, force: true });
});

async function session(body) {
  const c = await J('POST', '/v1/sessions', body);
  assert.equal(c.status, 201, JSON.stringify(c.body));
  return c.body.id;
}
const edit = async (id, e) => {
  const r = await J('POST', `/v1/sessions/${id}/edits`, e);
  assert.equal(r.status, 200, JSON.stringify(r.body));
  return r.body;
};

test('a step that grows nothing says why, and one that grows says nothing', async () => {
  const grows = await session({ preset: 'default', seed: 1 });
  const s = await edit(grows, { op: 'step', count: 3 });
  assert.ok(s.internodes > 1);
  assert.equal(s.stalled, undefined, 'no stalled key when the step grew');

  // Space colonization without a marker: nothing to grow towards.
  const bare = await session({ preset: 'fig4-colonization', seed: 1, params: { marker_count: 0 } });
  const a = await edit(bare, { op: 'step', count: 2 });
  assert.equal(a.steps_done, 2);
  assert.deepEqual(a.stalled, { reason: 'no-markers', node: null });
  // Constrained to a bud that has nothing to grow towards either: the constraint is named first.
  await edit(bare, { op: 'add_markers', center: [0, 40, 0], radius: 0.5, pressure: 0.1, constrain: { node: 0, bud: 1 } });
  const b = await edit(bare, { op: 'step' });
  assert.deepEqual(b.stalled, { reason: 'constrained', node: 0 });
  const r = await edit(bare, { op: 'release' });
  assert.equal(r.stalled, undefined, 'an edit that is not a step reports no stall');
  assert.equal(r.constraint, null);

  // A model that has grown all it will says it is done, not that it lacks light.
  const guided = await session({ preset: 'gv-fig3-sphere', seed: 1, params: { gv_iterations: 1 } });
  const g = await edit(guided, { op: 'step', count: 2 });
  assert.equal(g.steps_done, 2);
  assert.deepEqual(g.stalled, { reason: 'done', node: null });
  const ls = await session({ model: 'lsystem', lsystem: { source: 'derivation length: 1\naxiom: F\nF -> FF\n' } });
  const l = await edit(ls, { op: 'step', count: 2 });
  assert.deepEqual(l.stalled, { reason: 'done', node: null });
});

test('a bend spreads over the default internodes, and the journal says so', async () => {
  const id = await session({ preset: 'default', seed: 4 });
  await edit(id, { op: 'step', count: 7 });
  const elbow = await session({ preset: 'default', seed: 4 });
  await edit(elbow, { op: 'step', count: 7 });
  const bend = { op: 'bend', node: 2, axis: [0, 0, 1], angle: 25 };
  const curved = await edit(id, bend);
  const one = await edit(elbow, { ...bend, spread: 1 });
  assert.notEqual(curved.hash, one.hash, 'the default is not the elbow');
  const three = await session({ preset: 'default', seed: 4 });
  await edit(three, { op: 'step', count: 7 });
  assert.equal((await edit(three, { ...bend, spread: 3 })).hash, curved.hash, 'the default is 3');
  const journal = fs.readFileSync(path.join(dataDir, `${id}.journal`), 'latin1');
  assert.match(journal, /"op":\s*"bend"[^}]*"spread":\s*3/, 'the record holds the spread it was given');
  const bad = await J('POST', `/v1/sessions/${id}/edits`, { ...bend, spread: 0 });
  assert.equal(bad.status, 422);
  assert.equal(bad.body.field, 'spread');
});

/** The records of a journal: [{payload (object)}], and back to bytes. */
function readRecords(file) {
  const b = fs.readFileSync(file), out = [];
  for (let at = 0; at < b.length;) {
    const len = b.readUInt32LE(at);
    out.push(JSON.parse(b.subarray(at + 8, at + 8 + len).toString('utf8')));
    at += 8 + len;
  }
  return out;
}
function writeRecords(file, docs) {
  const parts = docs.map((doc) => {
    const payload = Buffer.from(JSON.stringify(doc));
    const head = Buffer.alloc(8);
    head.writeUInt32LE(payload.length, 0);
    head.writeUInt32LE(zlib.crc32(payload), 4);
    return Buffer.concat([head, payload]);
  });
  fs.writeFileSync(file, Buffer.concat(parts));
}

test('a journaled bend without spread (an old record) replays as the elbow', async () => {
  const id = await session({ preset: 'default', seed: 6 });
  await edit(id, { op: 'step', count: 7 });
  const elbow = await edit(id, { op: 'bend', node: 2, axis: [1, 0, 0], angle: 40, spread: 1 });
  const other = await session({ preset: 'default', seed: 6 });
  await edit(other, { op: 'step', count: 7 });
  const curved = await edit(other, { op: 'bend', node: 2, axis: [1, 0, 0], angle: 40 });
  await d.stop();
  // Take `spread` out of the first session's bend record, as a journal written before it.
  const file = path.join(dataDir, `${id}.journal`);
  const docs = readRecords(file);
  let found = 0;
  for (const doc of docs) for (const e of doc.edits || []) if (e.op === 'bend') { delete e.spread; found++; }
  assert.equal(found, 1);
  writeRecords(file, docs);
  d = await startDaemon(['--quiet'], { dataDir });
  assert.equal((await J('GET', `/v1/sessions/${id}`)).body.hash, elbow.hash, 'an old bend is an elbow');
  assert.equal((await J('GET', `/v1/sessions/${other}`)).body.hash, curved.hash, 'a new one keeps its spread');
});
