'use strict';
// Static files from the web root: MIME types, index.html, and no way out.
const { test, before, after } = require('node:test');
const assert = require('node:assert/strict');
const fs = require('node:fs');
const net = require('node:net');
const os = require('node:os');
const path = require('node:path');
const { startDaemon } = require('../support/daemon.js');

// fetch() normalizes "/../" away before sending, so traversal attempts go out raw.
function rawGet(port, target) {
  return new Promise((resolve, reject) => {
    const socket = net.connect(port, '127.0.0.1', () => {
      socket.write(`GET ${target} HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n`);
    });
    let data = '';
    socket.setEncoding('latin1');
    socket.on('data', (chunk) => { data += chunk; });
    socket.on('end', () => {
      const [head, ...body] = data.split('\r\n\r\n');
      const status = Number(head.split(' ')[1]);
      const type = (head.match(/^content-type:\s*(.*)$/im) || [])[1];
      resolve({ status, type, body: body.join('\r\n\r\n') });
    });
    socket.on('error', reject);
  });
}

// A web root of our own, with symlinks that point outside it.
let d, root, outside;
before(async () => {
  root = fs.mkdtempSync(path.join(os.tmpdir(), 'meristem-web-'));
  outside = fs.mkdtempSync(path.join(os.tmpdir(), 'meristem-outside-'));
  fs.writeFileSync(path.join(outside, 'secret.txt'), 'TOP-SECRET-CONTENT');
  fs.writeFileSync(path.join(root, 'index.html'), '<!doctype html><title>t</title>');
  fs.mkdirSync(path.join(root, 'js'));
  fs.writeFileSync(path.join(root, 'js', 'app.js'), 'export {};');
  fs.writeFileSync(path.join(root, 'tree.glb'), 'glTF');
  fs.writeFileSync(path.join(root, 'style.css'), 'body{}');
  fs.symlinkSync(path.join(outside, 'secret.txt'), path.join(root, 'link.txt'));
  fs.symlinkSync(outside, path.join(root, 'linkdir'));

  d = await startDaemon(['--web-root', root]);
});
after(async () => {
  await d.stop();
  fs.rmSync(root, { recursive: true, force: true });
  fs.rmSync(outside, { recursive: true, force: true });
});

test('/ serves index.html as HTML', async () => {
  const r = await fetch(`${d.url}/`);
  assert.equal(r.status, 200);
  assert.equal(r.headers.get('content-type'), 'text/html; charset=utf-8');
  assert.match(await r.text(), /<title>t<\/title>/);
});

test('MIME types follow the extension', async () => {
  for (const [p, type] of [['/js/app.js', 'text/javascript; charset=utf-8'],
    ['/style.css', 'text/css; charset=utf-8'], ['/tree.glb', 'model/gltf-binary']]) {
    const r = await fetch(d.url + p);
    assert.equal(r.status, 200, p);
    assert.equal(r.headers.get('content-type'), type, p);
  }
});

test('a folder without a trailing slash redirects', async () => {
  const r = await fetch(`${d.url}/js`, { redirect: 'manual' });
  assert.equal(r.status, 301);
  assert.equal(r.headers.get('location'), '/js/');
});

test('a missing file is a 404 problem', async () => {
  const r = await fetch(`${d.url}/missing.js`);
  assert.equal(r.status, 404);
  assert.equal(r.headers.get('content-type'), 'application/problem+json');
});

// The repository's own configure.ac lies one level above the real web root;
// these are the requests the foundation issue names, plus their cousins.
const escapes = ['/../configure.ac', '/%2e%2e/configure.ac', '/%2E%2E/configure.ac',
  '/js/../../configure.ac', '/..%2fconfigure.ac', '/%2e%2e%2fconfigure.ac',
  '//etc/passwd', '/etc/passwd', '/./index.html', '/link.txt', '/linkdir/secret.txt',
  '/..\\configure.ac', '/%00index.html'];
test('no request leaves the web root', async () => {
  for (const target of escapes) {
    const r = await rawGet(d.port, target);
    assert.equal(r.status, 404, `${target} → ${r.status}`);
    assert.equal(r.type, 'application/problem+json', target);
    assert.doesNotMatch(r.body, /TOP-SECRET|root:x:|AC_INIT/, target);
  }
});

// The real web root lies in the build folder, beside its Makefile (and, in an
// in-tree build, configure.ac): both are one "/../" away.
test('the real web root refuses /../configure.ac and its cousins', async (t) => {
  const real = await startDaemon();
  t.after(() => real.stop());
  assert.ok(fs.existsSync(path.join(process.env.MER_WEB_ROOT, '..', 'Makefile')));
  for (const target of ['/../configure.ac', '/%2e%2e/configure.ac', '/../Makefile',
    '/%2e%2e/Makefile', '/%2E%2E/Makefile']) {
    const r = await rawGet(real.port, target);
    assert.equal(r.status, 404, target);
    assert.equal(r.type, 'application/problem+json');
    assert.equal(JSON.parse(r.body).status, 404);
    assert.doesNotMatch(r.body, /automake|AC_INIT/, target);
  }
});

test('the real web root serves the page and three.js', async (t) => {
  const real = await startDaemon();
  t.after(() => real.stop());
  const page = await fetch(`${real.url}/`);
  assert.equal(page.status, 200);
  assert.match(await page.text(), /<title>meristem<\/title>/);
  const three = await fetch(`${real.url}/node_modules/three/build/three.module.js`);
  assert.equal(three.status, 200);
  assert.equal(three.headers.get('content-type'), 'text/javascript; charset=utf-8');
});
