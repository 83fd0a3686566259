// Pointer and keyboard routing: the tool buttons, the canvas's pointer events to the
// active tool (tools/index.js says what a tool answers), and keys to tools and panels.
import * as THREE from 'three';
import { $ } from './util.js';
import { toolApplies } from './models.js';

/** While a tool that has no `buttons` of its own is active. */
const TOOL_BUTTONS = { LEFT: null, MIDDLE: THREE.MOUSE.DOLLY, RIGHT: THREE.MOUSE.ROTATE };

export class Input {
  /**
   * @param tools the tools (instances), the first one active
   * @param keys {key: (keydown event) => void}: keys that are not a tool's
   * @param frame () => void: the Frame button (key F)
   */
  constructor({ viewer, session, tools, keys = {}, frame }) {
    this.viewer = viewer;
    this.session = session;
    this.tools = tools;
    this.tool = tools[0];
    this.keys = { f: () => $('#frame').click(), ...keys };
    this.down = null;   // the gesture under way: {tool, x, y, id, moved}
    this._addButtons();
    $('#frame').addEventListener('click', frame);
    this._routePointer(viewer.renderer.domElement);
    document.addEventListener('keydown', (e) => this._key(e));
  }

  /** Whether any tool's gesture is under way. */
  busy() { return this.tools.some((t) => t.busy?.()); }

  /** Makes tool `id` the active one (not one the session's model does not use). */
  setTool(id) {
    const tool = this.tools.find((t) => t.id === id);
    if (!tool || !toolApplies(tool, document.body.dataset.model || 'p09')) return;
    this.tool = tool;
    this.session.state.tool = id;
    for (const b of document.querySelectorAll('#tools [data-tool]')) b.classList.toggle('active', b.dataset.tool === id);
    this.viewer.controls.mouseButtons = tool.buttons || TOOL_BUTTONS;
    $('#view').dataset.tool = id;
    $('#hint').textContent = tool.hint;
    for (const t of this.tools) t.leave?.();
  }

  /** A button per tool, above the Frame button. */
  _addButtons() {
    const at = $('#tools hr');
    for (const t of this.tools) {
      const b = document.createElement('button');
      b.dataset.tool = t.id;
      b.className = t === this.tool ? 'tool active' : 'tool';
      b.title = t.title;
      const icon = document.createElement('span');
      icon.textContent = t.icon;
      b.append(icon, t.label);
      b.addEventListener('click', () => this.setTool(t.id));
      at.before(b);
    }
  }

  _routePointer(canvas) {
    canvas.addEventListener('pointerdown', (e) => {
      const tool = this.tool;
      if (e.button !== 0 || !this.session.state.id || !tool.begin) return;
      if (!tool.begin(e)) return;
      this.down = { tool, x: e.clientX, y: e.clientY, id: e.pointerId, moved: false };
      canvas.setPointerCapture(e.pointerId);
      e.preventDefault();
    });
    canvas.addEventListener('pointermove', (e) => {
      const d = this.down;
      if (d && e.pointerId === d.id) {
        if (Math.hypot(e.clientX - d.x, e.clientY - d.y) > 4) d.moved = true;
        d.tool.move?.(e);
        return;
      }
      if (e.buttons) return;
      this.tool.hover?.(e);
    });
    const finish = (e) => {
      const d = this.down;
      if (!d || e.pointerId !== d.id) return;
      this.down = null;
      d.tool.end?.(e, { moved: d.moved });
    };
    canvas.addEventListener('pointerup', finish);
    canvas.addEventListener('pointercancel', finish);
    canvas.addEventListener('pointerleave', () => { if (!this.down) for (const t of this.tools) t.leave?.(); });
  }

  _key(e) {
    if (e.target.closest('input, select, textarea') || e.ctrlKey || e.metaKey || e.altKey) return;
    const k = e.key.toLowerCase();
    const tool = this.tools.find((t) => t.key === k);
    if (tool) this.setTool(tool.id);
    else this.keys[k]?.(e);
  }
}
