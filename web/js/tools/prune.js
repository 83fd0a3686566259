// The Prune tool (Palubicki et al. 2009, §5): a click on a branch cuts it and
// everything above; hovering shows the node and the size of what would go, and the
// picked node is highlighted before the edit is sent.
import { NodeTool } from './hover.js';

const PICKED = 0xd23c2c;

const nextFrame = () => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r)));

export class PruneTool extends NodeTool {
  id = 'prune';
  key = 'p';
  icon = '✂';
  label = 'Prune';
  title = 'Prune: click a branch to cut it (P)';
  hint = 'Click a branch to cut it and everything above · right-drag orbits';

  get subtreeVerb() { return 'would go'; }

  /** The gesture is a click: taken here, acted on in end. */
  begin() { return true; }

  /** A click is under way until its prune is sent (the highlight is drawn first). */
  busy() { return this.clicking > 0; }

  clicking = 0;

  end(e, { moved }) {
    if (!moved && e.type === 'pointerup') this.click(e);
  }

  /** Click: highlight the node, then send the prune. */
  async click(e) {
    const hit = this.viewer.pick(e.clientX, e.clientY);
    if (!hit) return null;
    this.clicking++;
    try {
      this.leave();
      this.viewer.setHighlight('picked', new Set([hit.node]), PICKED);
      this.viewer.render();
      await nextFrame();
      return await this.session.send([{ op: 'prune', node: hit.node }]);
    } finally {
      this.clicking--;
      this.viewer.setHighlight('picked', null);
    }
  }
}
