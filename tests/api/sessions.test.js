'use strict';
// Sessions over HTTP against a real meristemd: every route and edit op, every
// refusal with its status and problem body (and the session unchanged after it),
// all-or-none batches, ETag/304, GLB replies, cancel.
const { test, before, after } = require('node:test');
const assert = require('node:assert/strict');
const fs = require('node:fs');
const path = require('node:path');
const { startDaemon, api } = require('../support/daemon.js');

let d;
const J = (method, p, body, headers) => api(d.url, method, p, body, headers);
const artifact = (name, bytes) => fs.writeFileSync(path.join(process.env.MER_ARTIFACTS, name), bytes);

before(async () => { d = await startDaemon(['--max-steps', '200', '--max-markers', '30000']); });
after(() => d.stop());

async function create(body = {}) {
  const r = await J('POST', '/v1/sessions', body);
  assert.equal(r.status, 201, JSON.stringify(r.body));
  return r;
}

// The state a refused request must leave untouched.
async function state(id) {
  const r = await J('GET', `/v1/sessions/${id}`);
  return { revision: r.body.revision, hash: r.body.hash, step: r.body.step };
}

function problem(r, status, slug, detail, field) {
  assert.equal(r.status, status, JSON.stringify(r.body));
  assert.equal(r.headers.get('content-type'), 'application/problem+json');
  assert.equal(r.body.status, status);
  assert.equal(r.body.type, `urn:meristem:problem:${slug}`);
  assert.ok(r.body.title);
  if (detail) assert.match(r.body.detail, detail);
  if (field !== undefined) assert.equal(r.body.field, field);
}

test('POST /v1/sessions with {} gives the default preset, seed 0', async () => {
  const r = await create();
  assert.match(r.headers.get('location'), /^\/v1\/sessions\/[0-9a-f]{32}$/);
  assert.equal(r.headers.get('meristem-revision'), '0');
  const s = r.body;
  assert.equal(s.id, r.headers.get('location').split('/').pop());
  assert.equal(s.revision, 0);
  assert.equal(s.step, 0);
  assert.equal(s.preset, 'default');
  assert.equal(s.seed, 0);
  assert.equal(s.plants, 1);
  assert.equal(typeof s.params.lambda, 'number');
  assert.equal(s.schedule.apical_off.length, 8);
  assert.deepEqual(s.running, { active: false, done: 0, total: 0 });
  // An empty body is {} too, for curl users.
  const e = await fetch(`${d.url}/v1/sessions`, { method: 'POST' });
  assert.equal(e.status, 201);
});

test('"model" names the growth model: "p09" is the default, an unknown one is refused', async () => {
  const plain = await create({ seed: 5 });
  const named = await create({ model: 'p09', seed: 5 });
  assert.equal(named.body.hash, plain.body.hash);
  for (const id of [plain.body.id, named.body.id]) {
    const r = await J('POST', `/v1/sessions/${id}/edits`, { op: 'step', count: 4 });
    assert.equal(r.status, 200);
  }
  const a = await state(plain.body.id), b = await state(named.body.id);
  assert.equal(a.hash, b.hash);
  problem(await J('POST', '/v1/sessions', { model: 'oak' }), 422, 'invalid-field', /use one of p09, runions, lsystem/, 'model');
  problem(await J('POST', '/v1/sessions', { model: 9 }), 422, 'invalid-field', /string/, 'model');
});

test('session ids are random 128-bit values, not counters', async () => {
  const a = (await create()).body.id, b = (await create()).body.id;
  assert.notEqual(a, b);
  let differing = 0;
  for (let i = 0; i < 32; i++) if (a[i] !== b[i]) differing++;
  assert.ok(differing > 16, `${a} vs ${b}`);
});

test('create with a preset, seed, params and a scene', async () => {
  const r = await create({
    preset: 'fig4-colonization', seed: 7, params: { theta: 100, rho: 1.5 },
    scene: {
      plants: [[-5, 0, 0], [5, 0, 0]],
      markers: [{ volume: 'box', center: [0, 10, 0], size: [8, 6, 4], count: 3000 }],
      obstacles: [{ box: { min: [-1, 0, -1], max: [1, 4, 1] } }, { sphere: { center: [0, 20, 0], radius: 2 } }],
    },
  });
  const s = r.body;
  assert.equal(s.preset, 'fig4-colonization');
  assert.equal(s.seed, 7);
  assert.equal(s.plants, 2);
  assert.equal(s.params.theta, 100);
  assert.equal(s.params.rho, 1.5);
  assert.ok(s.markers > 20000, `${s.markers} markers: the preset's and the box's`);
});

// A box as a .gltf with its buffer embedded, base64 as the API wants it.
function boxGltf(min, max) {
  const [a, b] = [min, max];
  const v = [[a[0], a[1], a[2]], [b[0], a[1], a[2]], [b[0], b[1], a[2]], [a[0], b[1], a[2]],
    [a[0], a[1], b[2]], [b[0], a[1], b[2]], [b[0], b[1], b[2]], [a[0], b[1], b[2]]];
  const idx = [0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4, 3, 7, 6, 3, 6, 2, 0, 4, 7, 0, 7, 3, 1, 2, 6, 1, 6, 5];
  const pos = Buffer.from(new Float32Array(v.flat()).buffer);
  const ind = Buffer.from(new Uint16Array(idx).buffer);
  const data = Buffer.concat([pos, ind]);
  const doc = {
    asset: { version: '2.0' }, scene: 0, scenes: [{ nodes: [0] }], nodes: [{ mesh: 0 }],
    meshes: [{ primitives: [{ attributes: { POSITION: 0 }, indices: 1 }] }],
    buffers: [{ byteLength: data.length, uri: `data:application/octet-stream;base64,${data.toString('base64')}` }],
    bufferViews: [{ buffer: 0, byteOffset: 0, byteLength: pos.length }, { buffer: 0, byteOffset: pos.length, byteLength: ind.length }],
    accessors: [{ bufferView: 0, componentType: 5126, count: 8, type: 'VEC3', min: a, max: b },
      { bufferView: 1, componentType: 5123, count: 36, type: 'SCALAR' }],
  };
  return Buffer.from(JSON.stringify(doc)).toString('base64');
}

test('a glTF mesh as an obstacle: a roof stops the tree; as a marker volume', async () => {
  const roof = boxGltf([-30, 6, -30], [30, 7, 30]);
  const open = (await create({ seed: 2 })).body.id;
  const roofed = (await create({ seed: 2, scene: { obstacles: [{ gltf: roof }] } })).body.id;
  const grow = async (id) => (await J('POST', `/v1/sessions/${id}/edits`, { op: 'step', count: 12 })).body;
  const [a, b] = [await grow(open), await grow(roofed)];
  assert.ok(a.height > 8, `open tree ${a.height}`);
  assert.ok(b.height <= 6.01, `the roofed tree stays under the roof: ${b.height}`);
  // A plant inside the mesh is refused, naming the plant.
  problem(await J('POST', '/v1/sessions', { scene: { plants: [[0, 6.5, 0]], obstacles: [{ gltf: roof }] } }),
    422, 'out-of-range', /scene\.plants\[0\]/, 'scene.plants[0]');
  problem(await J('POST', '/v1/sessions', { scene: { obstacles: [{ gltf: 'not base64!' }] } }), 422, 'invalid-field', /base64/, 'scene.obstacles[0].gltf');
  // A radius past float's range has no float to become: refused, not cast.
  problem(await J('POST', '/v1/sessions', { scene: { obstacles: [{ sphere: { center: [0, 20, 0], radius: 1e300 } }] } }),
    422, 'out-of-range', /radius must be a number in \(0, 1e6\]/, 'scene.obstacles[0].sphere.radius');
  problem(await J('POST', '/v1/sessions', { scene: { obstacles: [{ gltf: Buffer.from('{"asset":{}}').toString('base64') }] } }), 422, 'invalid-gltf', /glTF/, 'scene.obstacles[0].gltf');
  // The inside of a mesh filled with markers.
  const base = (await create({ preset: 'fig4-colonization', seed: 1 })).body.markers;
  const filled = (await create({ preset: 'fig4-colonization', seed: 1,
    scene: { markers: [{ gltf: boxGltf([20, 5, 20], [24, 9, 24]), count: 500 }] } })).body.markers;
  assert.equal(filled - base, 500);
});

test('GET /v1/sessions lists sessions; GET /v1/presets lists presets and parameters', async () => {
  const { body: { id } } = await create();
  const list = await J('GET', '/v1/sessions');
  assert.equal(list.status, 200);
  assert.ok(list.body.sessions.some((s) => s.id === id));
  assert.ok(!('params' in list.body.sessions[0]));
  const p = await J('GET', '/v1/presets');
  assert.ok(p.body.presets.length >= 10);
  const lambda = p.body.parameters.find((f) => f.name === 'lambda');
  assert.equal(lambda.symbol, 'λ');
  assert.deepEqual([lambda.min, lambda.max], [0, 1]);
});

test('every edit op, one at a time, moves the revision on', async () => {
  const { body: { id } } = await create({ preset: 'fig7-bh-0.54', seed: 3 });
  const E = (edit) => J('POST', `/v1/sessions/${id}/edits`, edit);
  let r = await E({ op: 'step', count: 8 });
  assert.equal(r.status, 200);
  assert.equal(r.body.revision, 1);
  assert.equal(r.body.step, 8);
  assert.equal(r.headers.get('meristem-revision'), '1');
  const grown = r.body.internodes;

  r = await E({ op: 'add_markers', points: [[0, 30, 0], [1, 31, 0], [2, 32, 1]] });
  assert.equal(r.body.revision, 2);
  assert.equal(r.body.markers, 3);

  r = await E({ op: 'add_markers', center: [0, 25, 0], radius: 3, pressure: 1, count: 40,
    symmetry: { rotational: 3, center: [0, 0, 0], mirror: { point: [0, 0, 0], normal: [1, 0, 0] } } });
  assert.equal(r.body.revision, 3);
  assert.ok(r.body.markers > 3);

  r = await E({ op: 'bend', node: 1, axis: [0, 0, 1], angle: 20 });
  assert.equal(r.body.revision, 4);

  r = await E({ op: 'set_apical_schedule', apical_off: [5, null], lambda_keys: [[0, 0.5], [20, 0.55]] });
  assert.equal(r.body.revision, 5);
  assert.equal(r.body.schedule.apical_off[0], 5);
  assert.equal(r.body.schedule.apical_off[1], null);
  assert.deepEqual(r.body.schedule.lambda_keys, [[0, 0.5], [20, 0.55]]);

  r = await E({ op: 'set_params', params: { xi: 0.25, eta: -0.1 } });
  assert.equal(r.body.params.xi, 0.25);
  assert.ok(Math.abs(r.body.params.eta + 0.1) < 1e-6);

  r = await E({ op: 'prune', node: 1 });
  assert.equal(r.body.revision, 7);
  assert.ok(r.body.internodes < grown, `${r.body.internodes} < ${grown}`);

  r = await E({ op: 'add_markers', center: [0, 3, 0], radius: 2, constrain: { node: 0, bud: 1 } });
  assert.equal(r.status, 200, JSON.stringify(r.body));
  assert.deepEqual(r.body.constraint, { node: 0, bud: 1 });
  r = await E({ op: 'release' });
  assert.equal(r.body.revision, 9);
  assert.equal(r.body.constraint, null);
});

test('a batch applies in order, and all or none', async () => {
  const { body: { id } } = await create({ seed: 4 });
  let r = await J('POST', `/v1/sessions/${id}/edits`, { edits: [{ op: 'step', count: 3 }, { op: 'step', count: 2 }] });
  assert.equal(r.body.step, 5);
  assert.equal(r.body.revision, 1);  // one batch, one revision
  const before = await state(id);
  // The prune fails after the step ran: the step must be undone too.
  r = await J('POST', `/v1/sessions/${id}/edits`, { edits: [{ op: 'step', count: 2 }, { op: 'prune', node: 4000000 }] });
  problem(r, 404, 'unknown-node', /never part of this tree/, 'edits[1].node');
  assert.deepEqual(await state(id), before);
  // A node that was pruned is a conflict, and again nothing changes.
  await J('POST', `/v1/sessions/${id}/edits`, { op: 'prune', node: 1 });
  const pruned = await state(id);
  r = await J('POST', `/v1/sessions/${id}/edits`, { edits: [{ op: 'step', count: 1 }, { op: 'bend', node: 1, axis: [1, 0, 0], angle: 10 }] });
  problem(r, 409, 'dead-node', /pruned or shed/, 'edits[1].node');
  assert.deepEqual(await state(id), pruned);
});

test('refusals: status, problem detail, and nothing changed', async () => {
  const { body: { id } } = await create();
  await J('POST', `/v1/sessions/${id}/edits`, { op: 'step', count: 2 });
  const before = await state(id);
  const E = (body, headers) => J('POST', `/v1/sessions/${id}/edits`, body, headers);

  problem(await E('{"op": "step",\n "count": }'), 400, 'malformed-json', /line 2, column \d+/);
  problem(await E('{"op": "step", "op": "prune"}'), 400, 'malformed-json', /duplicate/);
  problem(await E('['.repeat(40) + ']'.repeat(40)), 400, 'malformed-json', /nested deeper than 32/);
  problem(await E({ op: 'grow' }), 400, 'unknown-op', /unknown op 'grow'/, 'op');
  problem(await E({ op: 'step', count: 1, speed: 2 }), 400, 'unknown-field', /unknown field 'speed'/, 'speed');
  problem(await E({ op: 'step', count: 'ten' }), 422, 'invalid-field', /count must be an integer/, 'count');
  problem(await E({ op: 'step', count: 0 }), 422, 'out-of-range', /from 1 to 200, got 0/, 'count');
  problem(await E({ op: 'step', count: 500 }), 422, 'out-of-range', /from 1 to 200/, 'count');
  problem(await E({ edits: [{ op: 'step', count: 150 }, { op: 'step', count: 100 }] }), 422, 'out-of-range', /--max-steps/);
  problem(await E({ op: 'bend', node: 1, axis: [0, 0, 0], angle: 10 }), 422, 'out-of-range', /zero vector/, 'axis');
  problem(await E({ op: 'add_markers', points: [[0, 1]] }), 422, 'invalid-field', /array of 3 numbers/, 'points[0]');
  problem(await E({ op: 'add_markers', center: [0, 1, 0], radius: 1, pressure: 2 }), 422, 'out-of-range', /pressure must be from/, 'pressure');
  problem(await E({ op: 'add_markers', points: Array.from({ length: 30001 }, () => [0, 1, 0]) }), 422, 'out-of-range', /--max-markers/);
  problem(await J('POST', '/v1/sessions', { scene: { markers: [{ volume: 'box', center: [0, 5, 0], size: [1, 1, 1], count: 30001 }] } }), 422, 'out-of-range', /at most 30000 markers/, 'scene.markers');
  problem(await E({ op: 'set_params', params: { lambda: 1.5 } }), 422, 'out-of-range', /lambda/, 'params.lambda');
  problem(await E({ op: 'set_params', params: { nonsense: 1 } }), 400, 'unknown-field', /unknown parameter/, 'params.nonsense');
  problem(await E({ op: 'set_apical_schedule', lambda_keys: [[5, 0.5], [2, 0.6]] }), 422, 'out-of-range', /increasing step order/);
  problem(await E({ op: 'step', count: 1 }, { 'Content-Type': 'text/plain' }), 415, 'unsupported-media-type', /application\/json/);
  const big = await fetch(`${d.url}/v1/sessions/${id}/edits`, { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: `{"op":"add_markers","points":[${'[0,1,0],'.repeat(1200000)}[0,1,0]]}` });
  assert.equal(big.status, 413);
  assert.equal(big.headers.get('content-type'), 'application/problem+json');
  problem(await J('POST', `/v1/sessions/${'0'.repeat(32)}/edits`, { op: 'step' }), 404, 'unknown-session', /no session/);
  problem(await J('GET', '/v1/sessions/nope'), 404, 'unknown-session');
  const m = await J('PUT', `/v1/sessions/${id}`, {});
  problem(m, 405, 'method-not-allowed');
  assert.equal(m.headers.get('allow'), 'GET, DELETE');
  problem(await J('POST', '/v1/sessions', { preset: 'nope' }), 422, 'invalid-field', /unknown preset/, 'preset');
  problem(await J('POST', '/v1/sessions', { seed: -1 }), 422, 'out-of-range', /seed/, 'seed');
  problem(await J('POST', '/v1/sessions', { colour: 1 }), 400, 'unknown-field', /colour/);
  problem(await J('POST', '/v1/sessions', { scene: { markers: [{ volume: 'torus', center: [0, 0, 0], size: [1, 1, 1], count: 5 }] } }), 422, 'invalid-field', /box, sphere/, 'scene.markers[0].volume');

  assert.deepEqual(await state(id), before);
});

test('snapshots: GLB, ETag by revision and options, 304, options as query', async () => {
  const { body: { id } } = await create({ preset: 'fig7-bh-0.54', seed: 5 });
  await J('POST', `/v1/sessions/${id}/edits`, { op: 'step', count: 10 });
  const url = `${d.url}/v1/sessions/${id}/snapshot.glb`;
  const r = await fetch(url);
  assert.equal(r.status, 200);
  assert.equal(r.headers.get('content-type'), 'model/gltf-binary');
  const etag = r.headers.get('etag');
  assert.equal(etag, '"r1-d3l0m0c0q0t1z0"');
  const glb = Buffer.from(await r.arrayBuffer());
  assert.equal(glb.subarray(0, 4).toString('latin1'), 'glTF');
  artifact('api-snapshot.glb', glb);
  assert.equal((await fetch(url, { headers: { 'If-None-Match': etag } })).status, 304);
  const leafy = await fetch(`${url}?detail=5&leaves=1&color=order&quantize=0`);
  assert.equal(leafy.headers.get('etag'), '"r1-d5l1m0c1q0t1z0"');
  const leafyBytes = Buffer.from(await leafy.arrayBuffer());
  assert.ok(leafyBytes.length > glb.length);
  artifact('api-snapshot-leaves.glb', leafyBytes);
  problem(await J('GET', `/v1/sessions/${id}/snapshot.glb?detail=9`), 422, 'out-of-range', /detail must be an integer from 1 to 5/, 'detail');
  // The brush client's compact snapshot: quantized, meshopt-compressed, no UVs, a third of
  // the bytes of the default (float, for every importer).
  const compact = await fetch(`${url}?leaves=1&quantize=1&texcoords=0&compress=meshopt`);
  assert.equal(compact.status, 200);
  assert.equal(compact.headers.get('etag'), '"r1-d3l1m0c0q1t0z1"');
  const compactBytes = Buffer.from(await compact.arrayBuffer());
  const doc = JSON.parse(compactBytes.subarray(20, 20 + compactBytes.readUInt32LE(12)).toString('utf8'));
  assert.deepEqual(doc.extensionsRequired, ['KHR_mesh_quantization', 'EXT_meshopt_compression']);
  assert.ok(doc.bufferViews.every((v) => v.buffer === 1 && v.extensions.EXT_meshopt_compression.buffer === 0));
  assert.ok(doc.meshes[0].primitives.every((p) => !('TEXCOORD_0' in p.attributes) && '_NODE_ID' in p.attributes));
  const full = Buffer.from(await (await fetch(`${url}?leaves=1`)).arrayBuffer());
  assert.ok(compactBytes.length * 2.5 < full.length, `${compactBytes.length} vs ${full.length} bytes`);
  artifact('api-snapshot-meshopt.glb', compactBytes);
  problem(await J('GET', `/v1/sessions/${id}/snapshot.glb?compress=zip`), 422, 'out-of-range', /compress must be none or meshopt/, 'compress');
  problem(await J('GET', `/v1/sessions/${id}/snapshot.glb?texcoords=2`), 422, 'out-of-range', /texcoords must be an integer from 0 to 1/, 'texcoords');
  // Twig lines, for the brush client's level of detail: each twig chunk's triangles,
  // then a LINES primitive on the same positions, in the "twig" material.
  const lod = await fetch(`${url}?leaves=1&quantize=1&texcoords=0&compress=meshopt&twig_lines=1`);
  assert.equal(lod.headers.get('etag'), '"r1-d3l1m0c0q1t0z1w1"');
  const lodBytes = Buffer.from(await lod.arrayBuffer());
  const lodDoc = JSON.parse(lodBytes.subarray(20, 20 + lodBytes.readUInt32LE(12)).toString('utf8'));
  const prims = lodDoc.meshes[0].primitives;
  const lines = prims.map((p, i) => [p, i]).filter(([p]) => p.mode === 1);
  assert.ok(lines.length > 0, 'no twig lines');
  for (const [p, i] of lines) {
    assert.equal(prims[i - 1].extras.twig, true);
    assert.equal(p.attributes.POSITION, prims[i - 1].attributes.POSITION);
    assert.equal(lodDoc.materials[p.material].name, 'twig');
    assert.ok(p.extras.twig_diameter_max > 0);
  }
  assert.ok(lodBytes.length < compactBytes.length * 1.1, `${lodBytes.length} vs ${compactBytes.length} bytes`);
  artifact('api-snapshot-twig-lines.glb', lodBytes);
  problem(await J('GET', `/v1/sessions/${id}/snapshot.glb?twig_lines=2`), 422, 'out-of-range', /twig_lines must be an integer from 0 to 1/, 'twig_lines');
  // After an edit the old ETag no longer matches.
  await J('POST', `/v1/sessions/${id}/edits`, { op: 'step', count: 1 });
  assert.equal((await fetch(url, { headers: { 'If-None-Match': etag } })).status, 200);
});

test('the page\'s compact snapshot and a download do not evict each other', async () => {
  const { body: { id } } = await create({ seed: 9 });
  await J('POST', `/v1/sessions/${id}/edits`, { op: 'step', count: 6 });
  const url = `${d.url}/v1/sessions/${id}/snapshot.glb`;
  const counts = async () => {
    const text = await (await fetch(`${d.url}/v1/metrics`)).text();
    const n = (result) => Number(text.match(new RegExp(`meristem_snapshot_cache_total\\{result="${result}"\\} (\\d+)`))[1]);
    return { hit: n('hit'), miss: n('miss') };
  };
  const first = await counts();
  const bytes = {};
  for (const [name, query] of [['download', ''], ['page', '?texcoords=0&compress=meshopt&twig_lines=1'],
    ['download', ''], ['page', '?texcoords=0&compress=meshopt&twig_lines=1']]) {
    const r = await fetch(url + query);
    assert.equal(r.status, 200);
    const b = Buffer.from(await r.arrayBuffer());
    if (bytes[name]) assert.ok(bytes[name].equals(b), `${name}: the cached bytes are the ones meshed`);
    bytes[name] = b;
  }
  const then = await counts();
  assert.deepEqual({ hit: then.hit - first.hit, miss: then.miss - first.miss }, { hit: 2, miss: 2 });
  // A new revision makes every variant stale.
  await J('POST', `/v1/sessions/${id}/edits`, { op: 'step' });
  assert.equal((await fetch(url)).status, 200);
  assert.equal((await counts()).miss - then.miss, 1);
});

test('edits answer with the GLB when asked', async () => {
  const { body: { id } } = await create({ seed: 6 });
  const r = await fetch(`${d.url}/v1/sessions/${id}/edits`, {
    method: 'POST', headers: { 'Content-Type': 'application/json', Accept: 'model/gltf-binary' },
    body: JSON.stringify({ op: 'step', count: 5 }),
  });
  assert.equal(r.status, 200);
  assert.equal(r.headers.get('content-type'), 'model/gltf-binary');
  assert.equal(r.headers.get('meristem-revision'), '1');
  const glb = Buffer.from(await r.arrayBuffer());
  artifact('api-edit-reply.glb', glb);
  const json = JSON.parse(glb.subarray(20, 20 + glb.readUInt32LE(12)).toString('utf8'));
  assert.equal(json.asset.extras.session, id);
  assert.equal(json.asset.extras.revision, 1);
  assert.equal(json.asset.extras.step, 5);
});

test('cancel stops a long step at a whole step, and the journal agrees', async () => {
  const { body: { id } } = await create({ preset: 'fig7-bh-0.54', seed: 8 });
  const long = J('POST', `/v1/sessions/${id}/edits`, { op: 'step', count: 200 });
  // Wait until it is running, then cancel.
  for (let i = 0; i < 200; i++) {
    const s = await J('GET', `/v1/sessions/${id}`);
    if (s.body.running.active && s.body.running.done > 2) break;
    await new Promise((res) => setTimeout(res, 10));
  }
  const c = await J('POST', `/v1/sessions/${id}/cancel`);
  assert.equal(c.status, 202);
  const r = await long;
  assert.equal(r.status, 200);
  assert.equal(r.body.interrupted, 'cancelled');
  assert.ok(r.body.step > 0 && r.body.step < 200, `stopped at step ${r.body.step}`);
  assert.equal(r.body.steps_done, r.body.step);
  assert.equal(r.body.revision, 1);
  assert.equal((await J('POST', `/v1/sessions/${id}/cancel`)).body.cancelling, false);
});

test('DELETE ends a session and removes its journal', async () => {
  const { body: { id } } = await create();
  const file = path.join(d.dataDir, `${id}.journal`);
  assert.ok(fs.existsSync(file));
  assert.equal((await J('DELETE', `/v1/sessions/${id}`)).status, 204);
  assert.ok(!fs.existsSync(file));
  problem(await J('GET', `/v1/sessions/${id}`), 404, 'unknown-session');
  problem(await J('DELETE', `/v1/sessions/${id}`), 404, 'unknown-session');
});

test('GET /v1/metrics speaks Prometheus', async () => {
  const r = await fetch(`${d.url}/v1/metrics`);
  assert.equal(r.status, 200);
  assert.match(r.headers.get('content-type'), /^text\/plain; version=0\.0\.4/);
  const text = await r.text();
  assert.match(text, /meristem_requests_total\{route="\/v1\/sessions",status="201"\} \d+/);
  assert.match(text, /meristem_step_seconds_count \d+/);
  assert.match(text, /meristem_sessions \d+/);
  assert.match(text, /meristem_internodes \d+/);
});
