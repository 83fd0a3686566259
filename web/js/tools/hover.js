// What the tools that act on one internode share: the node under the pointer is
// highlighted before anything is sent (Palubicki et al. 2009, §5, after Power et al.
// 1999), picked by the _NODE_ID of the bark under the pointer.

const HOVER = 0xf0a030;

export class NodeTool {
  constructor({ viewer, session }) {
    this.viewer = viewer;
    this.session = session;
    this.hoverNode = null;   // the node highlighted under the pointer
  }

  /** Highlights the node under the pointer. */
  hover(e) {
    const hit = this.viewer.pick(e.clientX, e.clientY);
    const node = hit ? hit.node : null;
    if (node === this.hoverNode) return;
    this.hoverNode = node;
    this.viewer.setHighlight('hover', node === null ? null : new Set([node]), HOVER);
  }

  leave() { this.hoverNode = null; this.viewer.setHighlight('hover', null); }
}
