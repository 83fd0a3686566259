'use strict';
// `make bench-page`: the brush client loading and drawing snapshots of a 10,000-internode
// tree in headless Chromium (software WebGL), as the issue states its target. Prints
// figures, judges nothing. For each of ROUNDS fresh pages: when the tree is first drawn
// after navigation (opening a shared link), then loads after colour-mode changes (each a new snapshot the daemon meshes and
// encodes), split into fetch, parse (GLTFLoader with the meshopt decoder) and draw (until
// the frame is finished: one pixel read back).
const path = require('node:path');
const { chromium } = require('playwright-core');
const { startDaemon, api } = require('../support/daemon.js');

const ROUNDS = Number(process.env.ROUNDS || 5);
const ARGS = ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
  '--disable-background-networking', '--disable-component-update', '--disable-sync',
  '--use-angle=swiftshader', '--enable-unsafe-swiftshader'];
const MODES = ['order', 'none', 'light', 'none', 'age', 'none', 'order', 'none'];

const median = (xs) => { const s = [...xs].sort((a, b) => a - b); return s[(s.length - 1) >> 1]; };
const f = (x) => x.toFixed(0);

(async () => {
  const d = await startDaemon(['--quiet']);
  try {
    const s = (await api(d.url, 'POST', '/v1/sessions', { preset: 'fig7-bh-0.52', seed: 3 })).body;
    let n = 0;
    while (n < 10000) n = (await api(d.url, 'POST', `/v1/sessions/${s.id}/edits`, { op: 'step', count: 1 })).body.internodes;
    const browser = await chromium.launch({ executablePath: process.env.CHROMIUM || '/usr/bin/chromium', headless: true, args: ARGS });
    const firsts = [], plain = [], coloured = [];
    for (let round = 0; round < ROUNDS; round++) {
      const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
      await page.goto(`${d.url}/?session=${s.id}`);
      await page.waitForFunction(() => window.meristem?.ready && window.meristem.lastLoadMs !== null, null, { timeout: 60000 });
      firsts.push(await page.evaluate(() => window.meristem.lastLoad));
      for (const mode of MODES) {
        await page.selectOption('#color', mode);
        await page.evaluate(() => window.meristem.idle());
        (mode === 'none' ? plain : coloured).push(await page.evaluate(() => window.meristem.lastLoad));
      }
      await page.close();
    }
    await browser.close();
    const row = (name, loads) => {
      const ms = loads.map((l) => l.ms);
      console.log(`${name.padEnd(34)} median ${f(median(ms)).padStart(4)} ms  best ${f(Math.min(...ms)).padStart(4)}  ` +
        `worst ${f(Math.max(...ms)).padStart(4)}  (fetch ${f(median(loads.map((l) => l.fetchMs)))}, ` +
        `parse ${f(median(loads.map((l) => l.parseMs)))}, draw ${f(median(loads.map((l) => l.renderMs)))}; ` +
        `${loads[0].bytes} bytes, ${loads.length} loads)`);
    };
    console.log(`page-load: ${n} internodes; drawn: ${plain[0].triangles} triangles, ${plain[0].lines} line segments ` +
      `(twig lines and the grid); viewport 1280x800, ${ROUNDS} pages`);
    row('load+draw, bark colour', plain);
    row('load+draw, coloured by order/light/age', coloured);
    const drawn = firsts.map((l) => l.drawnAt);
    console.log(`${'opening the page: tree drawn at'.padEnd(34)} median ${f(median(drawn)).padStart(4)} ms after navigation  ` +
      `best ${f(Math.min(...drawn))}  worst ${f(Math.max(...drawn))}  (its load: median ${f(median(firsts.map((l) => l.ms)))} ms, ` +
      `worst ${f(Math.max(...firsts.map((l) => l.ms)))}, after waiting ${f(median(firsts.map((l) => l.paintWaitMs)))} ms for the page's first paint; ` +
      `the snapshot ${firsts.every((l) => l.prefetched) ? 'fetched while the page started' : 'fetched after start'})`);
  } finally {
    await d.stop();
  }
})().catch((e) => { console.error(e); process.exit(1); });
