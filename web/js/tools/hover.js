// What the tools that act on one internode share: before anything is sent, the node under
// the pointer is highlighted (Palubicki et al. 2009, §5, after Power et al. 1999), picked by
// the _NODE_ID of the bark under the pointer, and a label beside the pointer names it and
// the subtree an edit there would take: its internodes and branch order (from the session's
// skeleton; the node alone while that is not at hand).
import { $ } from '../util.js';

const HOVER = 0xf0a030;

/** The live subtree of `id` in an indexed skeleton (Session.skeleton): its ids, root first. */
export function subtreeOf(skel, id) {
  const out = [], stack = [id];
  while (stack.length) {
    const i = stack.pop();
    out.push(i);
    for (const c of skel.children.get(i) || []) stack.push(c);
  }
  return out;
}

export class NodeTool {
  constructor({ viewer, session }) {
    this.viewer = viewer;
    this.session = session;
    this.hoverNode = null;   // the node highlighted under the pointer
    this.hoverInfo = null;   // what the label says: {node, internodes, order} (the tests read it)
  }

  /** Highlights the node under the pointer, and labels it. */
  hover(e) {
    const hit = this.viewer.pick(e.clientX, e.clientY);
    const node = hit ? hit.node : null;
    this._place(e);
    if (node === this.hoverNode) return;
    this.hoverNode = node;
    this.viewer.setHighlight('hover', node === null ? null : new Set([node]), HOVER);
    this._label(node);
  }

  leave() {
    this.hoverNode = null;
    this.hoverInfo = null;
    this.viewer.setHighlight('hover', null);
    $('#node-info').hidden = true;
  }

  _place(e) {
    const box = $('#node-info'), rect = box.parentElement.getBoundingClientRect();
    box.style.left = `${e.clientX - rect.left + 14}px`;
    box.style.top = `${e.clientY - rect.top + 14}px`;
  }

  /** The label for `node`: its id at once, the subtree when the skeleton is at hand. */
  async _label(node) {
    const box = $('#node-info');
    if (node === null) { this.hoverInfo = null; box.hidden = true; return; }
    this.hoverInfo = { node, internodes: null, order: null };
    box.textContent = `node ${node}`;
    box.hidden = false;
    const skel = await this.session.skeleton();
    if (this.hoverNode !== node || !skel || !skel.byId.has(node)) return;
    const ids = subtreeOf(skel, node);
    this.hoverInfo = { node, internodes: ids.length, order: skel.byId.get(node).order };
    box.textContent = `node ${node} · order ${this.hoverInfo.order} · ${ids.length} internode${ids.length === 1 ? '' : 's'} ${this.subtreeVerb}`;
    // The whole subtree the edit would take, under the node's own highlight.
    this.viewer.setHighlight('hover', new Set(ids), HOVER);
  }

  /** What happens to the subtree (the label's last words). */
  get subtreeVerb() { return 'in its subtree'; }
}
