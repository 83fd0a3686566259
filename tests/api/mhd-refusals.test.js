'use strict';
// The requests libmicrohttpd refuses itself, before meristemd sees them. In
// libmicrohttpd 0.9.75 each is answered by transmit_error_response_static()
// in src/microhttpd/connection.c with a fixed HTML body; no option, callback or
// access handler runs first (see proto/README.md, "Errors"). This test pins the
// status of each so that an upgrade that changes them is noticed, and checks
// that the daemon keeps answering after every one.
const test = require('node:test');
const assert = require('node:assert/strict');
const net = require('node:net');
const { startDaemon, api } = require('../support/daemon.js');

const MEMORY = 4096;

/** Sends `text` raw and resolves with everything read until the daemon closes. */
function raw(port, text) {
  return new Promise((resolve, reject) => {
    const socket = net.connect(port, '127.0.0.1');
    let reply = '';
    const timer = setTimeout(() => { socket.destroy(); reject(new Error(`no close; got ${JSON.stringify(reply)}`)); }, 10000);
    socket.setEncoding('latin1');
    socket.on('data', (c) => { reply += c; });
    socket.on('error', () => {});  // a reset after the answer is fine
    socket.on('close', () => { clearTimeout(timer); resolve(reply); });
    socket.write(text);
  });
}

test('libmicrohttpd\'s own refusals keep their status, and the daemon keeps answering', async (t) => {
  const d = await startDaemon(['--quiet', '--connection-memory', String(MEMORY)]);
  t.after(() => d.stop());
  const host = `Host: 127.0.0.1:${d.port}\r\n`;
  const cases = [
    { name: 'request line over --connection-memory', status: 414,
      text: `GET /v1/health?pad=${'a'.repeat(2 * MEMORY)} HTTP/1.1\r\n${host}\r\n` },
    { name: 'header block over --connection-memory', status: 431,
      text: `GET /v1/health HTTP/1.1\r\n${host}X-Pad: ${'a'.repeat(2 * MEMORY)}\r\n\r\n` },
    { name: 'header line without a colon', status: 400,
      text: `GET /v1/health HTTP/1.1\r\n${host}no colon here\r\n\r\n` },
    { name: 'Content-Length that is not a number', status: 400,
      text: `POST /v1/sessions HTTP/1.1\r\n${host}Content-Length: ten\r\n\r\n` },
    { name: 'Content-Length over 64 bits', status: 413,
      text: `POST /v1/sessions HTTP/1.1\r\n${host}Content-Length: 99999999999999999999999\r\n\r\n` },
    { name: 'chunk size that is not hexadecimal', status: 400,
      text: `POST /v1/sessions HTTP/1.1\r\n${host}Content-Type: application/json\r\n` +
        'Transfer-Encoding: chunked\r\n\r\nzz\r\n{}\r\n0\r\n\r\n' },
    { name: 'chunk size over 64 bits', status: 413,
      text: `POST /v1/sessions HTTP/1.1\r\n${host}Content-Type: application/json\r\n` +
        'Transfer-Encoding: chunked\r\n\r\nfffffffffffffffffffff\r\n{}\r\n0\r\n\r\n' },
    { name: 'unknown HTTP version', status: 505,
      text: `GET /v1/health HTTP/2.0\r\n${host}\r\n` },
  ];
  for (const c of cases) {
    const reply = await raw(d.port, c.text);
    const m = reply.match(/^HTTP\/1\.[01] (\d{3}) /);
    assert.ok(m, `${c.name}: no status line in ${JSON.stringify(reply.slice(0, 200))}`);
    assert.equal(Number(m[1]), c.status, `${c.name}: ${JSON.stringify(reply.slice(0, 200))}`);
    const health = await api(d.url, 'GET', '/v1/health');
    assert.equal(health.status, 200, `health after ${c.name}`);
  }
});

test('a request line without a space is closed unanswered, not answered in HTML', async (t) => {
  const d = await startDaemon(['--quiet']);
  t.after(() => d.stop());
  assert.equal(await raw(d.port, 'GARBAGE\r\n\r\n'), '');
  assert.equal((await api(d.url, 'GET', '/v1/health')).status, 200);
});
