// The session the page shows. State lives in meristemd; the page keeps the session id,
// its last summary, a queue that sends edits one at a time, and the snapshot reloads
// that follow them. Panels and tools follow the session through onSummary and onLoaded.
import * as api from './api.js';
import { sleep } from './util.js';
import { hideProblem, setStatus, showProblem } from './status.js';
import { GrowthConstraint } from './constraint.js';
import { viewOptions } from './panels/view.js';

export class Session {
  /**
   * @param viewer the Viewer
   * @param gesture () => whether a tool's gesture is under way: the camera then stays
   *   put however the tree grows
   */
  constructor(viewer, { gesture = () => false } = {}) {
    this.viewer = viewer;
    this.gesture = gesture;
    this.state = {
      id: null, summary: null, presets: [], tool: 'view', playing: false,
      constraint: null, constraintSince: -1, busy: 0, loads: 0, lastLoadMs: null,
      framedHeight: 0, lastProblem: null,
    };
    this.constraint = new GrowthConstraint(this);
    this.chain = Promise.resolve();   // the edits sent so far, in order
    this.loading = null;              // the snapshot reload under way
    this.reloadAgain = false;
    this.summaryListeners = [];
    this.loadedListeners = [];
    this.editedListeners = [];
  }

  /** Calls fn(edits) after meristemd accepted edits the page sent. */
  onEdited(fn) { this.editedListeners.push(fn); }

  /** Calls fn(summary) with every summary meristemd sends for this session. */
  onSummary(fn) { this.summaryListeners.push(fn); }

  /** Calls fn(viewer.lastLoad) whenever a new snapshot is drawn. */
  onLoaded(fn) { this.loadedListeners.push(fn); }

  /** Shows a refusal or an error, and remembers it (state.lastProblem). */
  problem(e) { this.state.lastProblem = showProblem(e); }

  applySummary(s) {
    const { state } = this;
    if (!s || (state.id && s.id && s.id !== state.id)) return;
    state.summary = { ...state.summary, ...s };
    for (const fn of this.summaryListeners) fn(s);
    if (s.constraint !== undefined) this.constraint.set(s.constraint);   // when meristemd reports it
    if (s.interrupted) setStatus(`step interrupted (${s.interrupted}) after ${s.steps_done} steps`, 'warn');
    if (s.steps_done !== undefined) this.constraint.stalled(s);
    // Keep a growing tree in view.
    if (s.height > state.framedHeight * 1.25 + 2 && !this.gesture()) {
      this.viewer.frame(s.bounds, { whole: state.summary.model === 'forest' });
      state.framedHeight = s.height;
    }
  }

  /** Reloads the snapshot (If-None-Match: a 304 costs nothing); coalesces overlapping calls. */
  refresh() {
    const { state, viewer } = this;
    if (!state.id) return Promise.resolve();
    if (this.loading) { this.reloadAgain = true; return this.loading; }
    this.loading = (async () => {
      do {
        this.reloadAgain = false;
        try {
          const r = await viewer.load(api.snapshotUrl(state.id, { ...viewOptions(), compact: true }));
          if (r.changed) {
            state.loads++;
            state.lastLoadMs = viewer.lastLoad.ms;
            for (const fn of this.loadedListeners) fn(viewer.lastLoad);
            this.constraint.show();
          }
        } catch (e) {
          this.problem(e);
        }
      } while (this.reloadAgain);
    })().finally(() => { this.loading = null; });
    return this.loading;
  }

  /**
   * Sends edits in order (one request at a time, so a stroke's batches and the growth
   * steps never overtake each other). Resolves to the summary, or null when refused
   * (the problem is shown in the page).
   */
  send(edits, { reload = true } = {}) {
    const { state } = this;
    const p = this.chain.then(async () => {
      if (!state.id) return null;
      state.busy++;
      try {
        const s = await api.edit(state.id, edits);
        this.constraint.edited(edits);
        for (const fn of this.editedListeners) fn(edits);
        this.applySummary(s);
        if (reload) this.refresh();
        return s;
      } catch (e) {
        this.problem(e);
        return null;
      } finally {
        state.busy--;
      }
    });
    this.chain = p.catch(() => null);
    return p;
  }

  /**
   * Creates a session (api.createSession's spec) and opens it through `opener` (the
   * page's: the top bar follows it); resolves to its summary, or null when refused
   * (the problem is shown, and kept in state.lastProblem).
   */
  async create(spec) {
    this.state.playing = false;
    try {
      const summary = await api.createSession(spec);
      await (this.opener ? this.opener(summary) : this.open(summary));
      return summary;
    } catch (e) {
      this.problem(e);
      return null;
    }
  }

  /** Shows the session `summary` describes (a new one, or one reopened by its id). */
  async open(summary) {
    const { state, viewer } = this;
    hideProblem();   // the last session's
    state.id = summary.id;
    state.summary = null;
    state.constraint = null;
    state.constraintSince = -1;
    state.framedHeight = 0;
    viewer.framed = false;
    viewer.etag = null;
    this.constraint.restore();
    this.applySummary(summary);
    viewer.frame(summary.bounds, { whole: summary.model === 'forest' });
    state.framedHeight = summary.height;
    await this.refresh();
    this.constraint.show();
  }

  /**
   * The session's skeleton at its current revision (GET …/skeleton?alive=1), indexed:
   * {byId: Map id → node, children: Map id → [ids]}; null when meristemd has none to
   * give. Fetched once per revision.
   */
  skeleton() {
    const { state } = this;
    const rev = state.summary?.revision;
    if (!state.id || rev === undefined || this.noSkeleton) return Promise.resolve(null);
    if (this._skeleton?.rev === rev && this._skeleton.id === state.id) return this._skeleton.p;
    const p = api.skeleton(state.id).then((body) => {
      const byId = new Map(), children = new Map();
      for (const n of body.nodes) {
        byId.set(n.id, n);
        if (n.parent !== null) (children.get(n.parent) || children.set(n.parent, []).get(n.parent)).push(n.id);
      }
      return { byId, children };
    }).catch((e) => {
      // A meristemd without the route: the tools go without it for this page's life.
      if (e instanceof api.Problem && e.status === 404 && !e.type.includes('session')) this.noSkeleton = true;
      return null;
    });
    this._skeleton = { id: state.id, rev, p };
    return p;
  }

  /** Points the camera at the whole tree. */
  frame() {
    const { state, viewer } = this;
    if (!state.summary) return;
    viewer.framed = false;
    viewer.frame(state.summary.bounds, { whole: state.summary.model === 'forest' });
    state.framedHeight = state.summary.height;
  }

  /** Resolves when no edit is queued and the snapshot shows the latest revision. */
  async idle() {
    for (;;) {
      await this.chain;
      await this.refresh();
      if (!this.state.busy && !this.loading && !this.gesture()) return this.state.summary;
      await sleep(20);
    }
  }
}
