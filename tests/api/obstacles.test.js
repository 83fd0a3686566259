'use strict';
// An uploaded glTF obstacle whose work on the scene is unbounded (a mesh in raw
// quantized units: cells thousands of voxels wide where the scene asks) is
// refused with 422 problem+json naming its field, not voxelized for seconds.
const test = require('node:test');
const assert = require('node:assert/strict');
const { startDaemon, api } = require('../support/daemon.js');

// A .gltf with an embedded buffer: a cube [lo, hi]³, 12 triangles, not indexed.
function cubeGltf(lo, hi) {
  const v = (i) => [(i & 1) ? hi : lo, (i & 2) ? hi : lo, (i & 4) ? hi : lo];
  const quads = [[0, 4, 6, 2], [1, 3, 7, 5], [0, 1, 5, 4], [2, 6, 7, 3], [0, 2, 3, 1], [4, 5, 7, 6]];
  const xyz = [];
  for (const q of quads) for (const k of [0, 1, 2, 0, 2, 3]) xyz.push(...v(q[k]));
  const bytes = Buffer.from(new Float32Array(xyz).buffer);
  const doc = {
    asset: { version: '2.0' },
    buffers: [{ byteLength: bytes.length, uri: `data:application/octet-stream;base64,${bytes.toString('base64')}` }],
    bufferViews: [{ buffer: 0, byteLength: bytes.length }],
    accessors: [{ bufferView: 0, componentType: 5126, count: xyz.length / 3, type: 'VEC3',
      min: [lo, lo, lo], max: [hi, hi, hi] }],
    meshes: [{ primitives: [{ attributes: { POSITION: 0 } }] }],
    nodes: [{ mesh: 0 }],
    scenes: [{ nodes: [0] }],
    scene: 0,
  };
  return Buffer.from(JSON.stringify(doc)).toString('base64');
}

test('a glTF obstacle in raw quantized units is refused with 422 naming its field', async (t) => {
  const d = await startDaemon(['--quiet']);
  t.after(() => d.stop());
  const r = await api(d.url, 'POST', '/v1/sessions',
    { scene: { obstacles: [{ gltf: cubeGltf(-1, 65535) }] } });
  assert.equal(r.status, 422);
  assert.match(r.headers.get('content-type'), /application\/problem\+json/);
  assert.equal(r.body.type, 'urn:meristem:problem:out-of-range');
  assert.match(r.body.field, /^scene\.obstacles\[0\]\.gltf/);
  assert.match(r.body.detail, /too coarse/);
  // The same cube in the scene's units is taken.
  const ok = await api(d.url, 'POST', '/v1/sessions',
    { scene: { obstacles: [{ gltf: cubeGltf(-20, 20) }] } });
  assert.equal(ok.status, 201);
});
