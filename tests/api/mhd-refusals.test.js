'use strict';
// The requests libmicrohttpd 0.9.75 would refuse itself with a fixed HTML page
// (transmit_error_response_static() in src/microhttpd/connection.c) before any
// of meristemd's code runs. meristemd's front (server/front.h) sees each new
// connection's first request head before libmicrohttpd does and answers these
// with the same status as an RFC 9457 problem. This test sends each one on a
// fresh connection, checks status and body, and that the daemon keeps answering.
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

/** Checks that `reply` is a whole problem+json answer with `status`. */
function assertProblem(reply, status, name) {
  const shown = JSON.stringify(reply.slice(0, 300));
  const m = reply.match(/^HTTP\/1\.[01] (\d{3}) [^\r\n]*\r\n([\s\S]*?)\r\n\r\n([\s\S]*)$/);
  assert.ok(m, `${name}: no HTTP answer in ${shown}`);
  assert.equal(Number(m[1]), status, `${name}: ${shown}`);
  assert.match(m[2], /^Content-Type: application\/problem\+json$/mi, `${name}: ${shown}`);
  const length = m[2].match(/^Content-Length: (\d+)$/mi);
  assert.ok(length, `${name}: no Content-Length in ${shown}`);
  assert.equal(Buffer.byteLength(m[3], 'latin1'), Number(length[1]), `${name}: body length`);
  const problem = JSON.parse(m[3]);
  assert.equal(problem.status, status, name);
  assert.match(problem.type, /^urn:meristem:problem:[a-z-]+$/, name);
  assert.equal(typeof problem.title, 'string', name);
  assert.ok(problem.detail.length > 10, `${name}: a detail that says what to do`);
}

/** The requests libmicrohttpd would refuse, each with the status it would give. */
function badRequests(port) {
  const host = `Host: 127.0.0.1:${port}\r\n`;
  return [
    { name: 'request line over --connection-memory', status: 414,
      text: `GET /v1/health?pad=${'a'.repeat(2 * MEMORY)} HTTP/1.1\r\n${host}\r\n` },
    { name: 'header block over --connection-memory', status: 431,
      text: `GET /v1/health HTTP/1.1\r\n${host}X-Pad: ${'a'.repeat(2 * MEMORY)}\r\n\r\n` },
    { name: 'many small header lines over --connection-memory', status: 431,
      text: `GET /v1/health HTTP/1.1\r\n${host}${'a:\r\n'.repeat(MEMORY / 8)}\r\n` },
    { name: 'header line without a colon', status: 400,
      text: `GET /v1/health HTTP/1.1\r\n${host}no colon here\r\n\r\n` },
    { name: 'request line without a space', status: 400, text: 'GARBAGE\r\n\r\n' },
    { name: 'request line without a version', status: 400, text: `GET /v1/health\r\n${host}\r\n` },
    { name: 'Content-Length that is not a number', status: 400,
      text: `POST /v1/sessions HTTP/1.1\r\n${host}Content-Length: ten\r\n\r\n` },
    { name: 'Content-Length with trailing junk', status: 400,
      text: `POST /v1/sessions HTTP/1.1\r\n${host}Content-Length: 2x\r\n\r\n{}` },
    { name: 'Content-Length over 64 bits', status: 413,
      text: `POST /v1/sessions HTTP/1.1\r\n${host}Content-Length: 99999999999999999999999\r\n\r\n` },
    { name: 'chunk size that is not hexadecimal', status: 400,
      text: `POST /v1/sessions HTTP/1.1\r\n${host}Content-Type: application/json\r\n` +
        'Transfer-Encoding: chunked\r\n\r\nzz\r\n{}\r\n0\r\n\r\n' },
    { name: 'chunk not followed by a line end', status: 400,
      text: `POST /v1/sessions HTTP/1.1\r\n${host}Content-Type: application/json\r\n` +
        'Transfer-Encoding: chunked\r\n\r\n2\r\n{}XX0\r\n\r\n' },
    { name: 'chunk size over 64 bits', status: 413,
      text: `POST /v1/sessions HTTP/1.1\r\n${host}Content-Type: application/json\r\n` +
        'Transfer-Encoding: chunked\r\n\r\nfffffffffffffffffffff\r\n{}\r\n0\r\n\r\n' },
    { name: 'unknown HTTP version', status: 505,
      text: `GET /v1/health HTTP/2.0\r\n${host}\r\n` },
    { name: 'HTTP/0.9', status: 505, text: `GET /v1/health HTTP/0.9\r\n${host}\r\n` },
    { name: 'folded header line', status: 400,
      text: `GET /v1/health HTTP/1.1\r\n${host}X-A: 1\r\n folded\r\n\r\n` },
    { name: 'bad chunk size deep in the body', status: 400,
      text: `POST /v1/sessions HTTP/1.1\r\n${host}Content-Type: application/json\r\n` +
        `Transfer-Encoding: chunked\r\n\r\n${(16 * MEMORY).toString(16)}\r\n${' '.repeat(16 * MEMORY)}\r\n` +
        'zz\r\n{}\r\n0\r\n\r\n' },
    { name: 'chunk not followed by a line end deep in the body', status: 400,
      text: `POST /v1/sessions HTTP/1.1\r\n${host}Content-Type: application/json\r\n` +
        `Transfer-Encoding: chunked\r\n\r\n${(16 * MEMORY).toString(16)}\r\n${' '.repeat(16 * MEMORY)}XX` +
        '0\r\n\r\n' },
  ];
}

/** Splits what a connection received into its responses (each with a
 * Content-Length); what follows the last whole one is `rest`. */
function responses(text) {
  const out = [];
  let at = 0;
  for (;;) {
    const end = text.indexOf('\r\n\r\n', at);
    if (end < 0) break;
    const head = text.slice(at, end);
    const length = head.match(/^Content-Length: (\d+)$/mi);
    const size = length ? Number(length[1]) : 0;
    if (end + 4 + size > text.length) break;
    out.push(text.slice(at, end + 4 + size));
    at = end + 4 + size;
  }
  return { list: out, rest: text.slice(at) };
}

/** A good request, then `bad` on the same connection: sent together
 * (pipelined) or once the first answer is in. Resolves with all read until
 * the daemon closes. */
function keptAlive(port, bad, pipelined) {
  const good = `GET /v1/health HTTP/1.1\r\nHost: 127.0.0.1:${port}\r\n\r\n`;
  return new Promise((resolve, reject) => {
    const socket = net.connect(port, '127.0.0.1');
    let reply = '';
    let sent = pipelined;
    const timer = setTimeout(() => { socket.destroy(); reject(new Error(`no close; got ${JSON.stringify(reply)}`)); }, 10000);
    socket.setEncoding('latin1');
    socket.on('data', (c) => {
      reply += c;
      if (!sent && responses(reply).list.length === 1) {
        sent = true;
        socket.write(bad);
      }
    });
    socket.on('error', () => {});
    socket.on('close', () => { clearTimeout(timer); resolve(reply); });
    socket.write(pipelined ? good + bad : good);
  });
}

test('the heads libmicrohttpd would refuse in HTML get problem+json, and the daemon keeps answering', async (t) => {
  const d = await startDaemon(['--quiet', '--connection-memory', String(MEMORY)]);
  t.after(() => d.stop());
  for (const c of badRequests(d.port)) {
    assertProblem(await raw(d.port, c.text), c.status, c.name);
    const health = await api(d.url, 'GET', '/v1/health');
    assert.equal(health.status, 200, `health after ${c.name}`);
  }
});

test('a bad request after a good one on a kept-alive connection gets problem+json too', async (t) => {
  const d = await startDaemon(['--quiet', '--connection-memory', String(MEMORY)]);
  t.after(() => d.stop());
  for (const pipelined of [false, true]) {
    for (const c of badRequests(d.port)) {
      const name = `${c.name}${pipelined ? ', pipelined' : ''}`;
      const reply = await keptAlive(d.port, c.text, pipelined);
      const { list, rest } = responses(reply);
      assert.equal(list.length, 2, `${name}: two answers in ${JSON.stringify(reply.slice(0, 400))}`);
      assert.match(list[0], /^HTTP\/1\.1 200 /, name);
      assert.equal(rest, '', `${name}: nothing after the refusal`);
      assertProblem(list[1], c.status, name);
    }
  }
  const health = await api(d.url, 'GET', '/v1/health');
  assert.equal(health.status, 200);
});

test('pipelined good requests are all answered, in order', async (t) => {
  const d = await startDaemon(['--quiet']);
  t.after(() => d.stop());
  const host = `Host: 127.0.0.1:${d.port}\r\n`;
  const body = '{"preset":"fig7-bh-0.54","seed":1}';
  const text = `GET /v1/health HTTP/1.1\r\n${host}\r\n` +
    `POST /v1/sessions HTTP/1.1\r\n${host}Content-Type: application/json\r\nContent-Length: ${body.length}\r\n\r\n${body}` +
    `POST /v1/sessions HTTP/1.1\r\n${host}Content-Type: application/json\r\nTransfer-Encoding: chunked\r\n\r\n` +
    `${body.length.toString(16)}\r\n${body}\r\n0\r\nX-Trailer: 1\r\n\r\n` +
    `GET /v1/health HTTP/1.1\r\n${host}Connection: close\r\n\r\n`;
  const { list, rest } = responses(await raw(d.port, text));
  assert.deepEqual(list.map((r) => Number(r.slice(9, 12))), [200, 201, 201, 200]);
  assert.equal(rest, '');
});

test('heads that libmicrohttpd takes still reach meristemd', async (t) => {
  const d = await startDaemon(['--quiet', '--connection-memory', String(MEMORY)]);
  t.after(() => d.stop());
  const host = `Host: 127.0.0.1:${d.port}\r\n`;
  const close = 'Connection: close\r\n';
  const cases = [
    { name: 'bare LF line ends', text: `GET /v1/health HTTP/1.1\n${host.replace('\r\n', '\n')}${close.replace('\r\n', '\n')}\n` },
    { name: 'empty lines before the request', text: `\r\n\r\nGET /v1/health HTTP/1.1\r\n${host}${close}\r\n` },
    { name: 'HTTP/1.0 without Host', text: 'GET /v1/health HTTP/1.0\r\n\r\n' },
    { name: 'a head under half of --connection-memory',
      text: `GET /v1/health HTTP/1.1\r\n${host}${close}X-Pad: ${'a'.repeat(MEMORY / 2 - 400)}\r\n\r\n` },
  ];
  for (const c of cases) {
    const reply = await raw(d.port, c.text);
    assert.match(reply, /^HTTP\/1\.1 200 /, `${c.name}: ${JSON.stringify(reply.slice(0, 200))}`);
  }
  // A chunked upload is framed right: meristemd's handler answers it.
  const body = '{}';
  const chunked = await raw(d.port, `POST /v1/sessions HTTP/1.1\r\n${host}${close}` +
    `Content-Type: application/json\r\nTransfer-Encoding: chunked\r\n\r\n` +
    `${body.length.toString(16)};ext=1\r\n${body}\r\n0\r\n\r\n`);
  assert.match(chunked, /^HTTP\/1\.1 201 /, JSON.stringify(chunked.slice(0, 300)));
});
