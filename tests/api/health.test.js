'use strict';
// meristemd's skeleton: health, problem+json errors, options, clean shutdown.
const { test, before, after } = require('node:test');
const assert = require('node:assert/strict');
const { spawnSync } = require('node:child_process');
const { startDaemon } = require('../support/daemon.js');

let d;
before(async () => { d = await startDaemon(); });
after(() => d.stop());

test('GET /v1/health says ok and the version', async () => {
  const r = await fetch(`${d.url}/v1/health`);
  assert.equal(r.status, 200);
  assert.equal(r.headers.get('content-type'), 'application/json');
  assert.deepEqual(await r.json(), { status: 'ok', version: process.env.PACKAGE_VERSION });
});

test('an unknown API route is a 404 problem', async () => {
  const r = await fetch(`${d.url}/v1/nothing-here`);
  assert.equal(r.status, 404);
  assert.equal(r.headers.get('content-type'), 'application/problem+json');
  const p = await r.json();
  assert.equal(p.status, 404);
  assert.equal(p.title, 'Not Found');
  assert.match(p.type, /^urn:meristem:problem:/);
  assert.match(p.detail, /\/v1\/nothing-here/);
});

test('a wrong method is a 405 problem with Allow', async () => {
  const r = await fetch(`${d.url}/v1/health`, { method: 'DELETE' });
  assert.equal(r.status, 405);
  assert.equal(r.headers.get('allow'), 'GET, HEAD');
  assert.equal(r.headers.get('content-type'), 'application/problem+json');
  assert.match((await r.json()).detail, /DELETE is not allowed/);

  const s = await fetch(`${d.url}/index.html`, { method: 'POST', body: '{}' });
  assert.equal(s.status, 405);
  assert.equal(s.headers.get('allow'), 'GET, HEAD');
});

test('a body over --max-body is a 413 problem', async () => {
  const r = await fetch(`${d.url}/v1/health`, { method: 'POST', body: 'x'.repeat(9 * 1024 * 1024) });
  assert.equal(r.status, 413);
  assert.equal(r.headers.get('content-type'), 'application/problem+json');
  assert.match((await r.json()).detail, /--max-body/);
});

test('each request is logged with method, path, status, bytes and time', async () => {
  await fetch(`${d.url}/v1/health`);
  assert.match(d.log(), /GET \/v1\/health 200 \d+ \d+\.\d+ms/);
});


test('SIGTERM and SIGINT stop meristemd cleanly with exit status 0', async () => {
  for (const signal of ['SIGTERM', 'SIGINT']) {
    const d = await startDaemon();
    assert.equal((await fetch(`${d.url}/v1/health`)).status, 200);
    const result = await d.stop(signal);
    assert.deepEqual(result, { code: 0, signal: null }, d.log());
    assert.match(d.log(), /shutting down/);
  }
});

test('command-line options', () => {
  const exe = process.env.MERISTEMD;
  const help = spawnSync(exe, ['--help'], { encoding: 'utf8' });
  assert.equal(help.status, 0);
  for (const opt of ['--bind', '--port', '--web-root', '--data-dir', '--threads', '--help', '--version'])
    assert.ok(help.stdout.includes(opt), `--help mentions ${opt}`);
  assert.match(help.stdout, /--bind=VALUE.*default 127\.0\.0\.1/);

  const version = spawnSync(exe, ['--version'], { encoding: 'utf8' });
  assert.equal(version.status, 0);
  assert.equal(version.stdout.trim(), `meristemd ${process.env.PACKAGE_VERSION}`);

  const bad = spawnSync(exe, ['--port', '70000'], { encoding: 'utf8' });
  assert.equal(bad.status, 2);
  assert.match(bad.stderr, /--port wants an integer from 0 to 65535, got '70000'/);

  const unknown = spawnSync(exe, ['--frobnicate'], { encoding: 'utf8' });
  assert.equal(unknown.status, 2);
  assert.match(unknown.stderr, /unknown or incomplete option '--frobnicate'/);

  const noRoot = spawnSync(exe, ['--port', '0', '--web-root', '/nonexistent/web'], { encoding: 'utf8' });
  assert.equal(noRoot.status, 1);
  assert.match(noRoot.stderr, /--web-root '\/nonexistent\/web' does not exist/);
});

test('--bind refuses what is not an IP address', async () => {
  const bad = spawnSync(process.env.MERISTEMD, ['--port', '0', '--bind', 'not-an-address',
    '--web-root', process.env.MER_WEB_ROOT], { encoding: 'utf8' });
  assert.equal(bad.status, 1);
  assert.match(bad.stderr, /--bind 'not-an-address' is not an IPv4 or IPv6 address/);
});
