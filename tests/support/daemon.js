'use strict';
// Starts a real meristemd on a free loopback port for a test and stops it after.
const { spawn } = require('node:child_process');
const fs = require('node:fs');
const os = require('node:os');
const path = require('node:path');

/**
 * Starts meristemd with `--port 0` and resolves once it logs the URL it listens on.
 * @param {string[]} extraArgs more command-line options
 * @param {{dataDir?: string}} options an existing data folder to use (and keep)
 * @returns {Promise<{url: string, port: number, child: import('node:child_process').ChildProcess,
 *   dataDir: string, log: () => string, waitForLog: (pattern: RegExp) => Promise<string>,
 *   stop: (signal?: string) => Promise<{code: number|null, signal: string|null}>}>}
 */
async function startDaemon(extraArgs = [], options = {}) {
  const exe = process.env.MERISTEMD;
  if (!exe) throw new Error('MERISTEMD is not set; run the tests with make check');
  const keepData = Boolean(options.dataDir);
  const dataDir = options.dataDir || fs.mkdtempSync(path.join(os.tmpdir(), 'meristem-test-'));
  const args = ['--port', '0', '--web-root', process.env.MER_WEB_ROOT, '--data-dir', dataDir,
    ...extraArgs];
  const child = spawn(exe, args, { stdio: ['ignore', 'pipe', 'pipe'] });
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
  };
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

module.exports = { startDaemon, api };
