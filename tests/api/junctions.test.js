'use strict';
// snapshot.glb?junctions=implicit (issue 18): forks of thick branches as
// implicit patches, a `_RIDGE` attribute, a GLB the Khronos validator passes,
// its own ETag and cache variant; a bad value is a problem+json naming the
// field; the default snapshot is the tubes' one. --patch-threads sets the
// threads one snapshot's patches take, and the bytes do not depend on it; by
// default a snapshot is lent the cores no other snapshot is using.
const { test, before, after } = require('node:test');
const assert = require('node:assert/strict');
const fs = require('node:fs');
const os = require('node:os');
const path = require('node:path');
const { spawnSync } = require('node:child_process');
const { validates } = require('../support/gltf.js');
const { startDaemon, api } = require('../support/daemon.js');

let d;
const J = (method, p, body, headers) => api(d.url, method, p, body, headers);

before(async () => { d = await startDaemon(['--max-steps', '200']); });
after(() => d.stop());

const gltfJson = (b) => JSON.parse(b.subarray(20, 20 + b.readUInt32LE(12)).toString('utf8'));

test('junctions=implicit gives a valid GLB with the ridge; a bad value is refused', async () => {
  const made = await J('POST', '/v1/sessions', { preset: 'fig7-bh-0.54', seed: 7 });
  assert.equal(made.status, 201, JSON.stringify(made.body));
  const id = made.body.id;
  assert.equal((await J('POST', `/v1/sessions/${id}/edits`, { op: 'step', count: 12 })).status, 200);
  const url = `${d.url}/v1/sessions/${id}/snapshot.glb`;
  const plain = await fetch(url);
  const implicit = await fetch(`${url}?junctions=implicit&color=age`);
  assert.equal(implicit.status, 200);
  assert.equal(implicit.headers.get('content-type'), 'model/gltf-binary');
  assert.equal(implicit.headers.get('etag'), '"r1-d3l0m0c3q0t1z0j1"');
  const bytes = Buffer.from(await implicit.arrayBuffer());
  const doc = gltfJson(bytes);
  assert.ok(doc.meshes[0].primitives.every((p) => '_RIDGE' in p.attributes), 'every bark primitive has _RIDGE');
  const plainDoc = gltfJson(Buffer.from(await plain.arrayBuffer()));
  assert.ok(plainDoc.meshes[0].primitives.every((p) => !('_RIDGE' in p.attributes)));
  await validates(bytes);
  if (process.env.MER_ARTIFACTS) fs.writeFileSync(path.join(process.env.MER_ARTIFACTS, 'api-snapshot-junctions.glb'), bytes);
  // tubes is the default, byte for byte.
  const tubes = Buffer.from(await (await fetch(`${url}?junctions=tubes`)).arrayBuffer());
  assert.ok(tubes.equals(Buffer.from(await (await fetch(url)).arrayBuffer())));
  const bad = await J('GET', `/v1/sessions/${id}/snapshot.glb?junctions=blobs`);
  assert.equal(bad.status, 422);
  assert.equal(bad.headers.get('content-type'), 'application/problem+json');
  assert.equal(bad.body.type, 'urn:meristem:problem:out-of-range');
  assert.equal(bad.body.field, 'junctions');
  assert.match(bad.body.detail, /junctions must be tubes or implicit/);
});

// The thread count is each daemon's (--patch-threads, or the cores lent by
// default to each snapshot): a snapshot's bytes are the same whatever it is.
test('implicit junctions give the same bytes whatever --patch-threads; a bad count is refused', async () => {
  const glb = async (daemon) => {
    const call = (method, p, body) => api(daemon.url, method, p, body);
    const made = await call('POST', '/v1/sessions', { preset: 'fig7-bh-0.54', seed: 7 });
    assert.equal(made.status, 201, JSON.stringify(made.body));
    const stepped = await call('POST', `/v1/sessions/${made.body.id}/edits`, { op: 'step', count: 12 });
    assert.equal(stepped.status, 200);
    const res = await fetch(`${daemon.url}/v1/sessions/${made.body.id}/snapshot.glb?junctions=implicit`);
    assert.equal(res.status, 200);
    // All but the session's id (asset.extras), which each daemon makes anew.
    const bytes = Buffer.from(await res.arrayBuffer());
    const doc = gltfJson(bytes);
    assert.equal(doc.asset.extras.session, made.body.id);
    delete doc.asset.extras.session;
    return Buffer.concat([Buffer.from(JSON.stringify(doc)), bytes.subarray(20 + bytes.readUInt32LE(12))]);
  };
  const auto = await glb(d);
  for (const threads of ['1', '7']) {
    const other = await startDaemon(['--max-steps', '200', '--patch-threads', threads]);
    try {
      assert.ok((await glb(other)).equals(auto), `--patch-threads ${threads} gives the default's bytes`);
    } finally {
      await other.stop();
    }
  }
  const help = spawnSync(process.env.MERISTEMD, ['--help'], { encoding: 'utf8' });
  assert.match(help.stdout, /--patch-threads=VALUE.*\(default 0\) \[0\.\.64\]/);
  const bad = spawnSync(process.env.MERISTEMD, ['--patch-threads', '65'], { encoding: 'utf8' });
  assert.equal(bad.status, 2);
  assert.match(bad.stderr, /--patch-threads wants an integer from 0 to 64, got '65'/);
});

// GET /v1/metrics' lease counters: [snapshots lent cores, threads lent].
const leases = async (daemon) => {
  const text = await (await fetch(`${daemon.url}/v1/metrics`)).text();
  const n = (name) => {
    const m = text.match(new RegExp(`^${name} (\\d+)$`, 'm'));
    return m ? Number(m[1]) : null;
  };
  return [n('meristem_patch_leases_total'), n('meristem_patch_threads_total')];
};

// By default (--patch-threads 0) a snapshot with implicit junctions is lent the
// cores no other snapshot is meshing on: alone, all of them, so one user
// brushing with junctions on no longer waits on one core of an idle machine.
// Tubes take no threads; a fixed --patch-threads lends nothing.
test('a lone implicit snapshot is lent every core; tubes and a fixed --patch-threads are not', async () => {
  // The daemon counts the cores it may run on (its CPU affinity), as Node does here.
  const cores = Math.min(os.availableParallelism(), 64);
  const grow = async (daemon) => {
    const made = await api(daemon.url, 'POST', '/v1/sessions', { preset: 'fig7-bh-0.54', seed: 3 });
    assert.equal(made.status, 201, JSON.stringify(made.body));
    assert.equal((await api(daemon.url, 'POST', `/v1/sessions/${made.body.id}/edits`, { op: 'step', count: 8 })).status, 200);
    return `${daemon.url}/v1/sessions/${made.body.id}/snapshot.glb`;
  };
  const url = await grow(d);
  const [l0, t0] = await leases(d);
  assert.ok(l0 !== null && t0 !== null, 'the lease counters are in /v1/metrics');
  assert.equal((await fetch(url)).status, 200);
  assert.deepEqual(await leases(d), [l0, t0], 'tubes borrow no cores');
  assert.equal((await fetch(`${url}?junctions=implicit`)).status, 200);
  assert.deepEqual(await leases(d), [l0 + 1, t0 + cores], `a lone snapshot is lent all ${cores} cores`);
  assert.equal((await fetch(`${url}?junctions=implicit`)).status, 200); // the cache's: no mesh
  assert.deepEqual(await leases(d), [l0 + 1, t0 + cores]);
  const fixed = await startDaemon(['--max-steps', '200', '--patch-threads', '1']);
  try {
    const u = await grow(fixed);
    assert.equal((await fetch(`${u}?junctions=implicit`)).status, 200);
    assert.deepEqual(await leases(fixed), [0, 0], '--patch-threads 1 lends nothing');
  } finally {
    await fixed.stop();
  }
});
