'use strict';
// --token, --cors-origin and the Host check as a person deploying meristemd would rely on them.
const test = require('node:test');
const assert = require('node:assert/strict');
const fs = require('node:fs');
const http = require('node:http');
const net = require('node:net');
const os = require('node:os');
const path = require('node:path');
const { startDaemon } = require('../support/daemon.js');

test('with --token, every /v1 route but health wants the bearer token', async (t) => {
  const d = await startDaemon(['--token', 's3cret-token']);
  t.after(() => d.stop());
  assert.equal((await fetch(`${d.url}/v1/health`)).status, 200);
  for (const [method, p] of [['GET', '/v1/sessions'], ['POST', '/v1/sessions'], ['GET', '/v1/presets'], ['GET', '/v1/metrics']]) {
    const r = await fetch(d.url + p, { method });
    assert.equal(r.status, 401, `${method} ${p}`);
    assert.equal(r.headers.get('content-type'), 'application/problem+json');
    assert.equal(r.headers.get('www-authenticate'), 'Bearer');
    const wrong = await fetch(d.url + p, { method, headers: { Authorization: 'Bearer s3cret-tokeN' } });
    assert.equal(wrong.status, 401);
  }
  const ok = await fetch(`${d.url}/v1/sessions`, { method: 'POST', headers: { Authorization: 'Bearer s3cret-token' } });
  assert.equal(ok.status, 201);
  // The static page needs no token: it asks the person for one.
  assert.equal((await fetch(`${d.url}/`)).status, 200);
});

test('--token-file reads the token', async (t) => {
  const file = path.join(fs.mkdtempSync(path.join(os.tmpdir(), 'meristem-token-')), 'token');
  fs.writeFileSync(file, 'from-a-file\n');
  const d = await startDaemon(['--token-file', file]);
  t.after(() => d.stop());
  assert.equal((await fetch(`${d.url}/v1/sessions`)).status, 401);
  assert.equal((await fetch(`${d.url}/v1/sessions`, { headers: { Authorization: 'Bearer from-a-file' } })).status, 200);
});

test('CORS is off by default and allows exactly --cors-origin', async (t) => {
  const off = await startDaemon();
  t.after(() => off.stop());
  let r = await fetch(`${off.url}/v1/sessions`, { headers: { Origin: 'http://example.test' } });
  assert.equal(r.headers.get('access-control-allow-origin'), null);
  assert.equal((await fetch(`${off.url}/v1/sessions`, { method: 'OPTIONS', headers: { Origin: 'http://example.test' } })).status, 405);

  const on = await startDaemon(['--cors-origin', 'http://app.test']);
  t.after(() => on.stop());
  r = await fetch(`${on.url}/v1/sessions`, { headers: { Origin: 'http://app.test' } });
  assert.equal(r.headers.get('access-control-allow-origin'), 'http://app.test');
  r = await fetch(`${on.url}/v1/sessions`, { headers: { Origin: 'http://evil.test' } });
  assert.equal(r.headers.get('access-control-allow-origin'), null);
  const pre = await fetch(`${on.url}/v1/sessions`, { method: 'OPTIONS', headers: { Origin: 'http://app.test', 'Access-Control-Request-Method': 'POST' } });
  assert.equal(pre.status, 204);
  assert.match(pre.headers.get('access-control-allow-methods'), /POST/);
  assert.match(pre.headers.get('access-control-allow-headers'), /Authorization/);
});

test('--max-sessions is a 429 with a detail', async (t) => {
  const d = await startDaemon(['--max-sessions', '2']);
  t.after(() => d.stop());
  for (let i = 0; i < 2; i++) assert.equal((await fetch(`${d.url}/v1/sessions`, { method: 'POST' })).status, 201);
  const r = await fetch(`${d.url}/v1/sessions`, { method: 'POST' });
  assert.equal(r.status, 429);
  assert.match((await r.json()).detail, /--max-sessions/);
});

test('--max-internodes stops growth and then refuses with 409', async (t) => {
  const d = await startDaemon(['--max-internodes', '300']);
  t.after(() => d.stop());
  const s = await (await fetch(`${d.url}/v1/sessions`, { method: 'POST' })).json();
  const step = () => fetch(`${d.url}/v1/sessions/${s.id}/edits`, { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: '{"op":"step","count":50}' });
  const first = await (await step()).json();
  assert.equal(first.interrupted, 'internode limit');
  assert.ok(first.internodes >= 300 && first.step < 50);
  const again = await step();
  assert.equal(again.status, 409);
  assert.match((await again.json()).detail, /--max-internodes/);
});

/** A request with the Host header given (fetch will not send another): status,
 * content type and body. */
function withHost(port, p, host) {
  return new Promise((resolve, reject) => {
    const req = http.get({ host: '127.0.0.1', port, path: p, headers: { Host: host }, agent: false }, (res) => {
      let body = '';
      res.on('data', (c) => { body += c; });
      res.on('end', () => resolve({ status: res.statusCode, type: res.headers['content-type'], body }));
    });
    req.on('error', reject);
  });
}

test('DNS rebinding: only IP literals, localhost and --allowed-host names are served', async (t) => {
  const d = await startDaemon();
  t.after(() => d.stop());
  for (const host of [`127.0.0.1:${d.port}`, `localhost:${d.port}`, `LocalHost:${d.port}`, `[::1]:${d.port}`, 'localhost', '127.0.0.1'])
    assert.equal((await withHost(d.port, '/v1/health', host)).status, 200, host);
  // A rebinding page's own name, every route and the static files too.
  for (const p of ['/v1/health', '/v1/sessions', '/', '/index.html']) {
    const r = await withHost(d.port, p, `rebind.example:${d.port}`);
    assert.equal(r.status, 421, p);
    assert.equal(r.type, 'application/problem+json');
    const problem = JSON.parse(r.body);
    assert.equal(problem.type, 'urn:meristem:problem:host-not-allowed');
    assert.match(problem.detail, /--allowed-host/);
  }
  for (const host of [`localhost:${d.port + 1}`, 'rebind.example', `127.0.0.1.rebind.example:${d.port}`, `[::1:${d.port}`])
    assert.equal((await withHost(d.port, '/v1/health', host)).status, 421, host);

  // HTTP/1.1 must name a host; HTTP/1.0 may not, and a browser always does.
  const raw = async (request) => new Promise((resolve, reject) => {
    const socket = net.connect(d.port, '127.0.0.1');
    let text = '';
    socket.on('data', (c) => { text += c; });
    socket.on('end', () => resolve(text));
    socket.on('error', reject);
    socket.end(request);
  });
  let text = await raw('GET /v1/health HTTP/1.1\r\nConnection: close\r\n\r\n');
  assert.match(text, /^HTTP\/1\.1 400 /);
  assert.match(text, /urn:meristem:problem:missing-host/);
  text = await raw('GET /v1/health HTTP/1.0\r\n\r\n');
  assert.match(text, /^HTTP\/1\.[01] 200 /);

  const named = await startDaemon(['--allowed-host', 'trees.example', '--allowed-host', 'lab.example:8443']);
  t.after(() => named.stop());
  assert.equal((await withHost(named.port, '/v1/sessions', `trees.example:${named.port}`)).status, 200);
  assert.equal((await withHost(named.port, '/v1/sessions', 'TREES.example')).status, 200);
  assert.equal((await withHost(named.port, '/v1/sessions', 'lab.example:8443')).status, 200);
  assert.equal((await withHost(named.port, '/v1/sessions', `lab.example:${named.port}`)).status, 421);
  assert.equal((await withHost(named.port, '/v1/sessions', `rebind.example:${named.port}`)).status, 421);
  assert.equal((await withHost(named.port, '/v1/sessions', `127.0.0.1:${named.port}`)).status, 200);
});
