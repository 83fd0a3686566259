// The View panel: what the snapshot shows (bark, leaves, markers, grid, colour, detail)
// and the download link.
import * as api from '../api.js';
import { $ } from '../util.js';

/** The snapshot options the panel selects (api.snapshotUrl's). */
export function viewOptions() {
  return { detail: Number($('#detail').value), leaves: $('#show-leaves').checked,
    markers: $('#show-markers').checked, color: $('#color').value };
}

/** Sets the panel from a gallery page's query (?view=gallery&markers=1&leaves=0&detail=3&color=order). */
export function viewFromQuery(params) {
  $('#show-markers').checked = params.get('markers') === '1';
  $('#show-leaves').checked = params.get('leaves') !== '0';
  $('#detail').value = params.get('detail') || '3';
  if (params.get('color')) $('#color').value = params.get('color');
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
