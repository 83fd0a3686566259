// The brush client: wires the session, growth controls, tools and panels to meristemd.
// State lives in meristemd; the page keeps the session id in its URL (?session=ID) so
// a reload or a shared link returns to the same tree.
import * as THREE from 'three';
import * as api from './api.js';
import { Viewer, softwareRendering } from './viewer/viewer.js';
import { Brush } from './brush.js';
import { PruneTool, BendTool } from './tools.js';
import { ParamsPanel, SchedulePanel } from './panels.js';

const $ = (sel) => document.querySelector(sel);
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
const params = new URLSearchParams(location.search);
const GALLERY = params.get('view') === 'gallery';
const CONSTRAINED = 0xa040c8;   // Fig. 15b shows the constrained branch in purple

const state = {
  id: null, summary: null, presets: [], tool: 'view', playing: false,
  constraint: null, constraintSince: -1, busy: 0, loads: 0, lastLoadMs: null,
  framedHeight: 0, lastProblem: null,
};

// ?aa=1 / ?aa=0 force multisampling on or off; by default it is off on a software rasterizer.
const viewer = new Viewer($('#view'), { antialias: params.has('aa') ? params.get('aa') !== '0' : !softwareRendering() });
// The test suite waits for this: three.js from the web root has drawn a frame.
window.meristemFramesDrawn = viewer.frames;

// ---------------------------------------------------------------- problems and status

let problemTimer = null;
function showProblem(e) {
  console.warn('meristemd refused:', e);
  const p = e instanceof api.Problem ? e : { status: 0, title: 'Error', detail: String(e.message || e) };
  state.lastProblem = { status: p.status, title: p.title, detail: p.detail, field: p.field || null };
  $('#problem-title').textContent = p.status ? `${p.status} ${p.title}` : p.title;
  $('#problem-detail').textContent = p.detail;
  $('#problem-field').textContent = p.field || '';
  $('#problem-field').hidden = !p.field;
  const box = $('#problem');
  box.dataset.status = String(p.status || 0);
  box.hidden = false;
  clearTimeout(problemTimer);
  problemTimer = setTimeout(() => { box.hidden = true; }, 15000);
}
$('#problem-close').addEventListener('click', () => { $('#problem').hidden = true; });

function setStatus(text, kind) {
  const s = $('#status');
  s.textContent = text;
  s.dataset.state = kind;
}

// ---------------------------------------------------------------- summary and stats

function fmt(n) { return typeof n === 'number' ? n.toLocaleString('en-US') : '–'; }

function applySummary(s) {
  if (!s || (state.id && s.id && s.id !== state.id)) return;
  state.summary = { ...state.summary, ...s };
  $('#stat-step').textContent = fmt(s.step);
  $('#stat-internodes').textContent = fmt(s.internodes);
  $('#stat-buds').textContent = fmt(s.buds);
  $('#stat-markers').textContent = fmt(s.markers);
  $('#stat-height').textContent = typeof s.height === 'number' ? s.height.toFixed(2) : '–';
  $('#stat-revision').textContent = fmt(s.revision);
  if (s.params) paramsPanel?.show(s.params);
  if (s.schedule) schedulePanel.show(s.schedule, s.step);
  if (s.constraint !== undefined) setConstraint(s.constraint);   // when meristemd reports it
  if (s.interrupted) setStatus(`step interrupted (${s.interrupted}) after ${s.steps_done} steps`, 'warn');
  // Keep a growing tree in view.
  if (s.height > state.framedHeight * 1.25 + 2 && !brush.stroke && !bend.drag) {
    viewer.frame(s.bounds);
    state.framedHeight = s.height;
  }
}

// ---------------------------------------------------------------- snapshots

function viewOptions() {
  return { detail: Number($('#detail').value), leaves: $('#show-leaves').checked,
    markers: $('#show-markers').checked, color: $('#color').value };
}

let loading = null, reloadAgain = false;
/** Reloads the snapshot (If-None-Match: a 304 costs nothing); coalesces overlapping calls. */
function refresh() {
  if (!state.id) return Promise.resolve();
  if (loading) { reloadAgain = true; return loading; }
  loading = (async () => {
    do {
      reloadAgain = false;
      try {
        const r = await viewer.load(api.snapshotUrl(state.id, { ...viewOptions(), compact: true }));
        if (r.changed) {
          state.loads++;
          state.lastLoadMs = viewer.lastLoad.ms;
          $('#stat-load').textContent = `${viewer.lastLoad.ms.toFixed(0)} ms`;
          $('#stat-load').title = `fetch ${viewer.lastLoad.fetchMs.toFixed(1)} ms, parse ${viewer.lastLoad.parseMs.toFixed(1)} ms, ` +
            `draw ${viewer.lastLoad.renderMs.toFixed(1)} ms; ${viewer.lastLoad.bytes} bytes, ${viewer.lastLoad.triangles} triangles`;
          if (!brush.stroke) brush.clearPreview();
          showConstraint();
          updateDownload();
        }
      } catch (e) {
        showProblem(e);
      }
    } while (reloadAgain);
  })().finally(() => { loading = null; window.meristemFramesDrawn = viewer.frames; });
  return loading;
}

function updateDownload() {
  const a = $('#download');
  if (!state.id) { a.removeAttribute('href'); return; }
  a.href = api.snapshotUrl(state.id, { ...viewOptions(), detail: Math.max(3, Number($('#detail').value)) });
  a.download = `meristem-${state.id.slice(0, 8)}-step${state.summary?.step ?? 0}.glb`;
}

// ---------------------------------------------------------------- edits

let chain = Promise.resolve();
/**
 * Sends edits in order (one request at a time, so a stroke's batches and the growth
 * steps never overtake each other). Resolves to the summary, or null when refused
 * (the problem is shown in the page).
 */
function send(edits, { reload = true } = {}) {
  const p = chain.then(async () => {
    if (!state.id) return null;
    state.busy++;
    try {
      const s = await api.edit(state.id, edits);
      for (const e of edits) {
        if (e.op === 'add_markers' && e.constrain) setConstraint(e.constrain, viewer.maxNodeId());
        if (e.op === 'release') setConstraint(null);
      }
      applySummary(s);
      if (reload) refresh();
      return s;
    } catch (e) {
      showProblem(e);
      return null;
    } finally {
      state.busy--;
    }
  });
  chain = p.catch(() => null);
  return p;
}

// ---------------------------------------------------------------- growth constraint

function constraintKey() { return `meristem.constraint.${state.id}`; }

function setConstraint(c, since) {
  if (c) {
    state.constraint = { node: c.node, bud: c.bud ?? 0 };
    if (since !== undefined) state.constraintSince = since;
    sessionStorage.setItem(constraintKey(), JSON.stringify({ ...state.constraint, since: state.constraintSince }));
  } else {
    state.constraint = null;
    sessionStorage.removeItem(constraintKey());
  }
  showConstraint();
}

function showConstraint() {
  const c = state.constraint;
  $('#constraint').hidden = !c;
  if (!c) { viewer.setHighlight('constraint', null); return; }
  $('#constraint-node').textContent = `${c.node}${c.bud ? ` (bud ${c.bud})` : ''}`;
  // The bud's node and everything grown since the constraint was set: only its
  // descendants can have grown since (node ids are issued in growth order).
  const since = state.constraintSince;
  viewer.setHighlight('constraint', (id) => id === c.node || (since >= 0 && id > since), CONSTRAINED);
}

$('#release').addEventListener('click', () => send([{ op: 'release' }]));

// ---------------------------------------------------------------- growth controls

async function stepN(n) {
  const p = send([{ op: 'step', count: n }]);
  if (n > 1) trackProgress(p);
  return p;
}

async function trackProgress(p) {
  let done = false;
  p.finally(() => { done = true; });
  await sleep(120);
  const box = $('#progress');
  while (!done) {
    try {
      const s = await api.getSession(state.id);
      if (s.running?.active) {
        box.hidden = false;
        const { done: d, total } = s.running;
        $('#progress-fill').style.width = `${total ? (100 * d) / total : 0}%`;
        $('#progress-text').textContent = `step ${d} / ${total}`;
      }
    } catch { /* the edit's own reply reports problems */ }
    await sleep(200);
  }
  box.hidden = true;
}

$('#cancel').addEventListener('click', async () => {
  try { await api.cancel(state.id); } catch (e) { showProblem(e); }
});

$('#step-once').addEventListener('click', () => stepN(1));
$('#step-n').addEventListener('click', () => stepN(Math.max(1, Math.round(Number($('#step-count').value) || 1))));
const syncStepLabel = () => { $('#step-n').textContent = `Step ×${$('#step-count').value}`; };
$('#step-count').addEventListener('input', syncStepLabel);
syncStepLabel();

async function play() {
  if (state.playing) { state.playing = false; return; }
  state.playing = true;
  $('#play').textContent = '❚❚ Pause';
  $('#play').classList.add('playing');
  while (state.playing && state.id) {
    const t = performance.now();
    const s = await send([{ op: 'step', count: 1 }], { reload: false });
    if (!s) break;
    await refresh();
    const wait = 1000 / Number($('#rate').value) - (performance.now() - t);
    if (wait > 0) await sleep(wait);
  }
  state.playing = false;
  $('#play').textContent = '▶ Play';
  $('#play').classList.remove('playing');
}
$('#play').addEventListener('click', play);

// ---------------------------------------------------------------- brush and tools

function symmetry() {
  const sym = {};
  const base = treeBase();
  if ($('#sym-mirror').checked) {
    sym.mirror = { point: base, normal: $('#sym-plane').value === 'x' ? [1, 0, 0] : [0, 0, 1] };
  }
  if ($('#sym-rot').checked) {
    sym.rotational = Math.max(2, Math.min(64, Math.round(Number($('#sym-rot-n').value) || 2)));
    sym.center = base;
  }
  if ($('#sym-tile').checked) {
    const u = Math.max(1, Math.round(Number($('#sym-tile-u').value) || 1));
    const v = Math.max(1, Math.round(Number($('#sym-tile-v').value) || 1));
    const d = Number($('#sym-tile-step').value) || 10;
    sym.tiles = [u, v];
    sym.tile_step = [[d, 0, 0], [0, 0, d]];
  }
  return Object.keys(sym).length ? sym : null;
}

/** The base of the first plant (node 0), else the origin. */
function treeBase() {
  const root = viewer.nodes().get(0);
  return root ? [round3(root.center[0]), 0, round3(root.center[2])] : [0, 0, 0];
}
const round3 = (x) => Math.round(x * 1000) / 1000;

function treeCentre() {
  const b = state.summary?.bounds;
  if (!b) return [0, 5, 0];
  return [0, 1, 2].map((k) => round3((b.min[k] + b.max[k]) / 2));
}

const brush = new Brush(viewer, {
  getSettings: () => ({
    radius: Number($('#radius').value), count: Number($('#count').value),
    pressure: Number($('#pressure').value), constrain: $('#constrain').checked, symmetry: symmetry(),
  }),
  getCentre: treeCentre,
  send: (batch) => send(batch),
  onStrokeStart: ({ constrain }) => {
    if (constrain) viewer.setHighlight('picked', new Set([constrain.node]), CONSTRAINED);
  },
  onStrokeEnd: () => { viewer.setHighlight('picked', null); refresh(); },
});
const prune = new PruneTool(viewer, { send });
const bend = new BendTool(viewer, { send });

const HINTS = {
  view: 'Drag to orbit · right-drag to pan · wheel to zoom',
  brush: 'Drag to lay markers in a plane facing you · start on a branch to grow only from it · right-drag orbits',
  prune: 'Click a branch to cut it and everything above · right-drag orbits',
  bend: 'Drag a branch to bend it about its base · right-drag orbits',
};

function setTool(tool) {
  state.tool = tool;
  for (const b of document.querySelectorAll('#tools [data-tool]')) b.classList.toggle('active', b.dataset.tool === tool);
  viewer.controls.mouseButtons = tool === 'view'
    ? { LEFT: THREE.MOUSE.ROTATE, MIDDLE: THREE.MOUSE.DOLLY, RIGHT: THREE.MOUSE.PAN }
    : { LEFT: null, MIDDLE: THREE.MOUSE.DOLLY, RIGHT: THREE.MOUSE.ROTATE };
  $('#view').dataset.tool = tool;
  $('#hint').textContent = HINTS[tool];
  prune.leave();
  bend.leave();
}
for (const b of document.querySelectorAll('#tools [data-tool]')) b.addEventListener('click', () => setTool(b.dataset.tool));
$('#frame').addEventListener('click', () => {
  if (state.summary) { viewer.framed = false; viewer.frame(state.summary.bounds); state.framedHeight = state.summary.height; }
});

const canvas = viewer.renderer.domElement;
let down = null;
canvas.addEventListener('pointerdown', (e) => {
  if (e.button !== 0 || !state.id || state.tool === 'view') return;
  down = { x: e.clientX, y: e.clientY, id: e.pointerId, moved: false };
  if (state.tool === 'brush') brush.begin(e);
  else if (state.tool === 'bend' && !bend.begin(e, Math.max(2, (state.summary?.height || 10) * 0.3))) down = null;
  if (down) { canvas.setPointerCapture(e.pointerId); e.preventDefault(); }
});
canvas.addEventListener('pointermove', (e) => {
  if (down && e.pointerId === down.id) {
    if (Math.hypot(e.clientX - down.x, e.clientY - down.y) > 4) down.moved = true;
    if (state.tool === 'brush') brush.move(e);
    else if (state.tool === 'bend') bend.move(e);
    return;
  }
  if (e.buttons) return;
  if (state.tool === 'prune') prune.hover(e);
  else if (state.tool === 'bend') bend.hover(e);
});
const finish = (e) => {
  if (!down || e.pointerId !== down.id) return;
  const d = down;
  down = null;
  if (state.tool === 'brush') brush.end(e);
  else if (state.tool === 'bend') bend.end(e);
  else if (state.tool === 'prune' && !d.moved && e.type === 'pointerup') prune.click(e);
};
canvas.addEventListener('pointerup', finish);
canvas.addEventListener('pointercancel', finish);
canvas.addEventListener('pointerleave', () => { if (!down) { prune.leave(); bend.leave(); } });

document.addEventListener('keydown', (e) => {
  if (e.target.closest('input, select, textarea') || e.ctrlKey || e.metaKey || e.altKey) return;
  const k = e.key.toLowerCase();
  if (k === 'v') setTool('view');
  else if (k === 'b') setTool('brush');
  else if (k === 'p') setTool('prune');
  else if (k === 'n') setTool('bend');
  else if (k === 'f') $('#frame').click();
  else if (k === 's') stepN(1);
  else if (k === ' ') { e.preventDefault(); play(); } else return;
});

// ---------------------------------------------------------------- sliders and views

for (const input of document.querySelectorAll('input[type=range]')) {
  const out = input.parentElement.querySelector('output');
  const show = () => { if (out) out.textContent = input.value; };
  input.addEventListener('input', show);
  show();
}
$('#show-bark').addEventListener('change', (e) => viewer.setVisible({ bark: e.target.checked }));
$('#show-leaves').addEventListener('change', (e) => { viewer.setVisible({ leaves: e.target.checked }); refresh(); });
$('#show-markers').addEventListener('change', () => refresh());
$('#show-grid').addEventListener('change', (e) => viewer.setGridVisible(e.target.checked));
$('#color').addEventListener('change', () => refresh());
$('#detail').addEventListener('change', () => refresh());

// ---------------------------------------------------------------- schedule and parameters

const schedulePanel = new SchedulePanel();
let paramsPanel = null;
$('#apply-schedule').addEventListener('click', () => send([schedulePanel.edit()]));
$('#apply-params').addEventListener('click', () => {
  const changed = paramsPanel?.changed() || {};
  if (!Object.keys(changed).length) return;
  send([{ op: 'set_params', params: changed }]);
});

// ---------------------------------------------------------------- sessions

function describePreset() {
  const p = state.presets.find((x) => x.name === $('#preset').value);
  $('#preset-description').textContent = p ? p.description : '';
}
$('#preset').addEventListener('change', describePreset);

async function openSession(summary) {
  state.id = summary.id;
  state.summary = null;
  state.constraint = null;
  state.constraintSince = -1;
  state.framedHeight = 0;
  viewer.framed = false;
  viewer.etag = null;
  const saved = sessionStorage.getItem(constraintKey());
  if (saved) {
    const c = JSON.parse(saved);
    state.constraint = { node: c.node, bud: c.bud };
    state.constraintSince = c.since;
  }
  const url = new URL(location.href);
  url.searchParams.set('session', summary.id);
  url.hash = '';
  history.replaceState(null, '', url);
  $('#session-id').textContent = summary.id.slice(0, 8);
  $('#session-id').title = `session ${summary.id} (${summary.preset}, seed ${summary.seed}) — the URL reopens it`;
  if ([...$('#preset').options].some((o) => o.value === summary.preset)) $('#preset').value = summary.preset;
  $('#seed').value = String(summary.seed);
  describePreset();
  document.body.classList.add('has-session');
  applySummary(summary);
  viewer.frame(summary.bounds);
  state.framedHeight = summary.height;
  await refresh();
  showConstraint();
}

$('#session-form').addEventListener('submit', async (e) => {
  e.preventDefault();
  state.playing = false;
  try {
    const seed = Math.max(0, Math.round(Number($('#seed').value) || 0));
    await openSession(await api.createSession($('#preset').value, seed));
  } catch (err) {
    showProblem(err);
  }
});

function sessionFromUrl() {
  const q = params.get('session');
  if (q) return q;
  const h = location.hash.replace(/^#/, '');
  return /^[0-9a-f]{32}$/.test(h) ? h : null;
}

async function start() {
  if (GALLERY) {
    document.body.classList.add('gallery');
    $('#show-markers').checked = params.get('markers') === '1';
    $('#show-leaves').checked = params.get('leaves') !== '0';
    $('#detail').value = params.get('detail') || '3';
    if (params.get('color')) $('#color').value = params.get('color');
  }
  // Everything the page needs is asked for at once, the snapshot of a reopened session
  // too: the requests travel while the viewer compiles its shaders (about a second with
  // software WebGL, and it holds the main thread), not one after another behind it.
  const id = sessionFromUrl();
  const healthReply = api.health(), presetsReply = api.presets();
  const sessionReply = id ? api.getSession(id) : null;
  for (const r of [healthReply, presetsReply, sessionReply]) r?.catch(() => {});   // awaited below
  if (id) viewer.prefetch(api.snapshotUrl(id, { ...viewOptions(), compact: true }));
  try {
    const h = await healthReply;
    setStatus(`meristemd ${h.version}: ${h.status}`, h.status);
  } catch (e) {
    setStatus(`meristemd is not answering: ${e.message}`, 'error');
  }
  try {
    const p = await presetsReply;
    state.presets = p.presets;
    for (const x of p.presets) $('#preset').add(new Option(x.name, x.name));
    $('#preset').value = p.presets.some((x) => x.name === 'fig15-brushed') ? 'fig15-brushed' : p.presets[0]?.name;
    describePreset();
    paramsPanel = new ParamsPanel(p.parameters);
  } catch (e) {
    showProblem(e);
  }
  if (id) {
    try {
      await openSession(await sessionReply);
    } catch (e) {
      showProblem(e);
      const url = new URL(location.href);
      url.searchParams.delete('session');
      history.replaceState(null, '', url);
    }
  }
  setTool('view');
  viewer.render();
  window.meristemFramesDrawn = viewer.frames;
  window.meristem.ready = true;
}

// ---------------------------------------------------------------- test and script hooks

window.meristem = {
  api, viewer, brush, prune, bend, state, send, refresh, setTool, stepN,
  ready: false,
  get sessionId() { return state.id; },
  get summary() { return state.summary; },
  get lastLoadMs() { return state.lastLoadMs; },
  get lastLoad() { return viewer.lastLoad; },
  get constraint() { return state.constraint; },
  /** Resolves when no edit is queued and the snapshot shows the latest revision. */
  async idle() {
    for (;;) {
      await chain;
      await refresh();
      if (!state.busy && !loading && !brush.stroke) return state.summary;
      await sleep(20);
    }
  },
  /** Client coordinates of a node's centre in the current snapshot, or null. */
  screenOfNode(id) {
    const n = viewer.nodes().get(id);
    return n ? viewer.screenOf(n.center) : null;
  },
  nodeInfo(id) { return viewer.nodes().get(id) || null; },
  nodeIds() { return viewer.nodeIds(); },
  markerPositions() { return viewer.markerPositions(); },
  pixelVariance() { return viewer.pixelVariance(); },
};

start();
