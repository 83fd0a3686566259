// The L-system panel (issue 15): the session's cpfg source in an editor with line
// numbers, a refusal shown at its line and column (the problem+json's), ABOP's presets,
// derive one step or up to the derivation length, and the summary's derivation step,
// string length and module counts. Apply sends set_lsystem: new productions from the
// next derivation step on, the string so far kept; Restart grows the source from its
// axiom as a new tree.
import * as api from '../api.js';
import { $ } from '../util.js';

const fmt = (n) => (typeof n === 'number' ? n.toLocaleString('en-US') : '–');
/** Module counts listed; the rest are summed in one row. */
const MODULE_ROWS = 12;

/** A textarea with a line-number gutter and one marked line (an error). */
class CodeEditor {
  constructor({ area, gutter, mark }) {
    this.area = area; this.gutter = gutter; this.mark = mark;
    this.markLine = null;
    area.addEventListener('input', () => { this.setMark(null); this.sync(); });
    area.addEventListener('scroll', () => this.sync());
    this.sync();
  }

  get text() { return this.area.value; }

  set text(v) {
    this.area.value = v;
    this.setMark(null);
    this.sync();
  }

  /** Marks line `line` (1-based; null: none) and puts the caret at `column` on it. */
  setMark(line, column = null) {
    this.markLine = line;
    if (line !== null && column !== null) {
      const lines = this.area.value.split('\n');
      const at = lines.slice(0, line - 1).reduce((n, l) => n + l.length + 1, 0) + Math.max(0, column - 1);
      this.area.focus({ preventScroll: true });
      this.area.setSelectionRange(at, at);
      // The line in the middle of the box; the column in view, with the line's start if it can.
      this.area.scrollTop = Math.max(0, (line - 1) * this.lineHeight() - this.area.clientHeight / 2);
      const cw = this.charWidth();
      this.area.scrollLeft = Math.max(0, (column + 4) * cw - this.area.clientWidth);
    }
    this.sync();
  }

  lineHeight() { return parseFloat(getComputedStyle(this.area).lineHeight) || 16; }

  /** The width of a character of the (monospace) font. */
  charWidth() {
    const c = (CodeEditor.canvas ||= document.createElement('canvas')).getContext('2d');
    c.font = getComputedStyle(this.area).font;
    return c.measureText('0').width || 7;
  }

  /** The gutter's numbers and the mark follow the text and its scroll. */
  sync() {
    const n = this.area.value.split('\n').length;
    if (this.gutter.childElementCount !== n) {
      this.gutter.replaceChildren(...Array.from({ length: n }, (_, i) => {
        const s = document.createElement('span');
        s.textContent = String(i + 1);
        return s;
      }));
    }
    [...this.gutter.children].forEach((s, i) => s.classList.toggle('error', i + 1 === this.markLine));
    this.gutter.scrollTop = this.area.scrollTop;
    const pad = parseFloat(getComputedStyle(this.area).paddingTop) || 0;
    this.mark.hidden = this.markLine === null;
    if (this.markLine !== null) {
      this.mark.style.top = `${pad + (this.markLine - 1) * this.lineHeight() - this.area.scrollTop}px`;
      this.mark.style.height = `${this.lineHeight()}px`;
    }
  }
}

export class LSystemPanel {
  id = 'lsystem';

  constructor({ session }) {
    this.session = session;
    this.sources = new Map();    // preset name → its cpfg source
    this.sessionId = null;
    this.editor = new CodeEditor({ area: $('#ls-source'), gutter: $('#ls-gutter'), mark: $('#ls-mark') });
    $('#ls-apply').addEventListener('click', () => this.apply());
    $('#ls-restart').addEventListener('click', () => this.restart());
    $('#ls-open').addEventListener('click', () => this.open($('#ls-preset').value));
    $('#ls-derive').addEventListener('click', () => this.derive(1));
    $('#ls-derive-all').addEventListener('click', () => {
      const ls = session.state.summary?.lsystem;
      if (ls) this.derive(Math.max(1, ls.derivation_length - ls.derivation_step));
    });
    $('#ls-source').addEventListener('keydown', (e) => {
      if (e.key === 'Enter' && (e.ctrlKey || e.metaKey)) { e.preventDefault(); this.apply(); }
    });
  }

  /** The L-system presets and their sources (GET /v1/presets). */
  presets({ presets }) {
    const mine = presets.filter((p) => p.model === 'lsystem' && p.lsystem?.source);
    for (const p of mine) this.sources.set(p.name, p.lsystem.source);
    $('#ls-preset').replaceChildren(...mine.map((p) => {
      const o = new Option(p.name, p.name);
      o.title = p.description;
      return o;
    }));
  }

  show(s) {
    const summary = this.session.state.summary;
    if (summary?.model !== 'lsystem') return;
    if (summary.id !== this.sessionId) {
      this.sessionId = summary.id;
      this.showError(null);
      this.loadSource(summary);
    }
    const ls = s.lsystem || summary.lsystem;
    if (ls) this.showStats(ls);
  }

  /** The open session's source: meristemd's (GET …/lsystem), else its preset's. */
  async loadSource(summary) {
    let text = null;
    try {
      text = (await api.lsystemSource(summary.id)).source;
    } catch { /* a meristemd without the route: the preset's source */ }
    if (this.sessionId !== summary.id) return;
    if (text === null) text = this.sources.get(summary.preset) ?? '';
    this.editor.text = text;
    if ([...$('#ls-preset').options].some((o) => o.value === summary.preset)) $('#ls-preset').value = summary.preset;
  }

  showStats(ls) {
    $('#ls-step').textContent = `${fmt(ls.derivation_step)} / ${fmt(ls.derivation_length)}`;
    $('#ls-segments').textContent = fmt(ls.segments);
    $('#ls-length').textContent = fmt(ls.string_length);
    $('#ls-derive').disabled = $('#ls-derive-all').disabled = ls.derivation_step >= ls.derivation_length;
    const counts = Object.entries(ls.modules || {}).sort((a, b) => b[1] - a[1] || a[0].localeCompare(b[0]));
    const rows = counts.slice(0, MODULE_ROWS);
    const rest = counts.slice(MODULE_ROWS).reduce((n, [, c]) => n + c, 0);
    if (rest) rows.push([`${counts.length - MODULE_ROWS} more`, rest]);
    const max = Math.max(1, ...counts.map(([, c]) => c));
    $('#ls-modules').replaceChildren(...rows.map(([m, c]) => {
      const tr = document.createElement('tr');
      tr.innerHTML = '<th></th><td class="n"></td><td class="bar"><i></i></td>';
      tr.querySelector('th').textContent = m;
      tr.querySelector('.n').textContent = fmt(c);
      tr.querySelector('i').style.width = `${(100 * Math.min(c, max)) / max}%`;
      return tr;
    }));
  }

  /** A refusal of a source: at its line in the editor and below it; null clears it. */
  showError(p) {
    const box = $('#ls-error');
    if (!p) { box.hidden = true; this.editor.setMark(null); return; }
    box.hidden = false;
    const where = p.line !== null ? `line ${p.line}${p.column !== null ? `, column ${p.column}` : ''}` : '';
    // meristemd's detail usually says where already.
    box.textContent = where && !p.detail.startsWith(where) ? `${where}: ${p.detail}` : p.detail;
    if (p.line !== null) this.editor.setMark(p.line, p.column);
  }

  /** Sends the editor's source as set_lsystem; a refusal is shown at its line. */
  async apply() {
    const s = await this.session.send([{ op: 'set_lsystem', source: this.editor.text }]);
    this.showError(s ? null : this.session.state.lastProblem);
    return s;
  }

  derive(n) { return this.session.send([{ op: 'step', count: n }]); }

  /** A new tree from preset `name` (its source comes into the editor when it opens). */
  open(name) {
    return this.session.create({ preset: name, seed: this.seed() });
  }

  /** A new tree from the editor's source, from its axiom. */
  async restart() {
    const s = await this.session.create({ model: 'lsystem', seed: this.seed(),
      lsystem: { source: this.editor.text } });
    this.showError(s ? null : this.session.state.lastProblem);
    return s;
  }

  seed() { return this.session.state.summary?.seed ?? 0; }
}
