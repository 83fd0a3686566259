'use strict';
// Session hygiene and first-run manners: ttl_seconds removes a session and its
// files; GET /v1/sessions pages and filters; an unknown query parameter is a
// 400 naming it; every reply body ends with a newline; the data dir is logged.
const { test, before, after } = require('node:test');
const assert = require('node:assert/strict');
const fs = require('node:fs');
const path = require('node:path');
const { startDaemon, api } = require('../support/daemon.js');

let d;
const J = (method, p, body) => api(d.url, method, p, body);
before(async () => { d = await startDaemon(['--checkpoint-every', '1']); });
after(async () => { await d.stop(); });

const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));

test('a session with ttl_seconds is removed with its journal and checkpoint', async () => {
  // 3 s: long enough for the step below on a busy machine, short enough to wait for.
  const short = await J('POST', '/v1/sessions', { preset: 'default', ttl_seconds: 3 });
  assert.equal(short.status, 201, JSON.stringify(short.body));
  assert.equal(typeof short.body.expires_at, 'string');
  const keep = await J('POST', '/v1/sessions', { preset: 'default' });
  assert.equal(keep.body.expires_at, undefined);
  const id = short.body.id;
  assert.equal((await J('POST', `/v1/sessions/${id}/edits`, { op: 'step', count: 1 })).status, 200);
  const files = [`${id}.journal`, `${id}.checkpoint`].map((f) => path.join(d.dataDir, f));
  for (const f of files) assert.ok(fs.existsSync(f), f);
  let gone = false;
  for (let i = 0; i < 150 && !gone; i++) {
    await sleep(100);
    gone = (await J('GET', `/v1/sessions/${id}`)).status === 404;
  }
  assert.ok(gone, 'the session went after its ttl');
  // The line is written once its files are unlinked (the session leaves the list first).
  await d.waitForLog(new RegExp(`session ${id} reached its ttl_seconds and was removed`));
  for (const f of files) assert.ok(!fs.existsSync(f), `${f} is removed`);
  assert.equal((await J('GET', `/v1/sessions/${keep.body.id}`)).status, 200);
  for (const ttl of [0, -1, 'soon', 1e9]) {
    const r = await J('POST', '/v1/sessions', { ttl_seconds: ttl });
    assert.equal(r.status, 422, String(ttl));
    assert.equal(r.body.field, 'ttl_seconds');
  }
});

test('a time to live holds across a restart', async () => {
  const os = require('node:os');
  const data = fs.mkdtempSync(path.join(os.tmpdir(), 'meristem-ttl-'));
  let other = await startDaemon([], { dataDir: data });
  try {
    const c = await api(other.url, 'POST', '/v1/sessions', { ttl_seconds: 2 });
    assert.equal(c.status, 201);
    await other.stop();
    await sleep(2500);
    other = await startDaemon([], { dataDir: data });
    let gone = false;
    for (let i = 0; i < 50 && !gone; i++) {
      gone = (await api(other.url, 'GET', `/v1/sessions/${c.body.id}`)).status === 404;
      if (!gone) await sleep(100);
    }
    assert.ok(gone, 'removed after the restart');
    assert.ok(!fs.existsSync(path.join(data, `${c.body.id}.journal`)));
  } finally {
    await other.stop();
    fs.rmSync(data, { recursive: true, force: true });
  }
});

test('GET /v1/sessions pages and filters', async () => {
  const made = [];
  for (const preset of ['default', 'fig12a', 'default', 'fig12a', 'default']) {
    made.push((await J('POST', '/v1/sessions', { preset })).body.id);
  }
  const all = (await J('GET', '/v1/sessions')).body;
  assert.equal(all.next_after, null);
  const ids = all.sessions.map((s) => s.id);
  for (const id of made) assert.ok(ids.includes(id));
  const seen = [];
  let after = null;
  for (;;) {
    const r = await J('GET', `/v1/sessions?limit=2${after ? `&after=${after}` : ''}`);
    assert.equal(r.status, 200);
    assert.ok(r.body.sessions.length <= 2);
    seen.push(...r.body.sessions.map((s) => s.id));
    if (r.body.next_after === null) break;
    after = r.body.next_after;
  }
  assert.deepEqual(seen, ids);
  const col = (await J('GET', '/v1/sessions?preset=fig12a')).body.sessions;
  assert.ok(col.length >= 2 && col.every((s) => s.preset === 'fig12a'));
  const idle = (await J('GET', '/v1/sessions?state=idle')).body.sessions;
  assert.equal(idle.length, ids.length);
  assert.equal((await J('GET', '/v1/sessions?state=quarantined')).body.sessions.length, 0);
  assert.equal((await J('GET', '/v1/sessions?state=sleepy')).status, 422);
  assert.equal((await J('GET', '/v1/sessions?limit=0')).status, 422);
});

test('an unknown query parameter is refused with 400 naming it', async () => {
  const id = (await J('POST', '/v1/sessions', {})).body.id;
  const cases = [
    [`/v1/sessions/${id}/snapshot.glb?leafs=1`, 'leafs'],
    [`/v1/sessions/${id}/snapshot.glb?leaves=1&colour=age`, 'colour'],
    [`/v1/sessions/${id}?full=1`, 'full'],
    ['/v1/sessions?page=2', 'page'],
    [`/v1/sessions/${id}/skeleton?living=1`, 'living'],
    ['/v1/presets?x=1', 'x'],
  ];
  for (const [p, name] of cases) {
    const r = await J('GET', p);
    assert.equal(r.status, 400, p);
    assert.equal(r.headers.get('content-type'), 'application/problem+json');
    assert.equal(r.body.field, name);
    assert.match(r.body.detail, new RegExp(`'${name}'`));
  }
  const ok = await fetch(`${d.url}/v1/sessions/${id}/snapshot.glb?leaves=1&detail=2&color=age`);
  assert.equal(ok.status, 200);
});

test('every reply body ends with a newline', async () => {
  const id = (await J('POST', '/v1/sessions', {})).body.id;
  const replies = [
    await J('GET', '/v1/health'),
    await J('GET', '/v1/presets'),
    await J('GET', '/v1/sessions'),
    await J('POST', '/v1/sessions', {}),
    await J('GET', `/v1/sessions/${id}`),
    await J('POST', `/v1/sessions/${id}/edits`, { op: 'step', count: 1 }),
    await J('POST', `/v1/sessions/${id}/edits`, { op: 'nope' }),
    await J('GET', `/v1/sessions/${id}/revisions`),
    await J('GET', `/v1/sessions/${id}/skeleton`),
    await J('POST', `/v1/sessions/${id}/cancel`),
    await J('GET', '/v1/sessions/0123456789abcdef0123456789abcdef'),
    await J('GET', '/v1/nowhere'),
    await J('PUT', '/v1/sessions'),
    await J('GET', '/v1/metrics'),
  ];
  for (const r of replies) {
    assert.ok(r.raw.length > 0);
    assert.equal(r.raw[r.raw.length - 1], 0x0a, `${r.status} ${r.raw.toString().slice(0, 80)}`);
  }
});

test('run from its build tree without --web-root, meristemd serves the build\'s page', async () => {
  const { spawn } = require('node:child_process');
  const os = require('node:os');
  const data = fs.mkdtempSync(path.join(os.tmpdir(), 'meristem-root-'));
  const child = spawn(process.env.MERISTEMD, ['--port', '0', '--data-dir', data], { stdio: ['ignore', 'pipe', 'pipe'] });
  let out = '';
  child.stdout.on('data', (b) => { out += b; });
  child.stderr.on('data', (b) => { out += b; });
  try {
    for (let i = 0; i < 150 && !/listening on/.test(out); i++) await sleep(100);
    const m = out.match(/listening on (http:\/\/[^/]+)\/ \(web root ([^)]*)\)/);
    assert.ok(m, out);
    // An installed page wins; otherwise the build tree's, never a failure to start.
    const root = fs.realpathSync(process.env.MER_WEB_ROOT);
    if (m[2] === root) {
      const page = await fetch(`${m[1]}/`);
      assert.equal(page.status, 200);
      assert.match(await page.text(), /<title>meristem<\/title>/);
    } else {
      assert.ok(fs.existsSync(m[2]), `serves an existing web root: ${m[2]}`);
    }
    assert.match(out, new RegExp(`data dir ${fs.realpathSync(data)}\n`));
  } finally {
    child.kill('SIGTERM');
    await new Promise((resolve) => child.on('exit', resolve));
    fs.rmSync(data, { recursive: true, force: true });
  }
});

test('the data dir is logged as an absolute path', async () => {
  await d.waitForLog(new RegExp(`data dir ${fs.realpathSync(d.dataDir).replace(/[.*+?^${}()|[\]\\]/g, '\\$&')}\n`));  // stderr may lag: wait for the line
});
