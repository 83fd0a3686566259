'use strict';
// Refusals that must come early and precisely: a prune of a plant's first
// internode, an announced oversize body, a full work queue.
const test = require('node:test');
const assert = require('node:assert/strict');
const net = require('node:net');
const { startDaemon, api } = require('../support/daemon.js');

test('a prune of the root is refused with 422 naming node, and the tree stays', async (t) => {
  const d = await startDaemon(['--quiet']);
  t.after(() => d.stop());
  const s = (await api(d.url, 'POST', '/v1/sessions', {})).body;
  const grown = await api(d.url, 'POST', `/v1/sessions/${s.id}/edits`, { op: 'step', count: 3 });
  assert.equal(grown.status, 200);
  const r = await api(d.url, 'POST', `/v1/sessions/${s.id}/edits`, { op: 'prune', node: 0 });
  assert.equal(r.status, 422);
  assert.equal(r.body.type, 'urn:meristem:problem:root-node');
  assert.equal(r.body.field, 'node');
  assert.match(r.body.detail, /first internode/);
  const b = await api(d.url, 'POST', `/v1/sessions/${s.id}/edits`, { edits: [{ op: 'step', count: 1 }, { op: 'prune', node: 0 }] });
  assert.equal(b.status, 422);
  assert.equal(b.body.field, 'edits[1].node');
  const after = await api(d.url, 'GET', `/v1/sessions/${s.id}`);
  assert.equal(after.body.revision, grown.body.revision);
  assert.equal(after.body.internodes, grown.body.internodes);
});

test('an announced oversize Content-Length is refused before the body is sent', async (t) => {
  const d = await startDaemon(['--quiet', '--max-body', '65536']);
  t.after(() => d.stop());
  const reply = await new Promise((resolve, reject) => {
    const socket = net.connect(d.port, '127.0.0.1');
    let text = '';
    const timer = setTimeout(() => { socket.destroy(); reject(new Error(`no answer without the body; got ${JSON.stringify(text)}`)); }, 10000);
    socket.on('data', (c) => {
      text += c;
      if (/\r\n\r\n[\s\S]*\}/.test(text)) { clearTimeout(timer); socket.destroy(); resolve(text); }
    });
    socket.on('error', reject);
    // Only the head: a client announcing 100 MB must not have to send it to learn the answer.
    socket.write(`POST /v1/sessions HTTP/1.1\r\nHost: 127.0.0.1:${d.port}\r\n` +
      'Content-Type: application/json\r\nContent-Length: 100000000\r\n\r\n');
  });
  assert.match(reply, /^HTTP\/1\.1 413 /);
  assert.match(reply, /application\/problem\+json/);
  assert.match(reply, /body-too-large/);
});

test('a full work queue answers 503 with Retry-After at once', async (t) => {
  const d = await startDaemon(['--quiet', '--workers', '1', '--max-queue', '1']);
  t.after(() => d.stop());
  const ids = [];
  for (let i = 0; i < 4; i++) ids.push((await api(d.url, 'POST', '/v1/sessions', {})).body.id);
  // One long batch holds the only worker...
  const long = api(d.url, 'POST', `/v1/sessions/${ids[0]}/edits`, { op: 'step', count: 1000 });
  while (!(await api(d.url, 'GET', `/v1/sessions/${ids[0]}`)).body.running.active)
    await new Promise((r) => setTimeout(r, 20));
  // ...one more may wait for it; the others are told to come back.
  const others = await Promise.all(ids.slice(1).map(async (id, i) => {
    await new Promise((r) => setTimeout(r, 50 * i));
    const r = api(d.url, 'POST', `/v1/sessions/${id}/edits`, { op: 'step', count: 1 });
    return i === 0 ? { pending: r } : r;
  }));
  for (const r of others.slice(1)) {
    assert.equal(r.status, 503);
    assert.equal(r.headers.get('retry-after'), '1');
    assert.equal(r.body.type, 'urn:meristem:problem:queue-full');
    assert.match(r.body.detail, /--max-queue/);
  }
  assert.equal((await api(d.url, 'POST', `/v1/sessions/${ids[0]}/cancel`)).status, 202);
  assert.equal((await long).status, 200);
  assert.equal((await others[0].pending).status, 200);
});

test('one address holds at most --max-connections-per-ip connections, kept-alive and arriving alike', async (t) => {
  const LIMIT = 8;
  const d = await startDaemon(['--quiet', '--max-connections-per-ip', String(LIMIT), '--header-timeout', '60']);
  t.after(() => d.stop());
  const sockets = [];
  t.after(() => sockets.forEach((s) => s.destroy()));
  const open = (text, waitForAnswer) => new Promise((resolve) => {
    const socket = net.connect(d.port, '127.0.0.1');
    sockets.push(socket);
    const state = { socket, closed: false, answered: false };
    socket.on('data', () => { state.answered = true; if (waitForAnswer) resolve(state); });
    socket.on('error', () => {});
    socket.on('close', () => { state.closed = true; resolve(state); });
    socket.on('connect', () => { socket.write(text); if (!waitForAnswer) setTimeout(() => resolve(state), 200); });
  });
  const host = `Host: 127.0.0.1:${d.port}\r\n`;
  // LIMIT kept-alive connections between requests, then LIMIT heads arriving.
  const kept = [];
  for (let i = 0; i < LIMIT; i++) kept.push(await open(`GET /v1/health HTTP/1.1\r\n${host}\r\n`, true));
  assert.ok(kept.every((s) => s.answered && !s.closed), 'the kept-alive connections are answered and open');
  const arriving = [];
  for (let i = 0; i < LIMIT; i++) arriving.push(await open(`GET /v1/health HTTP/1.1\r\n${host}`, false));
  await new Promise((r) => setTimeout(r, 500));
  const refused = arriving.filter((s) => s.closed).length;
  assert.equal(refused, LIMIT, `connections over the limit from one address are closed (${refused} of ${LIMIT})`);
  assert.ok(kept.every((s) => !s.closed), 'the kept-alive connections stay');
});
