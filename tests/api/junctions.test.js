'use strict';
// snapshot.glb?junctions=implicit (issue 18): forks of thick branches as
// implicit patches, a `_RIDGE` attribute, a GLB the Khronos validator passes,
// its own ETag and cache variant; a bad value is a problem+json naming the
// field; the default snapshot is the tubes' one.
const { test, before, after } = require('node:test');
const assert = require('node:assert/strict');
const fs = require('node:fs');
const path = require('node:path');
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
