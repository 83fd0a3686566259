// The growth constraint (Palubicki et al. 2009, §5, Fig. 15b): a brush stroke that
// starts on the tree confines growth to that bud's descendants until released. The page
// shows it, highlights the subtree, and remembers it per session across reloads.
import { $ } from './util.js';

/** Fig. 15b shows the constrained branch in purple. */
export const CONSTRAINED = 0xa040c8;

export class GrowthConstraint {
  /** @param session the Session: its viewer, state (constraint, constraintSince) and send */
  constructor(session) {
    this.session = session;
    $('#release').addEventListener('click', () => session.send([{ op: 'release' }]));
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
      if (e.op === 'release') this.set(null);
    }
  }

  /** Shows the constraint, and highlights its subtree in the current snapshot. */
  show() {
    const { state, viewer } = this.session;
    const c = state.constraint;
    $('#constraint').hidden = !c;
    if (!c) { viewer.setHighlight('constraint', null); return; }
    $('#constraint-node').textContent = `${c.node}${c.bud ? ` (bud ${c.bud})` : ''}`;
    // The bud's node and everything grown since the constraint was set: only its
    // descendants can have grown since (node ids are issued in growth order).
    const since = state.constraintSince;
    viewer.setHighlight('constraint', (id) => id === c.node || (since >= 0 && id > since), CONSTRAINED);
  }
}
