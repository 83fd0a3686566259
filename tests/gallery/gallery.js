'use strict';
// `make gallery`: grows every preset to the size of its figure in a real meristemd and
// renders it to OUT/PRESET.png with headless Chromium through the brush client itself
// (the page at /?session=ID&view=gallery). usage: node gallery.js OUT [STEPS]
// (STEPS, when given, replaces every preset's own step count).
const fs = require('node:fs');
const path = require('node:path');
const { chromium } = require('playwright-core');
const { startDaemon, api } = require('../support/daemon.js');

/** Steps to the size each figure shows: Table 1's step counts for Fig. 10, the step
 * counts the form tests measure (tests/unit/test_forms*.c) for the others. */
const STEPS = {
  default: 16,
  'fig7-bh-0.46': 16, 'fig7-bh-0.48': 16, 'fig7-bh-0.50': 16, 'fig7-bh-0.52': 16, 'fig7-bh-0.54': 16,
  'fig9-priority-k0.5': 30, 'fig9-priority-k0.35': 30,
  'fig10-left': 106, 'fig10-center': 90, 'fig10-right': 68, 'table1-center': 90,
  'fig11-animation': 50,
  'fig6-sylleptic': 12, 'fig6-sympodial': 12,
  fig12a: 20, fig12b: 20, fig12c: 20, fig12d: 20,
  'fig13-tropism-late': 26,
  'fig14-tall-bole': 18,
  'fig15-brushed': 30,
  'fig4-colonization': 30,
  'perlin-noise': 16,
  'gv-fig2-small-2': 2, 'gv-fig2-small-5': 5, 'gv-fig2-large-2': 2, 'gv-fig2-large-5': 5,
  'gv-fig3-sphere': 4, 'gv-fig3-cone': 4, 'gv-fig4-1000': 6, 'gv-fig4-2000': 6, 'gv-fig4-4000': 6,
  'gv-shrub': 4,
};
/** Presets that grow the same tree as another (Table 1 is Fig. 10 at full size; the
 * centre tree of Table 1 keeps κ 0.5 and is drawn on its own). */
const SAME_AS = { 'table1-left': 'fig10-left', 'table1-right': 'fig10-right' };

/** Fig. 15: the crown is laid with broad heavy strokes before the tree grows into it. */
const BRUSHED = {
  'fig15-brushed': [
    ...[10, 12, 14, 16].map((y) => ({ op: 'add_markers', center: [-3, y, 0], radius: 4, pressure: 0.9, count: 120 })),
    ...[10, 12, 14, 16].map((y) => ({ op: 'add_markers', center: [3, y, 1], radius: 4, pressure: 0.9, count: 120 })),
  ],
};

(async () => {
  const out = path.resolve(process.argv[2] || 'gallery');
  const only = process.env.GALLERY_ONLY ? process.env.GALLERY_ONLY.split(',') : null;
  fs.mkdirSync(out, { recursive: true });
  const d = await startDaemon(['--quiet', '--max-request-seconds', '600']);
  const browser = await chromium.launch({ executablePath: process.env.CHROMIUM || '/usr/bin/chromium', headless: true,
    args: ['--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'] });
  const rows = [];
  try {
    const presets = (await api(d.url, 'GET', '/v1/presets')).body.presets;
    const page = await browser.newPage({ viewport: { width: 720, height: 720 } });
    page.on('pageerror', (e) => console.error(String(e)));
    for (const p of presets) {
      if (SAME_AS[p.name] || (only && !only.includes(p.name))) continue;
      const steps = Number(process.argv[3] || STEPS[p.name] || 30);
      const s = (await api(d.url, 'POST', '/v1/sessions', { preset: p.name, seed: 1 })).body;
      let summary = s;
      for (let done = 0; done < steps;) {
        if (done === 8 && BRUSHED[p.name]) {
          await api(d.url, 'POST', `/v1/sessions/${s.id}/edits`, { edits: BRUSHED[p.name] });
        }
        const n = Math.min(done < 8 ? 8 - done : 10, steps - done);
        summary = (await api(d.url, 'POST', `/v1/sessions/${s.id}/edits`, { op: 'step', count: n })).body;
        done += n;
      }
      await page.goto(`${d.url}/?session=${s.id}&view=gallery&leaves=1&detail=3`);
      await page.waitForFunction(() => window.meristem?.ready && window.meristem.lastLoadMs !== null, null, { timeout: 1800000 });
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
