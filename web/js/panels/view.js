// The View panel: what the snapshot shows (bark, leaves, markers, grid, colour, detail)
// and the download link.
import * as api from '../api.js';
import { $ } from '../util.js';

/** The snapshot options the panel selects (api.snapshotUrl's). */
export function viewOptions() {
  return { detail: Number($('#detail').value), leaves: $('#show-leaves').checked,
    markers: $('#show-markers').checked, color: $('#color').value, junctions: $('#junctions').checked };
}

/** The thickest fork with a lateral at least a quarter as thick as its parent (the
 * forks implicit junctions mesh first): its point and its parent's diameter, or null. */
export function thickestFork(nodes) {
  const byId = new Map(nodes.map((n) => [n.id, n]));
  let best = null;
  for (const n of nodes) {
    const p = n.parent === null ? null : byId.get(n.parent);
    if (!p || !n.alive || n.order <= p.order || n.diameter < 0.25 * p.diameter) continue;
    if (!best || p.diameter > best.diameter) best = { at: p.tip, diameter: p.diameter };
  }
  return best;
}

/** Sets the panel from a gallery page's query (?view=gallery&markers=1&leaves=0&detail=3&color=order). */
export function viewFromQuery(params) {
  $('#show-markers').checked = params.get('markers') === '1';
  $('#show-leaves').checked = params.get('leaves') !== '0';
  $('#detail').value = params.get('detail') || '3';
  if (params.get('color')) $('#color').value = params.get('color');
  $('#junctions').checked = params.get('junctions') === 'implicit';
}

export class ViewPanel {
  id = 'view';

  constructor({ viewer, session }) {
    this.session = session;
    const refresh = () => session.refresh();
    $('#show-bark').addEventListener('change', (e) => viewer.setVisible({ bark: e.target.checked }));
    $('#show-leaves').addEventListener('change', (e) => { viewer.setVisible({ leaves: e.target.checked }); refresh(); });
    $('#show-markers').addEventListener('change', refresh);
    $('#show-grid').addEventListener('change', (e) => viewer.setGridVisible(e.target.checked));
    $('#color').addEventListener('change', refresh);
    $('#detail').addEventListener('change', refresh);
    $('#junctions').addEventListener('change', refresh);
    // A close-up of the thickest fork, where implicit junctions show their ridge.
    $('#fork-close-up').addEventListener('click', () => {
      session.skeleton().then((skel) => {
        const fork = skel && thickestFork([...skel.byId.values()]);
        if (fork) viewer.closeUp(fork.at, 3 * fork.diameter);
      });
    });
  }

  /** A new snapshot: the download link follows it (at detail 3 or more, uncompressed). */
  loaded() {
    const { state } = this.session;
    const a = $('#download');
    if (!state.id) { a.removeAttribute('href'); return; }
    a.href = api.snapshotUrl(state.id, { ...viewOptions(), detail: Math.max(3, Number($('#detail').value)) });
    a.download = `meristem-${state.id.slice(0, 8)}-step${state.summary?.step ?? 0}.glb`;
  }
}
