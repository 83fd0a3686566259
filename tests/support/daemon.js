'use strict';
// Starts a real meristemd on a free loopback port for a test and stops it after.
const { spawn } = require('node:child_process');
const fs = require('node:fs');
const os = require('node:os');
const path = require('node:path');
const assert = require('node:assert/strict');

/**
 * The program to spawn for `exe` and its environment (this process's, now). In
 * a build tree `exe` is libtool's wrapper script, which sets the library path
 * and execs .libs/NAME after a dozen shell commands of its own; the suite
 * starts meristemd a few hundred times, so the wrapper is read once and the
 * program run directly, with the library path the wrapper would set. Anything
 * else is run as is.
 */
const programs = new Map();
function program(exe) {
  if (!programs.has(exe)) {
    let found = { exe, libs: null };
    const real = path.join(path.dirname(exe), '.libs', path.basename(exe));
    const script = fs.existsSync(real) ? fs.readFileSync(exe, 'latin1') : '';
    const m = /^\s*LD_LIBRARY_PATH="([^"$]+):\$LD_LIBRARY_PATH"$/m.exec(script);
    if (script.startsWith('#!') && /libtool/.test(script) && m) found = { exe: real, libs: m[1] };
    programs.set(exe, found);
  }
  const { exe: file, libs } = programs.get(exe);
  if (!libs) return { exe: file, env: process.env };
  const paths = [libs, process.env.LD_LIBRARY_PATH].filter(Boolean).join(':');
  return { exe: file, env: { ...process.env, LD_LIBRARY_PATH: paths } };
}

/**
 * Starts meristemd with `--port 0` and resolves once it logs the URL it listens on.
 * @param {string[]} extraArgs more command-line options
 * @param {{dataDir?: string, keepData?: boolean}} options an existing data folder to use
 *   (and keep, unless keepData is false)
 * @returns {Promise<{url: string, port: number, child: import('node:child_process').ChildProcess,
 *   dataDir: string, log: () => string, waitForLog: (pattern: RegExp) => Promise<string>,
 *   stop: (signal?: string) => Promise<{code: number|null, signal: string|null}>,
 *   restart: (args?: string[], options?: {signal?: string, whileDown?: () => void}) => Promise<object>}>}
 */
async function startDaemon(extraArgs = [], options = {}) {
  if (!process.env.MERISTEMD) throw new Error('MERISTEMD is not set; run the tests with make check');
  const { exe, env } = program(process.env.MERISTEMD);
  const keepData = options.keepData ?? Boolean(options.dataDir);
  const dataDir = options.dataDir || fs.mkdtempSync(path.join(os.tmpdir(), 'meristem-test-'));
  const args = ['--port', '0', '--web-root', process.env.MER_WEB_ROOT, '--data-dir', dataDir,
    ...extraArgs];
  const child = spawn(exe, args, { stdio: ['ignore', 'pipe', 'pipe'], env });
  let output = '';
  child.stdout.on('data', (d) => { output += d; });
  child.stderr.on('data', (d) => { output += d; });
  const exited = new Promise((resolve) => child.on('exit', (code, signal) => resolve({ code, signal })));

  const port = await new Promise((resolve, reject) => {
    const timer = setTimeout(() => reject(new Error(`meristemd did not start:\n${output}`)), 15000);
    const look = () => {
      const m = output.match(/listening on http:\/\/[^:]+:(\d+)\//);
      if (m) { clearTimeout(timer); resolve(Number(m[1])); }
    };
    child.stdout.on('data', look);
    exited.then(() => { clearTimeout(timer); reject(new Error(`meristemd exited early:\n${output}`)); });
  });

  return {
    url: `http://127.0.0.1:${port}`,
    port,
    child,
    dataDir,
    log: () => output,
    /** Resolves once the log matches `pattern` (rejects with the log if the
     * daemon exits first, or after 60 s): to wait for what the daemon does in
     * the background, such as loading its sessions. */
    waitForLog(pattern) {
      return new Promise((resolve, reject) => {
        const timer = setTimeout(() => { done(); reject(new Error(`no ${pattern} in the log:\n${output}`)); }, 60000);
        const look = () => { if (pattern.test(output)) { done(); resolve(output); } };
        const gone = () => { done(); reject(new Error(`meristemd exited before ${pattern}:\n${output}`)); };
        const done = () => { clearTimeout(timer); child.stdout.off('data', look); child.stderr.off('data', look); child.off('exit', gone); };
        child.stdout.on('data', look);
        child.stderr.on('data', look);
        child.on('exit', gone);
        look();
      });
    },
    async stop(signal = 'SIGTERM') {
      if (child.exitCode === null && child.signalCode === null) child.kill(signal);
      const result = await exited;
      if (!keepData) fs.rmSync(dataDir, { recursive: true, force: true });
      return result;
    },
    /** A crash and the next start: kills the daemon (SIGKILL unless `signal`
     * says otherwise), runs `whileDown` (to change the data folder as the crash
     * left it), and starts another daemon with `args` (default: this one's) on
     * the same data folder, which it then owns as this one did. Resolves to the
     * new daemon; this one is spent. */
    async restart(args = extraArgs, { signal = 'SIGKILL', whileDown = () => {} } = {}) {
      if (child.exitCode === null && child.signalCode === null) child.kill(signal);
      await exited;
      whileDown();
      return startDaemon(args, { dataDir, keepData });
    },
  };
}

/** What a restored session is compared with: its summary and GLB (`query`). */
async function sessionState(base, id, query = '') {
  const summary = await api(base, 'GET', `/v1/sessions/${id}`);
  assert.equal(summary.status, 200, JSON.stringify(summary.body));
  const glb = await api(base, 'GET', `/v1/sessions/${id}/snapshot.glb${query}`);
  assert.equal(glb.status, 200);
  return { summary: summary.body, glb: glb.raw, query };
}

/** Asserts that the session `id` answers as `before` (sessionState) did: the
 * same revision and hash, the same `keys` of the summary, the same GLB bytes. */
async function assertRestored(base, id, before, keys = [], what = 'after restore') {
  const now = await sessionState(base, id, before.query);
  assert.equal(now.summary.revision, before.summary.revision, `the revision ${what}`);
  assert.equal(now.summary.hash, before.summary.hash, `the hash ${what}`);
  for (const k of keys) assert.deepEqual(now.summary[k], before.summary[k], `${k} ${what}`);
  assert.ok(Buffer.compare(now.glb, before.glb) === 0, `the same GLB bytes ${what}`);
}

/** JSON request helper: returns {status, headers, body (parsed when JSON), raw}. */
async function api(base, method, p, body, headers = {}) {
  const init = { method, headers: { ...headers } };
  if (body !== undefined) {
    init.body = typeof body === 'string' ? body : JSON.stringify(body);
    if (!('Content-Type' in init.headers)) init.headers['Content-Type'] = 'application/json';
  }
  const r = await fetch(base + p, init);
  const raw = Buffer.from(await r.arrayBuffer());
  const type = r.headers.get('content-type') || '';
  let parsed = null;
  if (type.includes('json')) parsed = JSON.parse(raw.toString('utf8'));
  return { status: r.status, headers: r.headers, body: parsed, raw };
}

module.exports = { startDaemon, api, sessionState, assertRestored };
