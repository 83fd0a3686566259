// The Time panel of an inverse session (issue 16): a slider over the years the tree has
// grown, drawing it at any fractional year from snapshot.glb?t= (G04's continuous
// development: each metamer unfolds after G_e, G_lg and G_bg) without changing the
// session. Scrubbing keeps the last tree drawn until the next one is here; one snapshot
// is asked for at a time, the slider's newest value next, and one asked for a year the
// slider has left when it was let go is cancelled.
import * as api from '../api.js';
import { $ } from '../util.js';
import { viewOptions } from './view.js';

const fmtYear = (t) => (Number.isInteger(t) ? String(t) : t.toFixed(2));

export class TimePanel {
  id = 'time';

  constructor({ viewer, session }) {
    this.viewer = viewer;
    this.session = session;
    this.year = 0;            // the session's year (summary.inverse.year)
    this.viewing = null;      // the fractional year drawn, or null for the session's
    this.wanted = null;       // the year the slider asks for next
    this.inFlight = null;     // {t, abort: AbortController}
    this.fetching = null;
    this.requested = [];      // every t asked for (the tests read it)
    const slider = $('#time-slider');
    slider.addEventListener('input', () => this.scrub(Number(slider.value)));
    slider.addEventListener('change', () => this.settle());
    $('#time-play').addEventListener('click', () => this.play());
  }

  show(s) {
    const summary = this.session.state.summary;
    if (summary?.model !== 'inverse' || !summary.inverse) return;
    if (summary.id !== this.sessionId) {
      this.sessionId = summary.id;
      this.viewing = null;
    }
    this.year = summary.inverse.year;
    const slider = $('#time-slider');
    slider.max = String(this.year);
    slider.disabled = this.year === 0;
    if (this.viewing === null) slider.value = String(this.year);
    this.label();
  }

  label() {
    const y = this.viewing === null ? this.year : this.viewing;
    $('#time-at').textContent = `year ${fmtYear(y)}${this.viewing === null ? '' : ` of ${this.year}`}`;
  }

  /** An edit shows the session's tree again. */
  edited() {
    this.cancel();
    this.viewing = null;
    this.wanted = null;
    $('#time-slider').value = String(this.year);
    this.label();
  }

  /** The slider: draws the tree at year t (the session's own tree at its year). */
  async scrub(t) {
    if (!this.session.state.id) return;
    if (t >= this.year) { await this.backToLatest(); return; }
    this.viewing = t;
    this.wanted = t;
    this.label();
    if (this.fetching) return;
    this.fetching = (async () => {
      while (this.wanted !== null) {
        const want = this.wanted;
        this.wanted = null;
        const abort = new AbortController();
        this.inFlight = { t: want, abort };
        this.requested.push(want);
        try {
          await this.viewer.load(api.snapshotUrl(this.session.state.id,
            { ...viewOptions(), compact: true, t: want }), { signal: abort.signal });
        } catch (e) {
          if (e?.name !== 'AbortError') this.session.problem(e);
        } finally {
          this.inFlight = null;
        }
      }
    })().finally(() => { this.fetching = null; });
    await this.fetching;
  }

  /** The slider was let go: a request for a year it has left is stale. */
  settle() {
    if (this.inFlight && this.wanted !== null && this.inFlight.t !== this.wanted) this.inFlight.abort.abort();
  }

  cancel() {
    this.wanted = null;
    this.inFlight?.abort.abort();
  }

  async backToLatest() {
    this.cancel();
    this.viewing = null;
    $('#time-slider').value = String(this.year);
    this.label();
    await this.fetching;
    await this.session.refresh();
  }

  /** ▶: the tree's life from year 0 to its year, a tenth of a year a frame. */
  async play() {
    if (this.playing) { this.playing = false; return; }
    this.playing = true;
    $('#time-play').textContent = '❚❚';
    for (let t = 0; t < this.year && this.playing; t = Math.round((t + 0.1) * 10) / 10) {
      $('#time-slider').value = String(t);
      await this.scrub(t);
    }
    this.playing = false;
    $('#time-play').textContent = '▶';
    await this.backToLatest();
  }
}
