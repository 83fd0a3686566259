'use strict';
// The HTTP contract in proto/ against itself and against a real meristemd:
// openapi.yaml is a valid OpenAPI 3.1 document that names every route of
// server/routes.c; every JSON Schema compiles (draft 2020-12); every example
// request validates against its schema, and the daemon accepts it; the daemon's
// responses (summaries, lists, presets, problems, cancel) validate against theirs.
const { test, before, after } = require('node:test');
const assert = require('node:assert/strict');
const fs = require('node:fs');
const path = require('node:path');
const { pathToFileURL } = require('node:url');
const Ajv2020 = require('ajv/dist/2020');
const addFormats = require('ajv-formats');
const YAML = require('yaml');
const { startDaemon, api } = require('../support/daemon.js');

const SRC = process.env.MER_SRCDIR || path.resolve(__dirname, '..', '..');
const PROTO = path.join(SRC, 'proto');
const SCHEMAS = path.join(PROTO, 'schemas');
const EXAMPLES = path.join(PROTO, 'examples');

const readJson = (file) => JSON.parse(fs.readFileSync(file, 'utf8'));
const schemaFiles = fs.readdirSync(SCHEMAS).filter((f) => f.endsWith('.json')).sort();
const exampleFiles = fs.readdirSync(EXAMPLES).filter((f) => f.endsWith('.json')).sort();
const example = (name) => readJson(path.join(EXAMPLES, name));
const openapiText = fs.readFileSync(path.join(PROTO, 'openapi.yaml'), 'utf8');

// One Ajv holding every schema under its file name, so relative file refs
// ("edit.json", "session-summary.json#/$defs/item") resolve as they do on disk.
// strictRequired is off: it misreads `anyOf: [{required: [...]}]` beside `properties`.
const ajv = new Ajv2020({ strict: true, strictRequired: false, allowUnionTypes: true, allErrors: true });
addFormats(ajv);
for (const f of schemaFiles) ajv.addSchema(readJson(path.join(SCHEMAS, f)), f);

function check(schemaName, value, what) {
  const validate = ajv.getSchema(schemaName);
  assert.ok(validate, `no schema ${schemaName}`);
  const ok = validate(value);
  assert.ok(ok, `${what} does not match ${schemaName}: ${ajv.errorsText(validate.errors, { separator: '\n  ' })}\n${JSON.stringify(value).slice(0, 2000)}`);
}

// Every $ref / externalValue string anywhere in a parsed document.
function collect(node, key, out = []) {
  if (Array.isArray(node)) node.forEach((v) => collect(v, key, out));
  else if (node && typeof node === 'object') {
    for (const [k, v] of Object.entries(node)) {
      if (k === key && typeof v === 'string') out.push(v);
      else collect(v, key, out);
    }
  }
  return out;
}

// A copy of a schema file with its file refs made relative to proto/ (where
// openapi.yaml is), by URI resolution against the file's own place.
function rebased(file) {
  const base = new URL(`file:///proto/schemas/${file}`);
  const walk = (node) => {
    if (Array.isArray(node)) return node.map(walk);
    if (!node || typeof node !== 'object') return node;
    const out = {};
    for (const [k, v] of Object.entries(node)) {
      if (k === '$ref' && typeof v === 'string' && !v.startsWith('#')) {
        const u = new URL(v, base);
        out[k] = path.posix.relative('/proto', u.pathname) + u.hash;
      } else {
        out[k] = walk(v);
      }
    }
    return out;
  };
  return walk(readJson(path.join(SCHEMAS, file)));
}

// The route table of server/routes.c: [{method, pattern, open}].
function routeTable() {
  const text = fs.readFileSync(path.join(SRC, 'server', 'routes.c'), 'utf8');
  const rows = [...text.matchAll(/\{"([A-Z]+)", "(\/v1[^"]*)", (\w+), (true|false)(?:, \w+)?\}/g)];
  return rows.map((m) => ({ method: m[1].toLowerCase(), pattern: m[2], open: m[4] === 'true' }));
}

const REQUIRED_SCHEMAS = ['cancel.json', 'edit-batch.json', 'edit.json', 'edits-request.json',
  'edits-response.json', 'health.json', 'presets.json', 'problem.json', 'session-create.json',
  'session-list.json', 'session-summary.json', 'revisions.json', 'skeleton.json'];
const OPS = ['step', 'add_markers', 'prune', 'bend', 'set_apical_schedule', 'set_params', 'release'];
const METHODS = ['get', 'put', 'post', 'delete', 'options', 'head', 'patch', 'trace'];

// ------------------------------------------------------------ the documents

test('openapi.yaml is a valid OpenAPI 3.1 document, its refs resolved', async () => {
  const doc = YAML.parse(openapiText, { uniqueKeys: true, prettyErrors: true });
  assert.equal(doc.openapi, '3.1.0');
  const validatorPath = require.resolve('@seriousme/openapi-schema-validator');
  const { Validator } = await import(pathToFileURL(validatorPath).href);
  const validator = new Validator();
  for (const f of schemaFiles) await validator.addSpecRef(rebased(f), `schemas/${f}`);
  const res = await validator.validate(structuredClone(doc));
  assert.ok(res.valid, `openapi.yaml is not valid OpenAPI: ${JSON.stringify(res.errors, null, 2)}`);
  assert.equal(validator.version, '3.1');
  // The validator checks refs it knows; this checks every file ref names a real file.
  const fileRefs = collect(doc, '$ref').filter((r) => !r.startsWith('#'));
  assert.ok(fileRefs.length >= REQUIRED_SCHEMAS.length, 'openapi.yaml refers to no schema files');
  for (const ref of fileRefs) {
    assert.ok(fs.existsSync(path.join(PROTO, ref.split('#')[0])), `openapi.yaml: ${ref} does not exist`);
  }
  for (const f of REQUIRED_SCHEMAS) {
    if (f === 'edit.json' || f === 'edit-batch.json') continue; // reached through edits-request.json
    assert.ok(fileRefs.includes(`schemas/${f}`), `openapi.yaml does not use schemas/${f}`);
  }
});

test('openapi.yaml has exactly the routes of server/routes.c, and their security', () => {
  const doc = YAML.parse(openapiText);
  const routes = routeTable();
  assert.ok(routes.length >= 12, `found only ${routes.length} routes in server/routes.c`);
  const documented = [];
  for (const [p, item] of Object.entries(doc.paths)) {
    for (const m of METHODS) if (item[m]) documented.push(`${m.toUpperCase()} ${p}`);
  }
  const implemented = routes.map((r) => `${r.method.toUpperCase()} ${r.pattern}`);
  assert.deepEqual(documented.sort(), implemented.sort());
  for (const r of routes) {
    const op = doc.paths[r.pattern][r.method];
    if (r.open) {
      assert.deepEqual(op.security, [], `${r.method} ${r.pattern} is open in routes.c: its operation must say security: []`);
    } else {
      const security = op.security ?? doc.security;
      assert.ok(security.some((req) => Object.keys(req).length === 0),
        `${r.method} ${r.pattern}: the token is optional (needed only with --token)`);
      assert.ok(security.some((req) => 'bearer' in req), `${r.method} ${r.pattern} takes the bearer token`);
      assert.ok(op.responses['401'], `${r.method} ${r.pattern} documents 401`);
    }
    if (r.pattern.includes('{id}')) {
      assert.ok(op.responses['404'], `${r.method} ${r.pattern} documents 404`);
    }
  }
  assert.equal(doc.components.securitySchemes.bearer.scheme, 'bearer');
});

test('every schema in proto/schemas compiles as draft 2020-12', () => {
  assert.deepEqual(REQUIRED_SCHEMAS.filter((f) => !schemaFiles.includes(f)), [], 'schemas missing');
  for (const f of schemaFiles) {
    const s = readJson(path.join(SCHEMAS, f));
    assert.equal(s.$schema, 'https://json-schema.org/draft/2020-12/schema', f);
    assert.ok(ajv.getSchema(f), `${f} does not compile`);
  }
});

test('every example validates against its request schema and is named in openapi.yaml', () => {
  const creates = exampleFiles.filter((f) => f.startsWith('create-'));
  const edits = exampleFiles.filter((f) => f.startsWith('edit-'));
  const batches = exampleFiles.filter((f) => f.startsWith('batch'));
  assert.ok(creates.length >= 2, 'fewer than 2 create examples');
  assert.ok(edits.length >= 8, 'fewer than 8 edit examples');
  assert.ok(batches.length >= 1, 'no batch example');
  assert.equal(creates.length + edits.length + batches.length, exampleFiles.length,
    'examples must be named create-*.json, edit-*.json or batch*.json');
  for (const f of creates) check('session-create.json', example(f), f);
  for (const f of edits) {
    check('edit.json', example(f), f);
    check('edits-request.json', example(f), f);
  }
  for (const f of batches) {
    check('edit-batch.json', example(f), f);
    check('edits-request.json', example(f), f);
  }
  // Every op, and both forms of add_markers, has an example of its own.
  const single = edits.map((f) => example(f));
  for (const op of OPS) assert.ok(single.some((e) => e.op === op), `no example of ${op}`);
  assert.ok(single.some((e) => e.op === 'add_markers' && e.points), 'no add_markers points example');
  // A revert's example is a batch: the golden test replays every edit-*.json in one script.
  assert.ok(batches.some((f) => example(f).edits.some((e) => e.op === 'revert')), 'no revert example');
  assert.ok(single.some((e) => e.op === 'add_markers' && e.center && e.symmetry && e.constrain),
    'no brush example with symmetry and constrain');
  const external = collect(YAML.parse(openapiText), 'externalValue');
  for (const f of exampleFiles) assert.ok(external.includes(`examples/${f}`), `openapi.yaml does not list examples/${f}`);
  for (const x of external) assert.ok(fs.existsSync(path.join(PROTO, x)), `${x} does not exist`);
});

test('the schemas refuse what server/edit_ops.c and server/spec.c refuse', () => {
  const refused = {
    'edit.json': [
      {}, { op: 'grow' }, { op: 'step', count: 0 }, { op: 'step', count: 1.5 }, { op: 'step', n: 2 },
      { op: 'prune' }, { op: 'prune', node: -1 }, { op: 'bend', node: 1, axis: [0, 0, 0], angle: 10 },
      { op: 'bend', node: 1, axis: [0, 0, 1], angle: 400 }, { op: 'bend', node: 1, axis: [0, 1], angle: 1 },
      { op: 'add_markers', points: [[0, 0]] }, { op: 'add_markers', center: [0, 0, 0] },
      { op: 'add_markers', center: [0, 0, 0], radius: 1, pressure: 0 },
      { op: 'add_markers', center: [0, 0, 0], radius: 1, points: [] },
      { op: 'add_markers', center: [0, 0, 0], radius: 1, symmetry: { rotational: 65 } },
      { op: 'add_markers', center: [0, 0, 0], radius: 1, symmetry: { tiles: [2, 2] } },
      { op: 'add_markers', center: [0, 0, 0], radius: 1, symmetry: { mirror: { point: [0, 0, 0] } } },
      { op: 'add_markers', center: [0, 0, 0], radius: 1, constrain: { bud: 1 } },
      { op: 'add_markers', center: [0, 0, 0], radius: 1, constrain: { node: 1, bud: 3 } },
      { op: 'set_apical_schedule' }, { op: 'set_apical_schedule', apical_off: [] },
      { op: 'set_apical_schedule', lambda_keys: [[0, 2]] },
      { op: 'set_apical_schedule', eta_order_scale: [1, 1, 1, 1, 1, 1, 1, 1, 1] },
      { op: 'set_params' }, { op: 'set_params', params: { lambda: 'high' } },
      { op: 'release', node: 1 },
    ],
    'edits-request.json': [{ edits: [] }, { edits: [{ op: 'step' }], op: 'step' }, [{ op: 'step' }]],
    'session-create.json': [
      { seed: -1 }, { seed: 1.5 }, { preset: 3 }, { colour: 'red' }, { scene: { trees: [] } },
      { scene: { plants: [[0, 0]] } }, { scene: { markers: [{ volume: 'torus', center: [0, 0, 0], size: [1, 1, 1], count: 1 }] } },
      { scene: { markers: [{ volume: 'box', center: [0, 0, 0], size: [1, 1, 1], count: 0 }] } },
      { scene: { obstacles: [{ box: { min: [0, 0, 0] } }] } },
      { scene: { obstacles: [{ box: { min: [0, 0, 0], max: [1, 1, 1] }, sphere: { center: [0, 0, 0], radius: 1 } }] } },
      { scene: { obstacles: [{ sphere: { center: [0, 0, 0], radius: 1e300 } }] } },
    ],
  };
  for (const [schema, values] of Object.entries(refused)) {
    const validate = ajv.getSchema(schema);
    for (const v of values) assert.equal(validate(v), false, `${schema} accepts ${JSON.stringify(v)}`);
  }
});

// ---------------------------------------------------------- against meristemd

let d;
const J = (method, p, body, headers) => api(d.url, method, p, body, headers);

before(async () => { d = await startDaemon(['--quiet']); });
after(() => d.stop());

function problem(r, status, what) {
  assert.equal(r.status, status, `${what}: ${JSON.stringify(r.body)}`);
  assert.equal(r.headers.get('content-type'), 'application/problem+json', what);
  check('problem.json', r.body, what);
  assert.equal(r.body.status, status, what);
}

async function grown(steps = 8) {
  const c = await J('POST', '/v1/sessions', {});
  assert.equal(c.status, 201, JSON.stringify(c.body));
  const g = await J('POST', `/v1/sessions/${c.body.id}/edits`, { op: 'step', count: steps });
  assert.equal(g.status, 200, JSON.stringify(g.body));
  assert.equal(g.body.step, steps);
  return g.body;
}

test('every create example makes a session (201, Location, summary)', async () => {
  const creates = exampleFiles.filter((f) => f.startsWith('create-'));
  assert.ok(creates.length > 0);
  for (const f of creates) {
    const body = example(f);
    const r = await J('POST', '/v1/sessions', body);
    assert.equal(r.status, 201, `${f}: ${JSON.stringify(r.body)}`);
    check('session-summary.json', r.body, `${f} reply`);
    assert.equal(r.headers.get('location'), `/v1/sessions/${r.body.id}`, f);
    assert.equal(r.headers.get('meristem-revision'), '0', f);
    assert.equal(r.body.preset, body.preset ?? 'default', f);
    assert.equal(r.body.seed, body.seed ?? 0, f);
    for (const [k, v] of Object.entries(body.params ?? {})) {
      assert.ok(Math.abs(r.body.params[k] - v) < 1e-6, `${f}: params.${k} is ${r.body.params[k]}, not ${v}`);
    }
    if (body.scene?.plants) assert.equal(r.body.plants, body.scene.plants.length, f);
    const g = await J('GET', `/v1/sessions/${r.body.id}`);
    assert.equal(g.status, 200);
    check('session-summary.json', g.body, `GET of ${f}`);
    assert.equal(g.headers.get('meristem-revision'), '0');
  }
});

test('every edit and batch example is accepted by a default tree grown 8 steps', async () => {
  const files = exampleFiles.filter((f) => f.startsWith('edit-') || f.startsWith('batch'));
  assert.ok(files.length >= 9, `only ${files.length} edit and batch examples`);
  for (const f of files) {
    const s = await grown(8);
    const r = await J('POST', `/v1/sessions/${s.id}/edits`, example(f));
    assert.equal(r.status, 200, `${f}: ${JSON.stringify(r.body)}`);
    check('edits-response.json', r.body, `${f} reply`);
    assert.equal(r.body.id, s.id);
    assert.equal(r.body.revision, s.revision + 1, `${f} makes one revision`);
    assert.equal(r.headers.get('meristem-revision'), String(r.body.revision), f);
    const body = example(f);
    const steps = (body.edits ?? [body]).filter((e) => e.op === 'step').reduce((n, e) => n + (e.count ?? 1), 0);
    assert.equal(r.body.steps_done, steps, `${f}: steps_done`);
    assert.equal(r.body.step, 8 + steps, `${f}: step`);
    assert.equal(r.body.interrupted, undefined, f);
  }
});

test('an edit with Accept: model/gltf-binary answers with the snapshot and its ETag', async () => {
  const s = await grown(8);
  const r = await J('POST', `/v1/sessions/${s.id}/edits?detail=2&color=order`, example('edit-step.json'),
    { Accept: 'model/gltf-binary' });
  assert.equal(r.status, 200);
  assert.equal(r.headers.get('content-type'), 'model/gltf-binary');
  assert.equal(r.raw.subarray(0, 4).toString('latin1'), 'glTF');
  assert.match(r.headers.get('etag'), /^"r2-d2l0m0c1q0t1z0"$/);
});

test('snapshots: ETag as documented, If-None-Match gives 304', async () => {
  const doc = YAML.parse(openapiText);
  const etagPattern = new RegExp(doc.components.headers.ETag.schema.pattern);
  const s = await grown(3);
  const p = `/v1/sessions/${s.id}/snapshot.glb?detail=1&leaves=1&markers=0&color=age&quantize=0`;
  const r = await J('GET', p);
  assert.equal(r.status, 200);
  assert.equal(r.headers.get('content-type'), 'model/gltf-binary');
  assert.match(r.headers.get('etag'), etagPattern);
  assert.equal(r.headers.get('meristem-revision'), '1');
  const again = await J('GET', p, undefined, { 'If-None-Match': r.headers.get('etag') });
  assert.equal(again.status, 304);
  assert.equal(again.headers.get('etag'), r.headers.get('etag'));
  problem(await J('GET', `/v1/sessions/${s.id}/snapshot.glb?detail=9`), 422, 'detail=9');
  problem(await J('GET', `/v1/sessions/${s.id}/snapshot.glb?color=red`), 422, 'color=red');
});

test('refusals are problem documents as problem.json says', async () => {
  const s = await grown(8);
  const e = `/v1/sessions/${s.id}/edits`;
  let r = await J('POST', e, { op: 'grow' });
  problem(r, 400, 'unknown op');
  assert.equal(r.body.type, 'urn:meristem:problem:unknown-op');
  assert.equal(r.body.field, 'op');
  r = await J('POST', e, { edits: [{ op: 'step' }, { op: 'step', count: 0 }] });
  problem(r, 422, 'count 0');
  assert.equal(r.body.field, 'edits[1].count');
  r = await J('POST', e, { op: 'prune', node: 1, why: 'x' });
  problem(r, 400, 'unknown field');
  assert.equal(r.body.field, 'why');
  r = await J('POST', e, '{"op": "step",');
  problem(r, 400, 'malformed JSON');
  assert.equal(r.body.field, undefined);
  r = await J('POST', e, { op: 'step' }, { 'Content-Type': 'text/plain' });
  problem(r, 415, 'text/plain');
  r = await J('POST', e, { op: 'prune', node: 4000000000 });
  problem(r, 404, 'a node never issued');
  r = await J('POST', e, { edits: [{ op: 'prune', node: 5 }, { op: 'bend', node: 5, axis: [0, 0, 1], angle: 5 }] });
  problem(r, 409, 'a pruned node');
  assert.equal(r.body.field, 'edits[1].node');
  r = await J('GET', '/v1/sessions/0123456789abcdef0123456789abcdef');
  problem(r, 404, 'unknown session');
  r = await J('GET', '/v1/nothing');
  problem(r, 404, 'no such route');
  r = await J('PUT', `/v1/sessions/${s.id}`, {});
  problem(r, 405, 'PUT');
  assert.equal(r.headers.get('allow'), 'GET, DELETE');
  r = await J('POST', '/v1/sessions', { preset: 'no-such-preset' });
  problem(r, 422, 'unknown preset');
});

test('GET /v1/presets matches presets.json, and the examples use its names', async () => {
  const r = await J('GET', '/v1/presets');
  assert.equal(r.status, 200);
  check('presets.json', r.body, 'GET /v1/presets');
  const names = new Set(r.body.presets.map((p) => p.name));
  const params = new Set(r.body.parameters.map((p) => p.name));
  assert.ok(names.has('default'));
  const used = [];
  for (const f of exampleFiles) {
    const b = example(f);
    if (b.preset) assert.ok(names.has(b.preset), `${f}: no preset ${b.preset}`);
    for (const e of [b, ...(b.edits ?? [])]) used.push(...Object.keys(e.params ?? {}).map((k) => [f, k]));
  }
  assert.ok(used.length > 0);
  for (const [f, k] of used) assert.ok(params.has(k), `${f}: no parameter ${k}`);
  // The summary's params are the named parameters its model reads (its own and
  // every model's) less the schedule's, and less the noise's while it is off.
  for (const model of ['p09', 'lsystem']) {
    const s = await J('POST', '/v1/sessions', model === 'p09' ? {} : { preset: 'abop-1.24a' });
    const expected = r.body.parameters.filter((p) => p.model === '' || p.model === model).map((p) => p.name)
      .filter((n) => !/^(apical_off|eta_order_scale)\./.test(n) && !/^noise_/.test(n)).sort();
    assert.deepEqual(Object.keys(s.body.params).sort(), expected, model);
  }
});

test('a quarantined session is a list item of its own', () => {
  const q = { id: 'a'.repeat(32), state: 'quarantined', reason: 'record 2 is damaged' };
  check('session-list.json', { sessions: [q] }, 'a quarantined item');
  const validate = ajv.getSchema('session-list.json');
  assert.ok(!validate({ sessions: [{ ...q, reason: undefined }] }), 'a reason is required');
  assert.ok(!validate({ sessions: [{ ...q, revision: 3 }] }), 'no summary fields');
});

test('GET /v1/sessions matches session-list.json', async () => {
  const made = await grown(1);
  const r = await J('GET', '/v1/sessions');
  assert.equal(r.status, 200);
  check('session-list.json', r.body, 'GET /v1/sessions');
  assert.ok(r.body.sessions.length > 0);
  const item = r.body.sessions.find((x) => x.id === made.id);
  assert.ok(item, 'the new session is listed');
  assert.equal(item.params, undefined);
  assert.equal(item.schedule, undefined);
});

test('revisions, the skeleton and their refusals match their schemas', async () => {
  const s = await grown(4);
  assert.equal((await J('POST', `/v1/sessions/${s.id}/edits`, example('batch-undo.json'))).status, 200);
  const revisions = await J('GET', `/v1/sessions/${s.id}/revisions?limit=2`);
  assert.equal(revisions.status, 200);
  check('revisions.json', revisions.body, 'a page of revisions');
  check('revisions.json', (await J('GET', `/v1/sessions/${s.id}/revisions?after=1`)).body, 'the last page');
  const skeleton = await J('GET', `/v1/sessions/${s.id}/skeleton`);
  check('skeleton.json', skeleton.body, 'the skeleton');
  check('skeleton.json', (await J('GET', `/v1/sessions/${s.id}/skeleton?alive=1`)).body, 'the living');
  for (const r of [await J('POST', `/v1/sessions/${s.id}/edits`, { op: 'revert', revision: 9 }),
    await J('GET', `/v1/sessions/${s.id}/skeleton?alive=1&x=2`)]) {
    check('problem.json', r.body, `${r.status}`);
  }
  const ttl = await J('POST', '/v1/sessions', { ttl_seconds: 600 });
  check('session-create.json', { ttl_seconds: 600 }, 'a create with ttl_seconds');
  check('session-summary.json', ttl.body, 'a summary with expires_at');
});

test('POST .../cancel matches cancel.json (202), DELETE is 204', async () => {
  const s = await grown(1);
  const r = await J('POST', `/v1/sessions/${s.id}/cancel`);
  assert.equal(r.status, 202);
  check('cancel.json', r.body, 'cancel');
  assert.equal(r.body.cancelling, false);
  assert.equal(r.headers.get('meristem-revision'), '1');
  problem(await J('POST', '/v1/sessions/0123456789abcdef0123456789abcdef/cancel'), 404, 'cancel unknown');
  const del = await J('DELETE', `/v1/sessions/${s.id}`);
  assert.equal(del.status, 204);
  problem(await J('GET', `/v1/sessions/${s.id}`), 404, 'deleted');
});

test('with --token: 401 with WWW-Authenticate, /v1/health stays open', async () => {
  const t = await startDaemon(['--quiet', '--token', 'proto-test-token']);
  try {
    const h = await api(t.url, 'GET', '/v1/health');
    assert.equal(h.status, 200);
    check('health.json', h.body, 'health');
    const r = await api(t.url, 'GET', '/v1/sessions');
    problem(r, 401, 'no token');
    assert.equal(r.headers.get('www-authenticate'), 'Bearer');
    const ok = await api(t.url, 'GET', '/v1/sessions', undefined, { Authorization: 'Bearer proto-test-token' });
    assert.equal(ok.status, 200);
    check('session-list.json', ok.body, 'GET /v1/sessions with the token');
  } finally {
    await t.stop();
  }
});
