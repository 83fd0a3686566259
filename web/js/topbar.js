// The top bar: the growth model, its presets with their description, the seed, New
// tree, and the open session's id (which the page's URL carries: ?session=ID, so a
// reload or a shared link returns to the same tree).
import { $ } from './util.js';
import { MODELS } from './models.js';

export class TopBar {
  /** @param onNew ({model, preset, seed}) => called when the user asks for a new tree */
  constructor({ onNew }) {
    this.presets = [];
    for (const m of MODELS) $('#model').add(new Option(m.label, m.id));
    $('#model').addEventListener('change', () => { this.listPresets(); this.showSow(); });
    $('#preset').addEventListener('change', () => this.describePreset());
    $('#session-form').addEventListener('submit', (e) => {
      e.preventDefault();
      const seed = Math.max(0, Math.round(Number($('#seed').value) || 0));
      if ($('#model').value === 'forest') onNew({ seed, scene: { sow: this.sow(seed) } });
      else onNew({ preset: $('#preset').value, seed });   // a preset names its model
    });
  }

  /** scene.sow from the top bar's fields: a square area centred on the origin. */
  sow(seed) {
    const half = Math.max(0.5, Number($('#sow-size').value) || 50) / 2;
    return {
      area: [[-half, -half], [half, half]],
      count: Math.max(1, Math.round(Number($('#sow-count').value) || 1)),
      min_distance: Number($('#sow-distance').value) || 8,
      presets: $('#sow-presets').value.split(/[\s,]+/).filter(Boolean),
      seed,
    };
  }

  /** A forest has no preset of its own: its fields replace the preset list and its
   * description (index.html: what sowing does is their title). */
  showSow() {
    const sown = $('#model').value === 'forest';
    $('#sow-fields').hidden = !sown;
    $('#preset-label').hidden = sown;
    $('#preset-description').hidden = sown;
  }

  /** Keeps the presets (GET /v1/presets: presets [{name, description, model}]) and lists
   * the chosen model's. */
  setPresets(presets) {
    this.presets = presets;
    // A model no preset grows is not offered.
    for (const o of [...$('#model').options]) {
      o.hidden = !MODELS.find((m) => m.id === o.value)?.sown && !presets.some((x) => (x.model || 'p09') === o.value);
    }
    this.listPresets();
  }

  /** The preset list: the chosen model's presets (P09's first choice: fig15-brushed). */
  listPresets(keep = null) {
    const model = $('#model').value;
    const mine = this.presets.filter((x) => (x.model || 'p09') === model);
    $('#preset').replaceChildren(...mine.map((x) => new Option(x.name, x.name)));
    const first = MODELS.find((m) => m.id === model)?.firstPreset;
    $('#preset').value = [keep, first].find((n) => mine.some((x) => x.name === n)) || mine[0]?.name || '';
    this.describePreset();
  }

  describePreset() {
    const p = this.presets.find((x) => x.name === $('#preset').value);
    $('#preset-description').textContent = p ? p.description : '';
  }

  /** Shows an opened session, and puts its id in the page's URL. */
  show(summary) {
    const url = new URL(location.href);
    url.searchParams.set('session', summary.id);
    url.hash = '';
    history.replaceState(null, '', url);
    $('#session-id').textContent = summary.id.slice(0, 8);
    $('#session-id').title = `session ${summary.id} (${summary.preset}, seed ${summary.seed}) — the URL reopens it`;
    if (summary.model && summary.model !== $('#model').value) {
      $('#model').value = summary.model;
      this.listPresets(summary.preset);
    } else if ([...$('#preset').options].some((o) => o.value === summary.preset)) {
      $('#preset').value = summary.preset;
    }
    $('#seed').value = String(summary.seed);
    this.describePreset();
    this.showSow();
    document.body.classList.add('has-session');
  }
}

/** The session id the page was opened with (?session=ID, or an old-style #ID), or null. */
export function sessionFromUrl() {
  const q = new URLSearchParams(location.search).get('session');
  if (q) return q;
  const h = location.hash.replace(/^#/, '');
  return /^[0-9a-f]{32}$/.test(h) ? h : null;
}

/** Takes a session that could not be opened out of the page's URL. */
export function forgetSessionInUrl() {
  const url = new URL(location.href);
  url.searchParams.delete('session');
  history.replaceState(null, '', url);
}
