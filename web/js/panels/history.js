// The History panel: undo and redo (Ctrl+Z, Ctrl+Shift+Z and buttons), the list of the
// session's revisions (a click goes back to one), and a time slider that scrubs through
// them, drawing each past tree from snapshot.glb?revision=N (P09 Fig. 11's growth
// animation, seen live; ▶ plays it). Going back is a revert edit: a new revision with
// the old tree, so nothing is ever lost and redo is a revert to the later revision.
import * as api from '../api.js';
import { $ } from '../util.js';
import { viewOptions } from './view.js';

/** One line saying what a revision's edits did. */
function describe(edits) {
  if (!edits.length) return 'created';
  const parts = edits.map((e) => {
    switch (e.op) {
      case 'step': return `step ×${e.count ?? 1}`;
      case 'add_markers': return e.points ? `${e.points.length} markers` : 'brush';
      case 'prune': return `prune ${e.node}`;
      case 'bend': return `bend ${e.node}`;
      case 'revert': return `back to r${e.revision}`;
      default: return e.op.replace(/_/g, ' ');
    }
  });
  // A stroke is many dabs: say how many once.
  const counts = new Map();
  for (const p of parts) counts.set(p, (counts.get(p) || 0) + 1);
  return [...counts].map(([p, n]) => (n > 1 ? `${p} ×${n}` : p)).join(', ');
}

export class HistoryPanel {
  id = 'history';

  constructor({ viewer, session }) {
    this.viewer = viewer;
    this.session = session;
    this.revisions = [];      // oldest first, as GET .../revisions lists them
    this.redo = [];           // revisions an undo left, latest last
    this.viewing = null;      // the past revision the slider shows, or null for the current
    this.wanted = null;       // the revision the slider asks for while one loads
    this.fetching = null;
    $('#undo').addEventListener('click', () => this.undo());
    $('#redo').addEventListener('click', () => this.redoLast());
    $('#history-slider').addEventListener('input', (e) => this.scrub(Number(e.target.value)));
    $('#history-restore').addEventListener('click', () => this.goTo(this.viewing));
    $('#history-latest').addEventListener('click', () => this.backToLatest());
    $('#history-play').addEventListener('click', () => this.play());
    $('#history-list').addEventListener('click', (e) => {
      const li = e.target.closest('li[data-revision]');
      if (li) this.goTo(Number(li.dataset.revision));
    });
    document.addEventListener('keydown', (e) => {
      if (!(e.ctrlKey || e.metaKey) || e.altKey || e.key.toLowerCase() !== 'z') return;
      if (e.target.closest('input[type=text], input[type=number], textarea, select')) return;
      e.preventDefault();
      if (e.shiftKey) this.redoLast(); else this.undo();
    });
  }

  /** A summary arrived: fetch the revisions after the ones listed. */
  show(s) {
    if (s.id && s.id !== this.sessionId) {
      this.sessionId = s.id;
      this.revisions = [];
      this.redo = [];
      this.viewing = null;
    }
    this.latest = s.revision;
    this.sync();
  }

  async sync() {
    const id = this.session.state.id;
    if (!id || this.syncing) { this.syncAgain = true; return; }
    this.syncing = true;
    try {
      do {
        this.syncAgain = false;
        for (;;) {
          const last = this.revisions.at(-1);
          const page = await api.revisions(id, last ? last.revision : null);
          if (id !== this.session.state.id) return;
          this.revisions.push(...page.revisions);
          if (page.next_after === null) break;
        }
      } while (this.syncAgain);
      this.render();
    } catch (e) {
      this.session.problem(e);
    } finally {
      this.syncing = false;
    }
  }

  /** The revision that first made revision r's tree (a lone revert makes none). */
  tree(r) {
    const e = this.revisions[r]?.edits;
    return e && e.length === 1 && e[0].op === 'revert' && e[0].revision < r ? this.tree(e[0].revision) : r;
  }

  render() {
    const list = $('#history-list');
    const current = this.revisions.length - 1, tree = this.tree(current);
    const items = this.revisions.map((r) => {
      const li = document.createElement('li');
      li.dataset.revision = String(r.revision);
      li.classList.toggle('current', r.revision === tree);
      li.classList.toggle('viewing', r.revision === this.viewing);
      li.title = `go back to revision ${r.revision} (as a new revision)`;
      li.innerHTML = '<b></b> <span></span> <small></small>';
      li.querySelector('b').textContent = `r${r.revision}`;
      li.querySelector('span').textContent = describe(r.edits);
      li.querySelector('small').textContent = r.step === null ? '' : `step ${r.step} · ${r.internodes} internodes`;
      return li;
    });
    list.replaceChildren(...items);
    list.scrollTop = list.scrollHeight;   // the list only: the side panel stays where it is
    const slider = $('#history-slider');
    slider.max = String(Math.max(0, current));
    if (this.viewing === null) slider.value = String(current);
    $('#history-at').textContent = this.viewing === null ? `r${current} (latest)` : `r${this.viewing}`;
    $('#undo').disabled = tree <= 0;
    $('#redo').disabled = this.redo.length === 0;
    $('#history-viewing').hidden = this.viewing === null;
  }

  /** Ctrl+Z: back to the tree before the current one. */
  undo() {
    const current = this.revisions.length - 1, tree = this.tree(current);
    if (tree <= 0) return null;
    this.redo.push(current);
    return this.revert(tree - 1, { keepRedo: true });
  }

  /** Ctrl+Shift+Z: forward to the tree the last undo left. */
  redoLast() {
    const to = this.redo.pop();
    return to === undefined ? null : this.revert(to, { keepRedo: true });
  }

  /** A click in the list or "Restore this": revision r's tree becomes the current one. */
  goTo(r) {
    if (r === null || r === undefined) return null;
    this.redo = [];
    return this.revert(r, { keepRedo: false });
  }

  async revert(r, { keepRedo }) {
    this.viewing = null;
    const redo = this.redo.slice();
    const s = await this.session.send([{ op: 'revert', revision: r }]);
    if (keepRedo) this.redo = redo;
    await this.sync();
    return s;
  }

  /** Any edit shows the current tree again; one that is not a revert makes a new
   * future, with nothing to redo. */
  edited(edits) {
    this.viewing = null;
    this.wanted = null;
    if (!edits.some((e) => e.op === 'revert')) this.redo = [];
  }

  /** The slider: draws revision r without changing the session. */
  async scrub(r) {
    const current = this.revisions.length - 1;
    if (r >= current) { this.backToLatest(); return; }
    this.viewing = r;
    this.wanted = r;
    this.render();
    if (this.fetching) return;
    this.fetching = (async () => {
      while (this.wanted !== null) {
        const want = this.wanted;
        this.wanted = null;
        try {
          await this.viewer.load(api.snapshotUrl(this.session.state.id,
            { ...viewOptions(), compact: true, revision: want }));
        } catch (e) {
          this.session.problem(e);
        }
      }
    })().finally(() => { this.fetching = null; });
    await this.fetching;
  }

  async backToLatest() {
    this.viewing = null;
    this.wanted = null;
    this.render();
    await this.fetching;
    await this.session.refresh();
  }

  /** ▶: every revision from the first to the latest, one after another. */
  async play() {
    if (this.playing) { this.playing = false; return; }
    this.playing = true;
    $('#history-play').textContent = '❚❚';
    for (let r = 0; r < this.revisions.length - 1 && this.playing; r++) {
      $('#history-slider').value = String(r);
      await this.scrub(r);
    }
    this.playing = false;
    $('#history-play').textContent = '▶';
    await this.backToLatest();
  }
}
