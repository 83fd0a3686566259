// The brush client: boots the viewer, the session, the tools (tools/index.js) and the
// panels (panels/index.js), wires them to each other and to meristemd, and gives
// tests and scripts their hooks (window.meristem).
import * as api from './api.js';
import { $ } from './util.js';
import { Viewer, softwareRendering } from './viewer/viewer.js';
import { Session } from './session.js';
import { TopBar, sessionFromUrl, forgetSessionInUrl } from './topbar.js';
import { Input } from './input.js';
import { TOOLS } from './tools/index.js';
import { PANELS } from './panels/index.js';
import { viewOptions, viewFromQuery } from './panels/view.js';
import { mountProblemBox, setStatus } from './status.js';
import { showModel } from './models.js';

const params = new URLSearchParams(location.search);

// ?aa=1 / ?aa=0 force multisampling on or off; by default it is off on a software rasterizer.
const viewer = new Viewer($('#view'), { antialias: params.has('aa') ? params.get('aa') !== '0' : !softwareRendering() });
const session = new Session(viewer, { gesture: () => input.busy() });
const ctx = { viewer, session };
const tools = TOOLS.map((T) => new T(ctx));
const panels = PANELS.map((P) => new P(ctx));
const input = new Input({ viewer, session, tools, keys: Object.assign({}, ...panels.map((p) => p.keys)),
  frame: () => session.frame() });
for (const p of panels) if (p.show) session.onSummary((s) => p.show(s));
for (const p of panels) if (p.edited) session.onEdited((edits) => p.edited(edits));
for (const part of [...panels, ...tools]) if (part.loaded) session.onLoaded((l) => part.loaded(l));

// A preset names its model: the top bar's model choice only filters the presets.
const topbar = new TopBar({ onNew: (spec) => session.create(spec) });
session.opener = openSession;
mountProblemBox();

// Every slider shows its value beside it.
for (const slider of document.querySelectorAll('input[type=range]')) {
  const out = slider.parentElement.querySelector('output');
  const show = () => { if (out) out.textContent = slider.value; };
  slider.addEventListener('input', show);
  show();
}

async function openSession(summary) {
  topbar.show(summary);
  useModel(summary.model || 'p09');
  await session.open(summary);
}

/** The panels and tools of growth model `model` (models.js). */
function useModel(model) {
  showModel(model, { tools, activeTool: session.state.tool, setTool: (id) => input.setTool(id) });
}

async function start() {
  if (params.get('view') === 'gallery') {
    document.body.classList.add('gallery');
    viewFromQuery(params);
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
    session.state.presets = p.presets;
    topbar.setPresets(p.presets);
    for (const panel of panels) panel.presets?.(p);
  } catch (e) {
    session.problem(e);
  }
  useModel('p09');   // until a session says otherwise
  if (id) {
    try {
      await openSession(await sessionReply);
      // ?fork=ID (a lateral's node id) or ?fork=thickest: a gallery's fork close-up.
      const fork = params.get('fork');
      if (fork) await panelsById.view.closeUp({ lateral: fork === 'thickest' ? null : Number(fork) });
    } catch (e) {
      session.problem(e);
      forgetSessionInUrl();
    }
  }
  input.setTool(tools[0].id);
  viewer.render();
  window.meristem.ready = true;
}

// ---------------------------------------------------------------- test and script hooks

// The test suite waits for this: three.js from the web root has drawn a frame.
Object.defineProperty(window, 'meristemFramesDrawn', { get: () => viewer.frames, configurable: true });

const byId = (list) => Object.fromEntries(list.map((x) => [x.id, x]));
const toolsById = byId(tools), panelsById = byId(panels);
window.meristem = {
  api, viewer, session, state: session.state,
  tools: toolsById, panels: panelsById,
  ...toolsById,   // meristem.brush, .prune, .bend, ...
  ready: false,
  send: (edits, opts) => session.send(edits, opts),
  refresh: () => session.refresh(),
  setTool: (id) => input.setTool(id),
  stepN: (n) => panelsById.growth.stepN(n),
  undo: () => panelsById.history.undo(),
  /** The fork close-up (panels/view.js): resolves to the fork looked at, or null. */
  closeUp: (opts) => panelsById.view.closeUp(opts),
  redo: () => panelsById.history.redoLast(),
  get sessionId() { return session.state.id; },
  get summary() { return session.state.summary; },
  get lastLoadMs() { return session.state.lastLoadMs; },
  get lastLoad() { return viewer.lastLoad; },
  get constraint() { return session.state.constraint; },
  /** Resolves when no edit is queued and the snapshot shows the latest revision. */
  idle: () => session.idle(),
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
