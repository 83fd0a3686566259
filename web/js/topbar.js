// The top bar: the preset list with its description, the seed, New tree, and the open
// session's id (which the page's URL carries: ?session=ID, so a reload or a shared
// link returns to the same tree).
import { $ } from './util.js';

export class TopBar {
  /** @param onNew (preset, seed) => called when the user asks for a new tree */
  constructor({ onNew }) {
    this.presets = [];
    $('#preset').addEventListener('change', () => this.describePreset());
    $('#session-form').addEventListener('submit', (e) => {
      e.preventDefault();
      onNew($('#preset').value, Math.max(0, Math.round(Number($('#seed').value) || 0)));
    });
  }

  /** Fills the preset list (GET /v1/presets: presets [{name, description}]). */
  setPresets(presets) {
    this.presets = presets;
    for (const x of presets) $('#preset').add(new Option(x.name, x.name));
    $('#preset').value = presets.some((x) => x.name === 'fig15-brushed') ? 'fig15-brushed' : presets[0]?.name;
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
    if ([...$('#preset').options].some((o) => o.value === summary.preset)) $('#preset').value = summary.preset;
    $('#seed').value = String(summary.seed);
    this.describePreset();
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
