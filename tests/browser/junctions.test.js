'use strict';
// The View panel's "implicit junctions" toggle and its fork close-up, in headless
// Chromium against a real meristemd (issue 18, item 5): ticking the box asks for
// snapshot.glb?junctions=implicit and draws the forks of thick branches as patches
// (more triangles there, and a ridge value the page darkens the bark by); the close-up
// brings the camera to such a fork (the key C: the fork under the pointer); unticking
// it gives the tubes back.
const { test, before, after } = require('node:test');
const assert = require('node:assert/strict');
const path = require('node:path');
const { openPage } = require('../support/chromium.js');
const { startDaemon } = require('../support/daemon.js');

let d, browser, page;
const errors = [];
const snapshots = [];   // the snapshot URLs the page asked for
const idle = () => page.evaluate(() => window.meristem.idle());

before(async () => {
  d = await startDaemon(['--quiet']);
  ({ browser, page } = await openPage());
  page.on('pageerror', (e) => errors.push(String(e)));
  page.on('request', (r) => { if (r.url().includes('/snapshot.glb')) snapshots.push(new URL(r.url())); });
  await page.goto(`${d.url}/`, { timeout: 120000 });
  await page.waitForFunction(() => window.meristem?.ready, null, { timeout: 30000 });
});
after(async () => { await browser?.close(); await d?.stop(); });

/** The bark triangles drawn (all primitives), those with a corner within `r` of `at`,
 * and how many bark vertices carry a ridge value. */
function bark(at = null, r = 0) {
  return page.evaluate(({ at, r }) => {
    const m = window.meristem, v = m.viewer;
    let all = 0, near = 0;
    for (const mesh of v.barkMeshes) {
      const g = mesh.geometry, pos = g.attributes.position, idx = g.index;
      all += idx.count / 3;
      if (!at) continue;
      const close = new Uint8Array(pos.count);
      const p = mesh.position.clone();   // a THREE.Vector3 (three.js is not a global here)
      for (let i = 0; i < pos.count; i++) {
        p.set(pos.getX(i), pos.getY(i), pos.getZ(i)).applyMatrix4(mesh.matrixWorld);
        close[i] = Math.hypot(p.x - at[0], p.y - at[1], p.z - at[2]) < r ? 1 : 0;
      }
      for (let t = 0; t < idx.count; t += 3) {
        if (close[idx.getX(t)] || close[idx.getX(t + 1)] || close[idx.getX(t + 2)]) near++;
      }
    }
    return { all, near, ridge: v.ridgePoints().length / 3 };
  }, { at, r });
}

test('the junctions toggle asks for implicit junctions, the close-up looks at a fork, and off gives tubes back', async () => {
  await page.selectOption('#preset', 'fig7-bh-0.54');
  await page.fill('#seed', '1');
  await page.click('#new-session');
  await page.waitForFunction(() => window.meristem.summary?.preset === 'fig7-bh-0.54', null, { timeout: 15000 });
  await page.evaluate(() => window.meristem.send([{ op: 'step', count: 12 }]));
  await idle();
  assert.ok(!(await page.isChecked('#junctions')), 'off by default');
  assert.ok(snapshots.length > 0 && snapshots.every((u) => !u.searchParams.has('junctions')), 'tubes asked for');
  const tubes = await bark();
  assert.equal(tubes.ridge, 0, 'no ridge on tubes');

  const asked = snapshots.length;
  await page.check('#junctions');
  await page.waitForFunction(() => window.meristem.viewer.url?.includes('junctions=implicit'), null, { timeout: 120000 });
  await idle();
  const implicit = snapshots.slice(asked).filter((u) => u.searchParams.get('junctions') === 'implicit');
  assert.ok(implicit.length > 0, `a snapshot.glb?junctions=implicit request: ${snapshots.slice(asked).map(String)}`);
  const joined = await bark();
  assert.ok(joined.ridge > 0, 'bark vertices with a ridge value');
  assert.ok(joined.all > tubes.all, `${joined.all} triangles with junctions, ${tubes.all} without`);
  // The ridge is drawn darker than the bark (per-vertex colours from _RIDGE).
  assert.ok(await page.evaluate(() => window.meristem.viewer.barkMeshes.some((m) => m.geometry.attributes.color)),
    'ridge colours on the bark');

  const camera = () => page.evaluate(() => {
    const v = window.meristem.viewer;
    return { pos: v.camera.position.toArray(), target: v.controls.target.toArray() };
  });
  const before = await camera();
  await page.click('#fork-close-up');
  await page.waitForFunction(() => window.meristem.panels.view.fork, null, { timeout: 15000 });
  const fork = await page.evaluate(() => {
    const f = window.meristem.panels.view.fork;
    return { at: f.at, diameter: f.diameter, lateral: f.lateral.id, patched: window.meristem.viewer.junctionForks?.has(f.parent.id) };
  });
  assert.ok(fork.patched, 'the GLB lists the fork among those patched (the tree node\'s extras.junction_forks)');
  const cam = await camera();
  const dist = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
  assert.ok(dist(cam.target, fork.at) < fork.diameter, `the view centres on the fork (${dist(cam.target, fork.at)})`);
  assert.ok(dist(cam.pos, fork.at) < 12 * fork.diameter, `the camera is close (${dist(cam.pos, fork.at)} for a fork ${fork.diameter} thick)`);
  assert.ok(dist(cam.pos, before.pos) > 1, 'the camera moved');
  // The fork is a patch: its ridge points are near it, and more triangles than tubes.
  const near = await bark(fork.at, 1.5 * fork.diameter);
  await page.screenshot({ path: path.join(process.env.MER_ARTIFACTS, 'browser-junctions-fork.png') });

  // The key C: the fork nearest the tree under the pointer. The pointer goes to the
  // base of another thick lateral, where the tree in front is that fork.
  await page.click('#frame');
  // Right after a programmatic move the view's matrices are those of the new view, not
  // of the last frame drawn: the orbit target projects to the canvas's centre.
  const centre = await page.evaluate(() => {
    const v = window.meristem.viewer, r = v.renderer.domElement.getBoundingClientRect();
    const s = v.screenOf(v.controls.target);
    return { dx: s.x - (r.left + r.width / 2), dy: s.y - (r.top + r.height / 2) };
  });
  assert.ok(Math.hypot(centre.dx, centre.dy) < 1, `the target at the centre just after framing (${centre.dx}, ${centre.dy})`);
  const other = await page.evaluate(({ first, from }) => window.meristem.session.skeleton().then((sk) => {
    const v = window.meristem.viewer;
    for (const n of sk.byId.values()) {
      const p = sk.byId.get(n.parent);
      if (!p || n.order <= p.order || n.id === first || String(n.base) === String(from) || n.diameter < 0.3 * p.diameter) continue;
      const at = v.screenOf(n.base), hit = v.pick(at.x, at.y, 0);
      if (hit && hit.point.distanceTo(v.camera.position.clone().set(...n.base)) < p.diameter) return { base: n.base, at };
    }
    return null;
  }), { first: fork.lateral, from: fork.at });
  assert.ok(other, 'another fork in view');
  await page.mouse.move(other.at.x, other.at.y);
  await page.keyboard.press('c');
  await page.waitForFunction((b) => String(window.meristem.panels.view.fork.at) === String(b), other.base, { timeout: 15000 });

  await page.uncheck('#junctions');
  await page.waitForFunction(() => !window.meristem.viewer.url?.includes('junctions='), null, { timeout: 60000 });
  await idle();
  const back = await bark(fork.at, 1.5 * fork.diameter);
  assert.equal(back.ridge, 0, 'tubes again');
  assert.equal(back.all, tubes.all, 'the tubes of before');
  assert.ok(near.near > back.near, `${near.near} triangles at the fork with junctions, ${back.near} without`);
  assert.ok(!snapshots.at(-1).searchParams.has('junctions'), 'the last snapshot asked for tubes');
  assert.deepEqual(errors, []);
});

// A sylleptic shrub forks at its base, where the trunk's first fork gets no patch of
// its own but the fork at the tip of its lateral's short first internode does: that
// patch's ridge lies near the base fork. The close-up takes the forks the GLB lists as
// patched (extras.junction_forks), so it looks at a patch, not at tubes beside one
// (by the ridge alone, the gallery's ?fork=thickest chose the base fork: lateral 2 of
// node 0, which is tubes).
test('the close-up looks at a fork the mesher patched, not at tubes beside a patch', async () => {
  const post = (p, body) => fetch(`${d.url}${p}`, { method: 'POST', headers: { 'Content-Type': 'application/json' },
    body: JSON.stringify(body) }).then((r) => r.json());
  const s = await post('/v1/sessions', { preset: 'fig6-sylleptic', seed: 1 });
  await post(`/v1/sessions/${s.id}/edits`, { op: 'step', count: 10 });
  await page.goto(`${d.url}/?session=${s.id}&view=gallery&leaves=0&detail=4&junctions=implicit&color=none&fork=thickest`);
  await page.waitForFunction(() => window.meristem?.ready && window.meristem.lastLoadMs !== null &&
    window.meristem.panels.view.fork, null, { timeout: 120000 });
  const chosen = await page.evaluate(() => {
    const f = window.meristem.panels.view.fork, listed = window.meristem.viewer.junctionForks;
    return { parent: f.parent.id, lateral: f.lateral.id, listed: listed ? listed.size : 0, patched: Boolean(listed?.has(f.parent.id)) };
  });
  assert.ok(chosen.listed > 50, `the GLB lists the patched forks (${chosen.listed})`);
  assert.ok(chosen.patched, `the close-up's fork (lateral ${chosen.lateral} of ${chosen.parent}) is patched`);
  assert.deepEqual(errors, []);
});
