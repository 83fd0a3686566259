'use strict';
// The time meristemd takes to refuse an edit on a grown tree: a prune of a node
// that never existed, alone and at the end of a batch, against a GET of the same
// session. Printed, never judged. Run with MERISTEMD (the daemon) and
// MER_WEB_ROOT (web/) set, from the top of the source tree:
//   MERISTEMD=build/server/meristemd MER_WEB_ROOT=web node tests/bench/refused-edit.js [internodes]
const { startDaemon, api } = require('../support/daemon.js');

const want = Number(process.argv[2] || 20000);
const N = 20;

async function time(fn) {
  const t = [];
  for (let i = 0; i < N; i++) {
    const t0 = process.hrtime.bigint();
    await fn();
    t.push(Number(process.hrtime.bigint() - t0) / 1e6);
  }
  t.sort((a, b) => a - b);
  return `median ${t[N >> 1].toFixed(2)} ms, min ${t[0].toFixed(2)} ms`;
}

(async () => {
  const d = await startDaemon(['--max-steps', '1000']);
  try {
    const c = await api(d.url, 'POST', '/v1/sessions', { preset: 'default', seed: 1 });
    const id = c.body.id;
    let s = c.body;
    while (s.internodes < want) {
      const r = await api(d.url, 'POST', `/v1/sessions/${id}/edits`, { op: 'step', count: 1 });
      if (r.status !== 200) throw new Error(JSON.stringify(r.body));
      s = r.body;
    }
    console.log(`tree: ${s.internodes} internodes after ${s.step} steps (${s.step} journal records)`);
    const edit = (body, status) => async () => {
      const r = await api(d.url, 'POST', `/v1/sessions/${id}/edits`, body);
      if (r.status !== status) throw new Error(`${r.status} ${JSON.stringify(r.body)}`);
    };
    console.log('GET summary:          ', await time(async () => api(d.url, 'GET', `/v1/sessions/${id}`)));
    console.log('refused prune:        ', await time(edit({ op: 'prune', node: 99999999 }, 404)));
    console.log('refused 2-edit batch: ', await time(edit({ edits: [{ op: 'release' },
      { op: 'prune', node: 99999999 }] }, 404)));
  } finally {
    await d.stop();
  }
})().catch((e) => { console.error(e); process.exit(1); });
