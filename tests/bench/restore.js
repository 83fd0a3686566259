'use strict';
// Restore time of a big data folder: 1,000 sessions of 200 edits each, made by
// driving a real meristemd over HTTP (preset "default", seed k, with 1,000
// markers instead of 20,000 and bounds of 40 x 40 x 40 instead of 100 x 100 x
// 100, so that a checkpoint (which holds the shadow grid) is 1.6 MB instead of
// 5 MB and 1,000 loaded sessions fit in memory; each session's edits are 20 rounds of one `step`
// and nine `add_markers` of one point, so 200 journal records and 20 steps;
// checkpoints every 50 revisions, the default). Then meristemd is started on it and the figures are printed,
// never judged:
//  - time to listen: from spawn until GET /v1/health answers 200;
//  - time to the first answer from the oldest session: from spawn until
//    GET /v1/sessions/{oldest} answers 200 (asked as soon as health answers),
//    without the background loader (--warm-up=off) and with it;
//  - how long the background loader takes to load them all (what meristemd
//    spent before it listened, when it restored every session first).
// Spawning costs what the first line (an empty folder) shows: through the
// libtool wrapper of a build tree that is half a second more than the binary.
// The folder is kept (BENCH_RESTORE_DIR, default ./bench-restore-data) and
// reused when it holds the sessions already. Run from the top of the source
// tree with MERISTEMD (the daemon) and MER_WEB_ROOT (web/) set:
//   MERISTEMD=build/server/meristemd MER_WEB_ROOT=web node tests/bench/restore.js [sessions] [edits]
const { spawn } = require('node:child_process');
const fs = require('node:fs');
const path = require('node:path');
const { startDaemon, api } = require('../support/daemon.js');

const SESSIONS = Number(process.argv[2] || 1000);
const EDITS = Number(process.argv[3] || 200);
const DIR = path.resolve(process.env.BENCH_RESTORE_DIR || 'bench-restore-data');
const CLIENTS = 8;
const PARAMS = { marker_count: 1000, 'bounds_min.x': -20, 'bounds_min.z': -20, 'bounds_max.x': 20,
  'bounds_max.y': 40, 'bounds_max.z': 20 };

const edit = (k, i) => (i % 10 === 0 ? { op: 'step', count: 1 }
  : { op: 'add_markers', points: [[(k % 7) - 3 + i / 100, 4 + (i % 9), ((i * 7) % 11) / 2 - 2.5]] });

async function build() {
  const journals = fs.existsSync(DIR) ? fs.readdirSync(DIR).filter((f) => f.endsWith('.journal')) : [];
  const marker = path.join(DIR, 'bench-complete');
  if (journals.length === SESSIONS && fs.existsSync(marker) &&
      fs.readFileSync(marker, 'utf8') === `${SESSIONS} ${EDITS}`) {
    console.log(`reusing ${DIR}: ${SESSIONS} sessions of ${EDITS} edits`);
    return fs.readFileSync(path.join(DIR, 'oldest'), 'utf8');
  }
  fs.rmSync(DIR, { recursive: true, force: true });
  fs.mkdirSync(DIR, { recursive: true });
  const t0 = Date.now();
  // --fsync=interval only to build the folder sooner; the bytes are the same.
  const d = await startDaemon(['--fsync', 'interval', '--workers', '2', '--quiet'], { dataDir: DIR });
  let oldest = null;
  let next = 0;
  try {
    const client = async () => {
      for (let k = next++; k < SESSIONS; k = next++) {
        const c = await api(d.url, 'POST', '/v1/sessions', { preset: 'default', seed: k, params: PARAMS });
        if (c.status !== 201) throw new Error(JSON.stringify(c.body));
        if (k === 0) oldest = c.body.id;
        for (let i = 0; i < EDITS; i++) {
          const r = await api(d.url, 'POST', `/v1/sessions/${c.body.id}/edits`, edit(k, i));
          if (r.status !== 200) throw new Error(JSON.stringify(r.body));
        }
        if (k % 100 === 99) console.log(`  ${k + 1} sessions, ${((Date.now() - t0) / 1000).toFixed(0)} s`);
      }
    };
    await Promise.all(Array.from({ length: CLIENTS }, client));
  } finally {
    await d.stop();
  }
  // Make session 0 the oldest by its journal's time, as a long-lived folder would.
  const old = new Date(Date.now() - 86400e3);
  for (const f of fs.readdirSync(DIR).filter((x) => x.startsWith(oldest))) fs.utimesSync(path.join(DIR, f), old, old);
  fs.writeFileSync(path.join(DIR, 'oldest'), oldest);
  fs.writeFileSync(marker, `${SESSIONS} ${EDITS}`);
  console.log(`built ${DIR}: ${SESSIONS} sessions of ${EDITS} edits in ${((Date.now() - t0) / 1000).toFixed(0)} s`);
  return oldest;
}

const sleep = (ms) => new Promise((res) => setTimeout(res, ms));

/** Starts meristemd on the folder and times health and the oldest session. */
async function measure(oldest, warmUp, dir = DIR) {
  const args = ['--port', '0', '--web-root', process.env.MER_WEB_ROOT, '--data-dir', dir, '--quiet',
    '--warm-up', warmUp];
  const t0 = process.hrtime.bigint();
  const ms = () => Number(process.hrtime.bigint() - t0) / 1e6;
  const child = spawn(process.env.MERISTEMD, args, { stdio: ['ignore', 'pipe', 'pipe'] });
  let out = '';
  child.stdout.on('data', (x) => { out += x; });
  child.stderr.on('data', (x) => { out += x; });
  let port = null;
  while (port === null) {
    const m = out.match(/listening on http:\/\/[^:]+:(\d+)\//);
    if (m) port = Number(m[1]);
    else await sleep(1);
  }
  const base = `http://127.0.0.1:${port}`;
  let health = null;
  while (health === null) {
    try { if ((await fetch(`${base}/v1/health`)).status === 200) health = ms(); } catch { await sleep(1); }
  }
  if (oldest === null) {
    child.kill('SIGTERM');
    await new Promise((res) => child.on('exit', res));
    return { health };
  }
  const list = await api(base, 'GET', '/v1/sessions');
  const notLoaded = list.body.sessions.filter((s) => s.state === 'not loaded').length;
  const s = await api(base, 'GET', `/v1/sessions/${oldest}`);
  if (s.status !== 200) throw new Error(JSON.stringify(s.body));
  const first = ms();
  let all = null;
  if (warmUp === 'background') {
    while (!/restored \d+ sessions in the background in ([\d.]+) s/.test(out)) await sleep(20);
    all = Number(/restored \d+ sessions in the background in ([\d.]+) s/.exec(out)[1]);
  }
  child.kill('SIGTERM');
  await new Promise((res) => child.on('exit', res));
  return { health, first, notLoaded, revision: s.body.revision, all };
}

(async () => {
  if (!process.env.MERISTEMD || !process.env.MER_WEB_ROOT) throw new Error('set MERISTEMD and MER_WEB_ROOT');
  const oldest = await build();
  // What starting the process costs, whatever the data folder holds.
  const empty = fs.mkdtempSync(path.join(require('node:os').tmpdir(), 'meristem-bench-empty-'));
  const base = [];
  for (let i = 0; i < 3; i++) base.push((await measure(null, 'off', empty)).health);
  fs.rmSync(empty, { recursive: true, force: true });
  console.log(`an empty data folder: health answers ${base.sort((a, b) => a - b)[1].toFixed(1)} ms after spawn (median of 3)`);
  // Three runs each; one with the background loader, which loads them all.
  for (const [warmUp, n] of [['off', 3], ['background', 1]]) {
    const runs = [];
    for (let i = 0; i < n; i++) runs.push(await measure(oldest, warmUp));
    const med = (key) => runs.map((r) => r[key]).sort((a, b) => a - b)[n >> 1];
    console.log(`--warm-up=${warmUp}: time to listen (health 200) ${med('health').toFixed(1)} ms; ` +
      `first answer from the oldest session (revision ${runs[0].revision}) ${med('first').toFixed(1)} ms ` +
      `after spawn; ${runs[0].notLoaded} of ${SESSIONS} listed "not loaded" when health answered` +
      (warmUp === 'background' ? `; all loaded in the background in ${med('all').toFixed(2)} s` : '') +
      (n > 1 ? ` (median of ${n})` : ''));
  }
})().catch((e) => { console.error(e); process.exit(1); });
