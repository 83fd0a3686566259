'use strict';
// Slow clients cannot take the daemon down: thousands of connections that
// trickle their request heads a byte at a time, from many addresses and over
// --max-connections, while /v1/health keeps answering everyone else. The head
// deadline (--header-timeout) cuts them, and when the daemon is full the
// oldest connection not in a request makes room for a new one.
const test = require('node:test');
const assert = require('node:assert/strict');
const fs = require('node:fs');
const http = require('node:http');
const net = require('node:net');
const { startDaemon } = require('../support/daemon.js');

const PER_ADDRESS = 250;  // under the default --max-connections-per-ip (256)

/** This process's soft limit on open files (node cannot raise it). */
function fileLimit() {
  const m = fs.readFileSync('/proc/self/limits', 'utf8').match(/Max open files\s+(\d+)/);
  return m ? Number(m[1]) : 1024;
}

/** Sockets the daemon has open (its listener among them). */
function daemonSockets(pid) {
  let n = 0;
  for (const fd of fs.readdirSync(`/proc/${pid}/fd`)) {
    try { if (fs.readlinkSync(`/proc/${pid}/fd/${fd}`).startsWith('socket:')) n++; } catch { /* closed meanwhile */ }
  }
  return n;
}

/** One health check on a fresh connection: its status, or the error. */
function health(port) {
  return new Promise((resolve) => {
    const req = http.get({ host: '127.0.0.1', port, path: '/v1/health', agent: false }, (res) => {
      res.resume();
      res.on('end', () => resolve(res.statusCode));
    });
    req.setTimeout(10000, () => req.destroy(new Error('no answer in 10 s')));
    req.on('error', (e) => resolve(e.message));
  });
}

/** Slow clients: `count` connections from 127.0.0.2 up, each sending a request
 * head one byte every 500 ms and reconnecting when cut, as an attacker would. */
function slowClients(port, count) {
  const head = `GET /v1/health HTTP/1.1\r\nHost: 127.0.0.1:${port}\r\nX-Pad: ${'a'.repeat(200)}\r\n\r\n`;
  const state = { open: 0, cuts: 0, stopped: false, sockets: new Set() };
  const connect = (i) => {
    if (state.stopped) return;
    const socket = net.connect({ host: '127.0.0.1', port, localAddress: `127.0.0.${2 + Math.floor(i / PER_ADDRESS)}` });
    let sent = 0, connected = false;
    state.sockets.add(socket);
    socket.on('connect', () => { connected = true; state.open++; });
    socket.on('data', () => {});
    socket.on('error', () => {});
    socket.on('close', () => {
      state.sockets.delete(socket);
      if (connected) { state.open--; state.cuts++; }
      setTimeout(() => connect(i), 50 + Math.random() * 100);
    });
    socket.trickle = () => {
      if (connected && sent < head.length - 1 && !socket.destroyed) socket.write(head[sent++]);
    };
  };
  for (let i = 0; i < count; i++) connect(i);
  const timer = setInterval(() => { for (const s of state.sockets) s.trickle(); }, 500);
  state.stop = () => {
    state.stopped = true;
    clearInterval(timer);
    for (const s of state.sockets) s.destroy();
  };
  return state;
}

test('health answers while thousands of slow clients trickle their headers', async (t) => {
  // Room for the slow sockets, the health checks and the test's own files.
  const slow = Math.min(4000, fileLimit() - 600);
  if (slow < 1000) {
    t.skip(`the open-file limit (${fileLimit()}) leaves no room for a thousand slow clients`);
    return;
  }
  // Fewer slots than slow clients: they alone could fill the daemon.
  const DEADLINE_MS = 5000;  // --header-timeout's default
  const d = await startDaemon(['--quiet', '--max-connections', String(slow - 500)]);
  const attack = slowClients(d.port, slow);
  t.after(async () => { attack.stop(); await d.stop(); });

  for (let w = 0; w < 150 && attack.open < slow - 600; w++) await new Promise((r) => setTimeout(r, 100));
  const answers = [];
  let held = 0;
  // Past two head deadlines, and ten answers at least: the slow clients are
  // cut and come back while health answers (on a busy machine each answer
  // takes longer, so fewer are needed to see the deadlines go by).
  const start = Date.now();
  for (let i = 0; i < 40 && (i < 10 || Date.now() - start < 2 * DEADLINE_MS + 500); i++) {
    held = Math.max(held, daemonSockets(d.child.pid));
    answers.push(await health(d.port));
    if (answers.at(-1) !== 200) break;
    await new Promise((r) => setTimeout(r, 300));
  }
  const failed = answers.filter((a) => a !== 200);
  assert.deepEqual(failed, [], `health failed ${failed.length} of ${answers.length} times`);
  assert.ok(attack.cuts > 0, 'slow clients are cut');
  t.diagnostic(`the daemon held up to ${held} connections (${slow} slow clients trying) with health answering ` +
    `${answers.length} of ${answers.length}; ${attack.cuts} cuts`);
});

test('a head trickled slower than --header-timeout is cut, however busy the client', async (t) => {
  const d = await startDaemon(['--quiet', '--header-timeout', '1']);
  t.after(() => d.stop());
  const outcome = await new Promise((resolve) => {
    const socket = net.connect(d.port, '127.0.0.1');
    const head = `GET /v1/health HTTP/1.1\r\nHost: 127.0.0.1:${d.port}\r\n${'X-Pad: a\r\n'.repeat(100)}\r\n`;
    let sent = 0;
    // A byte every 100 ms is never idle, so only a deadline on the head ends it.
    const timer = setInterval(() => { if (sent < head.length - 1) socket.write(head[sent++]); }, 100);
    const guard = setTimeout(() => { clearInterval(timer); socket.destroy(); resolve('still open after 20 s'); }, 20000);
    socket.on('error', () => {});
    socket.on('close', () => { clearInterval(timer); clearTimeout(guard); resolve(`cut after ${sent} bytes`); });
  });
  assert.match(outcome, /^cut after/);
  assert.equal((await fetch(`${d.url}/v1/health`)).status, 200);
});
