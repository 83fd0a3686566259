'use strict';
// `make gallery-junctions`: the README's figures of implicit junctions (G04 §3), drawn
// by the brush client in headless Chromium against a real meristemd, as gallery.js
// draws the presets:
//   junctions-tree.png   a whole tree with implicit junctions;
//   junctions-fork.png   the page's fork close-up of that tree (?fork=thickest);
//   junctions-years.png  one fork when its lateral is 1, 4, 7 and 10 years old (the
//                        years of G04 Fig. 7), a 2×2 montage;
//   junctions-relay.png  a sympodium's fork with no living continuation, as tubes and
//                        relayed through a patch, side by side;
//   junctions-run.png    two forks a few radii apart up the trunk, as tubes and as one
//                        patch (a run), side by side.
// usage: node junctions.js OUT
// The engine is deterministic, so "the same fork, older" is the same preset and seed
// stepped further: one session per year, each drawn at ?fork=LATERAL.
const fs = require('node:fs');
const path = require('node:path');
const { chromium } = require('playwright-core');
const { startDaemon, api } = require('../support/daemon.js');

const TREE = { preset: 'fig7-bh-0.54', seed: 1, steps: 12 };
/** The fork of the years (the one test_junctions' fork_ages follows): a lateral whose
 * fork is a patch from its first season to its tenth and also ends its parent's shoot,
 * so it has a bud scale scar; it is `age` seasons old (steps since the step that grew
 * it) after `born` + age steps. */
const FORK = { preset: 'fig7-bh-0.54', seed: 7, lateral: 58, born: 4 };
const YEARS = [1, 4, 7, 10];
/** A fork whose parent (node 92, a flowered tip) has no living continuation: its one
 * lateral, 126, relays the axis. */
const RELAY = { preset: 'fig6-sympodial', seed: 1, steps: 14, lateral: 126 };
/** Forks 3 and 4 of TREE's trunk, an internode apart (one run of two): the close-up
 * looks at fork 4's lateral, 11, with fork 3's, 8, below. */
const RUN = { lateral: 11 };

/** Grows a new session of `preset` to `steps` steps; resolves to its summary. */
async function grow(url, preset, seed, steps) {
  const s = (await api(url, 'POST', '/v1/sessions', { preset, seed })).body;
  let summary = s;
  for (let done = 0; done < steps; done += 10) {
    summary = (await api(url, 'POST', `/v1/sessions/${s.id}/edits`, { op: 'step', count: Math.min(10, steps - done) })).body;
  }
  return summary;
}

/** Opens the gallery view of session `id` with `query` (junctions `junctions`, implicit
 * unless said) and waits until it is drawn. */
async function show(page, base, id, query, junctions = 'implicit') {
  await page.goto(`${base}/?session=${id}&view=gallery&leaves=0&detail=4&junctions=${junctions}&${query}`);
  await page.waitForFunction(() => window.meristem?.ready && window.meristem.lastLoadMs !== null, null, { timeout: 600000 });
}

/** What the page's close-up looked at: the fork's lateral, its age, and how many bark
 * points near the fork carry a ridge value (0: the mesher made no patch there). */
function closeUpState(page) {
  return page.evaluate(() => {
    const m = window.meristem, f = m.panels.view.fork;
    if (!f) return null;
    const pts = m.viewer.ridgePoints(), r = 2 * f.diameter;
    let near = 0;
    for (let i = 0; i < pts.length; i += 3) {
      if (Math.hypot(pts[i] - f.at[0], pts[i + 1] - f.at[1], pts[i + 2] - f.at[2]) < r) near++;
    }
    return { lateral: f.lateral.id, age: f.lateral.age, ridgePoints: near, triangles: m.lastLoad.triangles };
  });
}

/** Images two to a row with their captions, `size` px each. */
async function montage(page, images, size, file) {
  const cells = images.map(({ png, label }) => `<figure><img src="data:image/png;base64,${png.toString('base64')}">` +
    `<figcaption>${label}</figcaption></figure>`).join('');
  await page.setViewportSize({ width: 2 * size, height: Math.ceil(images.length / 2) * size });
  await page.setContent(`<style>body{margin:0;display:grid;grid-template-columns:${size}px ${size}px;background:#fff}
    figure{margin:0;position:relative;width:${size}px;height:${size}px}img{width:${size}px;height:${size}px;display:block}
    figcaption{position:absolute;left:8px;top:6px;font:bold 18px sans-serif;color:#333;background:rgba(255,255,255,.7);padding:1px 6px}
    </style>${cells}`);
  await page.screenshot({ path: file });
}

/** The close-up of lateral `lateral`'s fork in session `id` as tubes and with implicit
 * junctions (`what`: how the patch serves it), side by side in `file`; throws unless the
 * implicit one is a patch there. */
async function tubesBesidePatch(page, base, id, lateral, what, size, file) {
  await page.setViewportSize({ width: size, height: size });
  const pair = [];
  for (const j of ['tubes', 'implicit']) {
    await show(page, base, id, `color=none&fork=${lateral}`, j);
    const st = await closeUpState(page);
    console.log(`${what}, ${j}: ${JSON.stringify(st)}`);
    if (!st || st.lateral !== lateral || (j === 'implicit') !== (st.ridgePoints > 0)) {
      throw new Error(`the fork of lateral ${lateral} is not ${j === 'tubes' ? 'tubes' : 'a patch'}: ${JSON.stringify(st)}`);
    }
    pair.push({ png: await page.screenshot(), label: j === 'tubes' ? 'tubes' : `implicit, ${what}` });
  }
  await montage(page, pair, size, file);
}

(async () => {
  const out = path.resolve(process.argv[2] || 'gallery');
  fs.mkdirSync(out, { recursive: true });
  const d = await startDaemon(['--quiet', '--max-request-seconds', '600']);
  const browser = await chromium.launch({ executablePath: process.env.CHROMIUM || '/usr/bin/chromium', headless: true,
    args: ['--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'] });
  try {
    const page = await browser.newPage({ viewport: { width: 720, height: 720 } });
    page.on('pageerror', (e) => console.error(String(e)));

    const tree = await grow(d.url, TREE.preset, TREE.seed, TREE.steps);
    await show(page, d.url, tree.id, 'color=none');
    await page.screenshot({ path: path.join(out, 'junctions-tree.png') });
    await show(page, d.url, tree.id, 'color=none&fork=thickest');
    const thickest = await closeUpState(page);
    await page.screenshot({ path: path.join(out, 'junctions-fork.png') });
    console.log(`${TREE.preset} seed ${TREE.seed}, ${tree.internodes} internodes; thickest fork ${JSON.stringify(thickest)}`);

    const size = 480;
    await page.setViewportSize({ width: size, height: size });
    const images = [];
    for (const year of YEARS) {
      const s = await grow(d.url, FORK.preset, FORK.seed, FORK.born + year);
      await show(page, d.url, s.id, `color=none&fork=${FORK.lateral}`);
      const st = await closeUpState(page);
      console.log(`year ${year}: step ${s.step}, ${JSON.stringify(st)}`);
      if (!st || st.lateral !== FORK.lateral || st.age !== year || st.ridgePoints === 0) {
        throw new Error(`year ${year}: the fork of lateral ${FORK.lateral} is not a junction patch of that age: ${JSON.stringify(st)}`);
      }
      images.push({ png: await page.screenshot(), label: year === 1 ? '1 year' : `${year} years` });
    }
    await montage(page, images, size, path.join(out, 'junctions-years.png'));

    const relay = await grow(d.url, RELAY.preset, RELAY.seed, RELAY.steps);
    await tubesBesidePatch(page, d.url, relay.id, RELAY.lateral, 'relayed', size, path.join(out, 'junctions-relay.png'));
    await tubesBesidePatch(page, d.url, tree.id, RUN.lateral, 'one run', size, path.join(out, 'junctions-run.png'));
  } finally {
    await browser.close();
    await d.stop();
  }
})().catch((e) => { console.error(e); process.exit(1); });
