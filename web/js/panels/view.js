// The View panel: what the snapshot shows (bark, leaves, markers, grid, colour, detail)
// and the download link.
import * as api from '../api.js';
import { $ } from '../util.js';
import { forks, chooseFork, forkView } from '../viewer/fork.js';

/** The snapshot options the panel selects (api.snapshotUrl's). */
export function viewOptions() {
  return { detail: Number($('#detail').value), leaves: $('#show-leaves').checked,
    markers: $('#show-markers').checked, color: $('#color').value, junctions: $('#junctions').checked };
}

/** Sets the panel from a gallery page's query (?view=gallery&markers=1&leaves=0&detail=3&color=order
 * &junctions=implicit). */
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
    this.viewer = viewer;
    this.pointer = null;   // the pointer over the view, client px, or null
    this.fork = null;      // the fork of the last close-up
    const refresh = () => session.refresh();
    $('#show-bark').addEventListener('change', (e) => viewer.setVisible({ bark: e.target.checked }));
    $('#show-leaves').addEventListener('change', (e) => { viewer.setVisible({ leaves: e.target.checked }); refresh(); });
    $('#show-markers').addEventListener('change', refresh);
    $('#show-grid').addEventListener('change', (e) => viewer.setGridVisible(e.target.checked));
    $('#color').addEventListener('change', refresh);
    $('#detail').addEventListener('change', refresh);
    $('#junctions').addEventListener('change', refresh);
    $('#fork-close-up').addEventListener('click', () => this.closeUp());
    const canvas = viewer.renderer.domElement;
    canvas.addEventListener('pointermove', (e) => { this.pointer = { x: e.clientX, y: e.clientY }; });
    canvas.addEventListener('pointerleave', () => { this.pointer = null; });
    this.keys = { c: () => this.closeUp({ atPointer: true }) };
  }

  /**
   * A close-up of a fork, where implicit junctions show their blend and ridge
   * (viewer/fork.js): the fork of lateral `lateral` (a node id), or with `atPointer`
   * the fork nearest the tree under the pointer, else the thickest fork with a
   * junction patch (or that would get one). Resolves to the fork, or null.
   */
  async closeUp({ lateral = null, atPointer = false } = {}) {
    const skel = await this.session.skeleton();
    if (!skel) return null;
    const nodes = [...skel.byId.values()];
    let fork;
    if (lateral !== null) {
      fork = forks(nodes).find((f) => f.lateral.id === lateral) || null;
    } else {
      const hit = atPointer && this.pointer ? this.viewer.pick(this.pointer.x, this.pointer.y) : null;
      fork = chooseFork(nodes, {
        patched: this.viewer.junctionForks, ridge: this.viewer.ridgePoints(), near: hit ? hit.point.toArray() : null,
      });
    }
    if (!fork) return null;
    const v = forkView(fork);
    this.viewer.closeUp(v.center, v.radius, v.dir);
    this.fork = fork;
    return fork;
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
