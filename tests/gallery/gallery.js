'use strict';
// `make gallery`: grows every preset for a few tens of steps in a real meristemd and
// renders it to OUT/PRESET.png with headless Chromium through the brush client itself
// (the page at /?session=ID&view=gallery). usage: node gallery.js OUT [STEPS] [PRESET,...]
// (the presets named, or all of them)
const fs = require('node:fs');
const path = require('node:path');
const { chromium } = require('playwright-core');
const { startDaemon, api } = require('../support/daemon.js');

const MAX_INTERNODES = 12000;   // keeps a picture quick to grow and to draw

/** Fig. 15: the crown is laid with broad heavy strokes before the tree grows into it. */
const BRUSHED = {
  'fig15-brushed': [
    ...[10, 12, 14, 16].map((y) => ({ op: 'add_markers', center: [-3, y, 0], radius: 4, pressure: 0.9, count: 120 })),
    ...[10, 12, 14, 16].map((y) => ({ op: 'add_markers', center: [3, y, 1], radius: 4, pressure: 0.9, count: 120 })),
  ],
};

(async () => {
  const out = path.resolve(process.argv[2] || 'gallery');
  const steps = Number(process.argv[3] || 30);
  fs.mkdirSync(out, { recursive: true });
  const d = await startDaemon(['--quiet', '--max-request-seconds', '600']);
  const browser = await chromium.launch({ executablePath: process.env.CHROMIUM || '/usr/bin/chromium', headless: true,
    args: ['--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'] });
  const rows = [];
  try {
    const only = process.argv[4] ? new Set(process.argv[4].split(',')) : null;
    const presets = (await api(d.url, 'GET', '/v1/presets')).body.presets.filter((p) => !only || only.has(p.name));
    const page = await browser.newPage({ viewport: { width: 720, height: 720 } });
    page.on('pageerror', (e) => console.error(String(e)));
    for (const p of presets) {
      const s = (await api(d.url, 'POST', '/v1/sessions', { preset: p.name, seed: 1 })).body;
      let summary = s;
      for (let done = 0; done < steps && summary.internodes < MAX_INTERNODES;) {
        if (done === 8 && BRUSHED[p.name]) {
          await api(d.url, 'POST', `/v1/sessions/${s.id}/edits`, { edits: BRUSHED[p.name] });
        }
        const n = Math.min(done < 8 ? 8 - done : 2, steps - done);
        summary = (await api(d.url, 'POST', `/v1/sessions/${s.id}/edits`, { op: 'step', count: n })).body;
        done += n;
      }
      await page.goto(`${d.url}/?session=${s.id}&view=gallery&leaves=1&detail=3`);
      await page.waitForFunction(() => window.meristem?.ready && window.meristem.lastLoadMs !== null, null, { timeout: 120000 });
      const file = path.join(out, `${p.name}.png`);
      await page.screenshot({ path: file });
      rows.push({ preset: p.name, description: p.description, step: summary.step, internodes: summary.internodes,
        height: summary.height, file: path.basename(file) });
      console.log(`${p.name}: step ${summary.step}, ${summary.internodes} internodes → ${file}`);
    }
  } finally {
    await browser.close();
    await d.stop();
  }
  fs.writeFileSync(path.join(out, 'gallery.json'), `${JSON.stringify(rows, null, 2)}\n`);
})().catch((e) => { console.error(e); process.exit(1); });
