// The Functions panel of an inverse session (issue 16): each graphically defined
// function of G04 §4 drawn as a small curve with its control points, its symbol and what
// it controls. Dragging a point sends the function as set_functions (at most one request
// per DEBOUNCE_MS while dragging, and once more when the point is let go): the tree
// regrows from it at every year. The functions download and upload as lpfg .fset text.
import * as api from '../api.js';
import { $ } from '../util.js';
import { FUNCTION_INFO, curve, fsetText } from './gfunc.js';

export const DEBOUNCE_MS = 250;
const W = 150, H = 78, PAD = 6;
const SVG = 'http://www.w3.org/2000/svg';

const svgEl = (name, attrs = {}) => {
  const e = document.createElementNS(SVG, name);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, String(v));
  return e;
};

/** One function's card: the curve, the control polygon and its draggable points. */
class FunctionCard {
  constructor(f, onChange) {
    this.f = f;
    this.onChange = onChange;
    // The view's y range: [0, 1], or wider when the function leaves it.
    const ys = f.points.map((p) => p[1]);
    this.lo = Math.min(0, ...ys);
    this.hi = Math.max(1, ...ys);
    this.el = document.createElement('figure');
    this.el.className = 'fn';
    this.el.dataset.name = f.name;
    const [what, long, axis] = FUNCTION_INFO[f.name] || ['', '', 'x'];
    const cap = document.createElement('figcaption');
    cap.innerHTML = '<b class="symbol"></b> <span></span>';
    const [base, sub] = f.name.split(/_(.*)/);   // G_s2: G with s2 as a subscript
    const sym = cap.querySelector('b');
    sym.textContent = base;
    if (sub) sym.append(Object.assign(document.createElement('sub'), { textContent: sub }));
    cap.querySelector('span').textContent = what;
    cap.title = `${f.name}: ${long}; x: ${axis}${f.kind === 'linear' ? '; a polyline' : '; a cubic B-spline'}`;
    this.svg = svgEl('svg', { viewBox: `0 0 ${W} ${H}`, role: 'img', 'aria-label': `${f.name}: ${long}` });
    const axisLabel = document.createElement('small');
    axisLabel.className = 'axis';
    axisLabel.textContent = `x: ${axis}`;
    this.el.append(cap, this.svg, axisLabel);
    this.draw();
  }

  sx(x) { return PAD + x * (W - 2 * PAD); }
  sy(y) { return H - PAD - ((y - this.lo) / (this.hi - this.lo)) * (H - 2 * PAD); }

  draw() {
    const { f, svg } = this;
    svg.replaceChildren();
    const grid = svgEl('g', { class: 'grid' });
    for (const y of [this.lo, 0.5 * (this.lo + this.hi), this.hi]) {
      grid.append(svgEl('line', { x1: this.sx(0), x2: this.sx(1), y1: this.sy(y), y2: this.sy(y) }));
    }
    if (this.lo < 0) grid.append(svgEl('line', { class: 'zero', x1: this.sx(0), x2: this.sx(1), y1: this.sy(0), y2: this.sy(0) }));
    for (const x of [0, 0.5, 1]) grid.append(svgEl('line', { x1: this.sx(x), x2: this.sx(x), y1: this.sy(this.lo), y2: this.sy(this.hi) }));
    svg.append(grid);
    const path = (pts) => pts.map(([x, y], i) => `${i ? 'L' : 'M'}${this.sx(x).toFixed(1)},${this.sy(y).toFixed(1)}`).join('');
    if (f.kind !== 'linear') svg.append(svgEl('path', { class: 'polygon', d: path(f.points) }));
    svg.append(svgEl('path', { class: 'curve', d: path(curve(f)) }));
    f.points.forEach(([x, y, m = 1], i) => {
      const g = svgEl('g', { class: 'point', 'data-index': i });
      g.append(svgEl('circle', { class: 'hit', cx: this.sx(x), cy: this.sy(y), r: 9 }));
      g.append(svgEl('circle', { class: m > 1 ? 'dot multiple' : 'dot', cx: this.sx(x), cy: this.sy(y), r: 3.6 }));
      const title = svgEl('title');
      title.textContent = `(${x.toFixed(3)}, ${y.toFixed(3)})${m > 1 ? ` ×${m}` : ''}: drag`;
      g.append(title);
      g.addEventListener('pointerdown', (e) => this.grab(e, i));
      svg.append(g);
    });
  }

  /** A drag of point i: its x stays between its neighbours' (the ends' at 0 and 1). */
  grab(e, i) {
    e.preventDefault();
    this.svg.setPointerCapture(e.pointerId);
    this.el.classList.add('dragging');
    const pts = this.f.points;
    // The point follows the pointer's motion from where it was grabbed (no jump).
    const toSvg = (ev) => new DOMPoint(ev.clientX, ev.clientY).matrixTransform(this.svg.getScreenCTM().inverse());
    const p0 = toSvg(e), [x0, y0] = pts[i];
    let moved = false;
    const move = (ev) => {
      moved = true;
      const p = toSvg(ev);
      const x = x0 + (p.x - p0.x) / (W - 2 * PAD);
      const y = y0 - ((p.y - p0.y) / (H - 2 * PAD)) * (this.hi - this.lo);
      const first = i === 0, last = i === pts.length - 1;
      const xlo = first ? 0 : pts[i - 1][0], xhi = last ? 1 : pts[i + 1][0];
      pts[i][0] = first ? 0 : last ? 1 : Math.min(xhi, Math.max(xlo, x));
      pts[i][1] = Math.min(this.hi, Math.max(this.lo, y));
      this.draw();
      this.onChange(this, false);
    };
    const up = (ev) => {
      this.svg.removeEventListener('pointermove', move);
      this.svg.removeEventListener('pointerup', up);
      this.svg.removeEventListener('pointercancel', up);
      this.svg.releasePointerCapture(ev.pointerId);
      this.el.classList.remove('dragging');
      if (moved) this.onChange(this, true);
    };
    this.svg.addEventListener('pointermove', move);
    this.svg.addEventListener('pointerup', up);
    this.svg.addEventListener('pointercancel', up);
  }
}

export class InversePanel {
  id = 'inverse';

  constructor({ session }) {
    this.session = session;
    this.sessionId = null;
    this.cards = [];
    this.dirty = new Set();    // cards changed since the last set_functions sent
    this.timer = null;
    this.sending = null;
    this.sent = 0;             // set_functions edits sent from a drag (the tests read it)
    $('#inv-upload').addEventListener('change', (e) => this.upload(e.target));
  }

  show() {
    const summary = this.session.state.summary;
    if (summary?.model !== 'inverse' || summary.id === this.sessionId) return;
    this.sessionId = summary.id;
    const a = $('#inv-download');
    a.href = api.functionsUrl(summary.id);
    a.download = `${summary.preset || 'functions'}-${summary.id.slice(0, 8)}.fset`;
    this.load();
  }

  /** The functions meristemd holds now (after a session opens, an upload, a revert). */
  async load() {
    const id = this.sessionId;
    try {
      const { functions } = await api.functions(id);
      if (id !== this.sessionId || this.dirty.size) return;
      this.cards = functions.map((f) => new FunctionCard(f, (card, done) => this.changed(card, done)));
      $('#inv-functions').replaceChildren(...this.cards.map((c) => c.el));
    } catch (e) {
      this.session.problem(e);
    }
  }

  /** Functions may have changed other than by a drag here: draw meristemd's. */
  edited(edits) {
    if (this.session.state.summary?.model !== 'inverse') return;
    if (edits.some((e) => e.op === 'revert' || (e.op === 'set_functions' && !e.fromDrag))) this.load();
  }

  /** A card's point moved (done: let go): send within DEBOUNCE_MS, or now. */
  changed(card, done) {
    this.dirty.add(card);
    if (done) this.flush();
    else if (!this.timer) this.timer = setTimeout(() => this.flush(), DEBOUNCE_MS);
  }

  /** Sends the changed functions as one set_functions edit; while one is under way,
   * the changes wait for it (a slow regrowth never queues a backlog of edits). */
  async flush() {
    clearTimeout(this.timer);
    this.timer = null;
    if (this.sending || !this.dirty.size) return null;
    const fs = [...this.dirty].map((c) => c.f);
    this.dirty.clear();
    this.sent++;
    const edit = { op: 'set_functions', fset: fsetText(fs) };
    Object.defineProperty(edit, 'fromDrag', { value: true });   // not enumerable: not sent
    this.sending = this.session.send([edit]);
    const s = await this.sending;
    this.sending = null;
    if (this.dirty.size) this.flush();
    return s;
  }

  /** An .fset file chosen to upload: it replaces the functions it names. */
  async upload(input) {
    const file = input.files?.[0];
    input.value = '';
    if (!file) return null;
    return this.session.send([{ op: 'set_functions', fset: await file.text() }]);
  }
}
