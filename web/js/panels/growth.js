// The Growth panel: step once or N times (with a progress bar and Cancel for long
// runs), play and pause at a rate, and the tree's figures.
import * as api from '../api.js';
import { $, sleep } from '../util.js';

const fmt = (n) => (typeof n === 'number' ? n.toLocaleString('en-US') : '–');

export class GrowthPanel {
  id = 'growth';

  constructor({ session }) {
    this.session = session;
    /** Keys (lower case) the panel answers: S steps once, space plays or pauses. */
    this.keys = {
      s: () => this.stepN(1),
      ' ': (e) => { e.preventDefault(); this.play(); },
    };
    $('#cancel').addEventListener('click', async () => {
      try { await api.cancel(session.state.id); } catch (e) { session.problem(e); }
    });
    $('#step-once').addEventListener('click', () => this.stepN(1));
    $('#step-n').addEventListener('click', () => this.stepN(Math.max(1, Math.round(Number($('#step-count').value) || 1))));
    const syncStepLabel = () => { $('#step-n').textContent = `Step ×${$('#step-count').value}`; };
    $('#step-count').addEventListener('input', syncStepLabel);
    syncStepLabel();
    $('#play').addEventListener('click', () => this.play());
  }

  /** The tree's figures from a summary: buds and markers only for the models
   * that have them (an L-system has no buds, an L-system or an inverse tree no
   * environment to draw markers from). */
  show(s) {
    const model = s.model ?? 'p09';
    $('#stat-step').textContent = fmt(s.step);
    $('#stat-internodes').textContent = fmt(s.internodes);
    this._row('#stat-buds', model !== 'lsystem', s.buds);
    this._row('#stat-markers', model !== 'lsystem' && model !== 'inverse', s.markers);
    $('#stat-height').textContent = typeof s.height === 'number' ? s.height.toFixed(2) : '–';
    $('#stat-revision').textContent = fmt(s.revision);
  }

  /** Shows the figure `value` in the stats row of `sel` (its term and value), or hides the row. */
  _row(sel, shown, value) {
    const dd = $(sel);
    dd.hidden = !shown;
    dd.previousElementSibling.hidden = !shown;
    dd.textContent = fmt(value);
  }

  /** What the last snapshot cost to load and draw. */
  loaded(load) {
    $('#stat-load').textContent = `${load.ms.toFixed(0)} ms`;
    $('#stat-load').title = `fetch ${load.fetchMs.toFixed(1)} ms, parse ${load.parseMs.toFixed(1)} ms, ` +
      `draw ${load.renderMs.toFixed(1)} ms; ${load.bytes} bytes, ${load.triangles} triangles`;
  }

  /** Grows `n` steps; resolves to the summary (null when refused). */
  async stepN(n) {
    const p = this.session.send([{ op: 'step', count: n }]);
    if (n > 1) this._trackProgress(p);
    return p;
  }

  /** Shows the progress of a long step request until it settles. */
  async _trackProgress(p) {
    let done = false;
    p.finally(() => { done = true; });
    await sleep(120);
    const box = $('#progress');
    while (!done) {
      try {
        const s = await api.getSession(this.session.state.id);
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

  /** Plays (one step, then its snapshot, at the chosen rate), or pauses. */
  async play() {
    const { session } = this, { state } = session;
    if (state.playing) { state.playing = false; return; }
    state.playing = true;
    $('#play').textContent = '❚❚ Pause';
    $('#play').classList.add('playing');
    while (state.playing && state.id) {
      const t = performance.now();
      const s = await session.send([{ op: 'step', count: 1 }], { reload: false });
      if (!s) break;
      await session.refresh();
      const wait = 1000 / Number($('#rate').value) - (performance.now() - t);
      if (wait > 0) await sleep(wait);
    }
    state.playing = false;
    $('#play').textContent = '▶ Play';
    $('#play').classList.remove('playing');
  }
}
