// The growth constraint (Palubicki et al. 2009, §5, Fig. 15b): a brush stroke begun on a
// branch with Shift held (or with "grow only from here" on) confines growth to that bud's
// descendants until released. The page shows it, draws the constrained branch so that it
// is seen at any zoom, says so when a step grows nothing and why, and remembers the
// constraint per session across reloads.
import * as THREE from 'three';
import { $ } from './util.js';

/** Fig. 15b shows the constrained branch in purple. */
export const CONSTRAINED = 0xa040c8;

/** What a summary's stalled.reason means, for the page. */
const STALL_TEXT = {
  constrained: 'growth is constrained to node {node}, and nothing above it can grow',
  'all-buds-dead': 'no living bud is left on the tree',
  'no-markers': 'no bud has a free marker within reach (brush some more)',
  'no-light': 'no bud gets light enough to grow',
  done: 'the model has grown all it will (its iterations or derivation length are used up)',
};

export class GrowthConstraint {
  /** @param session the Session: its viewer, state (constraint, constraintSince) and send */
  constructor(session) {
    this.session = session;
    const release = () => session.send([{ op: 'release' }]);
    $('#release').addEventListener('click', release);
    $('#stalled-release').addEventListener('click', release);
    $('#stalled-close').addEventListener('click', () => { $('#stalled').hidden = true; });
    // Lines and a pin drawn over everything, in pixels: seen however far the camera is.
    this.marks = new THREE.Group();
    this.marks.renderOrder = 20;
    session.viewer.preview.add(this.marks);
  }

  _key() { return `meristem.constraint.${this.session.state.id}`; }

  /** Sets the constraint {node, bud} (null: none); `since` is the largest node id then. */
  set(c, since) {
    const { state } = this.session;
    if (c) {
      state.constraint = { node: c.node, bud: c.bud ?? 0 };
      if (since !== undefined) state.constraintSince = since;
      sessionStorage.setItem(this._key(), JSON.stringify({ ...state.constraint, since: state.constraintSince }));
    } else {
      state.constraint = null;
      sessionStorage.removeItem(this._key());
    }
    this.show();
  }

  /** Takes back the constraint this tab remembers for the session just opened. */
  restore() {
    const { state } = this.session;
    const saved = sessionStorage.getItem(this._key());
    if (!saved) return;
    const c = JSON.parse(saved);
    state.constraint = { node: c.node, bud: c.bud };
    state.constraintSince = c.since;
  }

  /** Follows the edits meristemd accepted: a constraining dab, or a release. */
  edited(edits) {
    for (const e of edits) {
      if (e.op === 'add_markers' && e.constrain) this.set(e.constrain, this.session.viewer.maxNodeId());
      if (e.op === 'release') { this.set(null); $('#stalled').hidden = true; }
    }
  }

  /** A summary after steps: says why the last step grew nothing (summary.stalled), offering Release. */
  stalled(s) {
    const box = $('#stalled');
    if (!s.stalled) {
      if (s.steps_done > 0) box.hidden = true;
      return;
    }
    const { reason, node } = s.stalled;
    $('#stalled-reason').textContent = (STALL_TEXT[reason] || reason).replace('{node}', String(node));
    box.dataset.reason = reason;
    $('#stalled-release').hidden = reason !== 'constrained';
    box.hidden = false;
  }

  /** Shows the constraint, and highlights its subtree in the current snapshot. */
  show() {
    const { state, viewer } = this.session;
    const c = state.constraint;
    $('#constraint').hidden = !c;
    if (!c) {
      viewer.setHighlight('constraint', null);
      this._drawMarks(null);
      return;
    }
    $('#constraint-node').textContent = `${c.node}${c.bud ? ` (bud ${c.bud})` : ''}`;
    // The bud's node and everything grown since the constraint was set: only its
    // descendants can have grown since (node ids are issued in growth order).
    const since = state.constraintSince;
    const has = (id) => id === c.node || (since >= 0 && id > since);
    viewer.setHighlight('constraint', has, CONSTRAINED);
    this._drawMarks(has, c.node);
    // With the skeleton at hand, the lines run exactly from each internode's base to its tip.
    this.session.skeleton().then((skel) => {
      if (skel && this.session.state.constraint === c) this._drawMarks(has, c.node, skel);
    });
  }

  /**
   * The constrained internodes as lines (base to tip from the skeleton, else along the
   * axis the snapshot's bark gives), and a pin on the bud's node.
   */
  _drawMarks(has, node, skel = null) {
    const { viewer } = this.session;
    for (const o of this.marks.children) o.geometry.dispose();
    this.marks.clear();
    if (!has) { viewer.requestRender(); return; }
    const nodes = viewer.nodes();
    const seg = [];
    for (const [id, info] of nodes) {
      if (!has(id)) continue;
      const n = skel?.byId.get(id);
      if (n?.base && n.tip) { seg.push(...n.base, ...n.tip); continue; }
      const [cx, cy, cz] = info.center, [ax, ay, az] = info.axis;
      // The bark's height over the axis's rise, but no longer than the bark is tall and
      // a unit more: a flat internode's axis is the least sure.
      const rise = info.ymax - info.ymin;
      const half = Math.max(0.05, Math.min(rise / Math.max(0.2, Math.abs(ay)), rise + 1) / 2);
      seg.push(cx - ax * half, cy - ay * half, cz - az * half, cx + ax * half, cy + ay * half, cz + az * half);
    }
    const over = { depthTest: false, depthWrite: false, transparent: true };
    if (seg.length) {
      const g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.Float32BufferAttribute(seg, 3));
      const lines = new THREE.LineSegments(g, new THREE.LineBasicMaterial({ color: CONSTRAINED, ...over }));
      lines.renderOrder = 20;
      this.marks.add(lines);
    }
    const at = nodes.get(node);
    if (at) {
      const g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.Float32BufferAttribute(at.center, 3));
      const pin = new THREE.Points(g, new THREE.PointsMaterial({ color: CONSTRAINED, size: 14,
        sizeAttenuation: false, ...over }));
      pin.renderOrder = 21;
      this.marks.add(pin);
    }
    viewer.requestRender();
  }
}
