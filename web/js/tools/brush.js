// The Brush tool: the procedural brush of Palubicki et al. 2009, §5. A pointer stroke
// lays marker points along its path in a working plane parallel to the screen, through
// the point where the stroke began (the tree under the pointer, else the tree's
// centre). Pen pressure (or the pressure slider, for a mouse) sets the dab's spread and
// count on the server. Constraining growth to a branch is deliberate: a stroke that
// starts on the tree with Shift held (or with "grow only from here" ticked) constrains
// growth to that bud's descendants (P09 §5); any other stroke only lays markers. Dabs
// are batched: one request per BATCH_MS, not one per pointer event.
import * as THREE from 'three';
import { $, round3 } from '../util.js';
import { CONSTRAINED } from '../constraint.js';
import { symmetricCopies, symmetrySettings } from './symmetry.js';

export const BATCH_MS = 250;
const MAX_PREVIEW = 4096;

export class BrushTool {
  id = 'brush';
  key = 'b';
  icon = '✎';
  label = 'Brush';
  title = 'Brush: lay markers of free space (B)';
  models = ['p09', 'runions'];   // the models that grow towards markers
  hint = 'Drag: lay markers · Shift+drag from a branch: grow only from it · right-drag orbits';

  constructor({ viewer, session }) {
    this.viewer = viewer;
    this.session = session;
    this.stroke = null;
    this.requests = 0;      // batches sent (the tests read it)
    this.dabsSent = 0;
    this.pointerEvents = 0; // pointer moves seen during strokes

    const sphere = new THREE.SphereGeometry(1, 14, 10);
    this.dabMesh = new THREE.InstancedMesh(sphere, new THREE.MeshBasicMaterial({
      color: 0xffffff, transparent: true, opacity: 0.28, depthWrite: false }), MAX_PREVIEW);
    this.dabMesh.count = 0;
    this.dabMesh.renderOrder = 5;
    this.dabMesh.frustumCulled = false;
    viewer.preview.add(this.dabMesh);
  }

  /** The brush panel's settings: {radius, count, pressure, constrain, symmetry}. */
  settings() {
    return {
      radius: Number($('#radius').value), count: Number($('#count').value),
      pressure: Number($('#pressure').value), constrain: $('#constrain').checked,
      symmetry: symmetrySettings(this.viewer),
    };
  }

  /** The centre of the tree's bounds (where a stroke off the tree lays its plane). */
  _centre() {
    const b = this.session.state.summary?.bounds;
    if (!b) return [0, 5, 0];
    return [0, 1, 2].map((k) => round3((b.min[k] + b.max[k]) / 2));
  }

  busy() { return Boolean(this.stroke); }

  /** A new snapshot shows the real markers: the drawn dabs go, unless a stroke is on. */
  loaded() { if (!this.stroke) this.clearPreview(); }

  /** Clears the drawn dabs. */
  clearPreview() {
    this.dabMesh.count = 0;
    this.dabMesh.instanceMatrix.needsUpdate = true;
    this.viewer.requestRender();
  }

  _drawDab(center, spread, sym) {
    const copies = symmetricCopies(center, sym);
    const m = new THREE.Matrix4(), col = new THREE.Color();
    copies.forEach((p, k) => {
      if (this.dabMesh.count >= MAX_PREVIEW) return;
      m.makeScale(spread, spread, spread).setPosition(p);
      const i = this.dabMesh.count++;
      this.dabMesh.setMatrixAt(i, m);
      this.dabMesh.setColorAt(i, col.set(k === 0 ? 0xe0702a : 0x2f7fd0));
    });
    this.dabMesh.instanceMatrix.needsUpdate = true;
    if (this.dabMesh.instanceColor) this.dabMesh.instanceColor.needsUpdate = true;
    this.viewer.requestRender();
  }

  _pressure(e) {
    const s = this.settings();
    // A mouse reports 0.5 while a button is down: use the slider. A pen (or touch with
    // force) reports its own pressure.
    if (e.pointerType === 'mouse' || !(e.pressure > 0)) return s.pressure;
    return Math.min(1, Math.max(0.001, e.pressure));
  }

  /** Starts a stroke at a pointerdown; returns true when it took the event. */
  begin(e) {
    const s = this.settings();
    const hit = this.viewer.pick(e.clientX, e.clientY);
    const anchor = hit ? hit.point.clone() : new THREE.Vector3(...this._centre());
    const normal = new THREE.Vector3();
    this.viewer.camera.getWorldDirection(normal);
    const plane = new THREE.Plane().setFromNormalAndCoplanarPoint(normal, anchor);
    this.stroke = {
      plane, last: null, queue: [], timer: null, pending: Promise.resolve(),
      constrain: hit && (s.constrain || e.shiftKey) ? { node: hit.node, bud: 0 } : null,
      startNode: hit ? hit.node : null, anchor, dabs: 0, pointerId: e.pointerId,
    };
    this.stroke.timer = setInterval(() => this._flush(), BATCH_MS);
    const { constrain } = this.stroke;
    if (constrain) this.viewer.setHighlight('picked', new Set([constrain.node]), CONSTRAINED);
    this._addAt(e, true);
    return true;
  }

  move(e) {
    if (!this.stroke || e.pointerId !== this.stroke.pointerId) return;
    const events = e.getCoalescedEvents ? e.getCoalescedEvents() : [];
    for (const ev of events.length ? events : [e]) { this.pointerEvents++; this._addAt(ev, false); }
  }

  async end(e) {
    const st = this.stroke;
    if (!st || (e && e.pointerId !== st.pointerId)) return;
    if (e) this._addAt(e, false);
    clearInterval(st.timer);
    this.stroke = null;
    this._flush(st);
    await st.pending;
    this.viewer.setHighlight('picked', null);
    this.session.refresh();
  }

  _addAt(e, first) {
    const st = this.stroke;
    const ray = this.viewer.ray(e.clientX, e.clientY);
    const p = new THREE.Vector3();
    if (!ray.intersectPlane(st.plane, p)) return;
    const s = this.settings();
    const pressure = this._pressure(e);
    const spacing = Math.max(0.05, s.radius * 0.6);
    const dab = (c) => {
      const d = { op: 'add_markers', center: [c.x, c.y, c.z].map(round3),
        radius: s.radius, pressure: Math.round(pressure * 1000) / 1000, count: s.count };
      if (s.symmetry) d.symmetry = s.symmetry;
      if (st.dabs === 0 && st.constrain) d.constrain = st.constrain;
      st.dabs++;
      st.queue.push(d);
      this._drawDab(c, s.radius * (0.1 + 0.9 * pressure), s.symmetry);
    };
    if (first || !st.last) { dab(p); st.last = p; return; }
    const dist = p.distanceTo(st.last);
    if (dist < spacing) return;
    // Lay dabs evenly along a fast move, so a quick flick still draws a line.
    const n = Math.min(32, Math.floor(dist / spacing));
    for (let k = 1; k <= n; k++) dab(st.last.clone().lerp(p, k / n));
    st.last = p;
  }

  _flush(st = this.stroke) {
    if (!st || !st.queue.length) return;
    const batch = st.queue.splice(0);
    this.requests++;
    this.dabsSent += batch.length;
    st.pending = st.pending.then(() => this.session.send(batch)).catch(() => {});
  }
}
