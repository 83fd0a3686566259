// The Bend tool (Palubicki et al. 2009, §5, after Power et al. 1999): drag a branch
// to turn it about its base; the picked node is highlighted and a line shows the bend
// while the drag goes on.
import * as THREE from 'three';
import { NodeTool } from './hover.js';

const BEND = 0x2f86d6;

export class BendTool extends NodeTool {
  id = 'bend';
  key = 'n';
  icon = '↷';
  label = 'Bend';
  title = 'Bend: drag a branch about its base (N)';
  hint = 'Drag a branch to bend it about its base · right-drag orbits';

  constructor(ctx) {
    super(ctx);
    const { viewer } = ctx;
    this.drag = null;
    const mat = new THREE.LineBasicMaterial({ color: BEND, depthTest: false, transparent: true });
    this.line = new THREE.Line(new THREE.BufferGeometry().setFromPoints(
      [new THREE.Vector3(), new THREE.Vector3(), new THREE.Vector3()]), mat);
    this.line.visible = false;
    this.line.renderOrder = 10;
    viewer.preview.add(this.line);
    this.lastBend = null;
  }

  hover(e) { if (!this.drag) super.hover(e); }

  busy() { return Boolean(this.drag); }

  /** The base of the node: the end of its axis nearer the root. */
  _pivot(node) {
    const info = this.viewer.nodes().get(node);
    if (!info) return null;
    const c = new THREE.Vector3(...info.center), a = new THREE.Vector3(...info.axis);
    const half = Math.max(0, (info.ymax - info.ymin) / Math.max(0.2, Math.abs(a.y))) / 2;
    const root = this.viewer.nodes().get(0);
    const r = root ? new THREE.Vector3(...root.center) : new THREE.Vector3();
    const e1 = c.clone().addScaledVector(a, -Math.min(half, 2));
    const e2 = c.clone().addScaledVector(a, Math.min(half, 2));
    return e1.distanceTo(r) <= e2.distanceTo(r) ? e1 : e2;
  }

  /**
   * Starts a drag on a branch. The drag moves a handle on the branch's axis, at least
   * `reach` from the node's base (so a short drag is a small bend, not a swing about a
   * point next to the pivot); the bend takes the handle to where the drag puts it.
   */
  begin(e, reach = this._reach()) {
    const hit = this.viewer.pick(e.clientX, e.clientY);
    if (!hit) return false;
    const pivot = this._pivot(hit.node) || hit.point.clone();
    const normal = new THREE.Vector3();
    this.viewer.camera.getWorldDirection(normal);
    const plane = new THREE.Plane().setFromNormalAndCoplanarPoint(normal, pivot);
    const start = new THREE.Vector3();
    if (!this.viewer.ray(e.clientX, e.clientY).intersectPlane(plane, start)) return false;
    this.viewer.setHighlight('hover', null);
    this.viewer.setHighlight('picked', new Set([hit.node]), BEND);
    const info = this.viewer.nodes().get(hit.node);
    const axis = info ? new THREE.Vector3(...info.axis) : start.clone().sub(pivot).normalize();
    const handle = pivot.clone().addScaledVector(axis, Math.max(reach, start.distanceTo(pivot)));
    this.drag = { node: hit.node, pivot, plane, start, end: start.clone(), handle, pointerId: e.pointerId };
    this._drawLine();
    return true;
  }

  /** A third of the tree's height, at least 2 (10 before the tree has one). */
  _reach() { return Math.max(2, (this.session.state.summary?.height || 10) * 0.3); }

  move(e) {
    const d = this.drag;
    if (!d || e.pointerId !== d.pointerId) return;
    const p = new THREE.Vector3();
    if (this.viewer.ray(e.clientX, e.clientY).intersectPlane(d.plane, p)) d.end = p;
    this._drawLine();
  }

  _drawLine() {
    const d = this.drag;
    const pos = this.line.geometry.attributes.position;
    const moved = this._moved();
    pos.setXYZ(0, d.handle.x, d.handle.y, d.handle.z);
    pos.setXYZ(1, d.pivot.x, d.pivot.y, d.pivot.z);
    pos.setXYZ(2, moved.x, moved.y, moved.z);
    pos.needsUpdate = true;
    this.line.geometry.computeBoundingSphere();
    this.line.visible = true;
    this.viewer.requestRender();
  }

  /** Where the drag has put the handle. */
  _moved() { const d = this.drag; return d.handle.clone().add(d.end).sub(d.start); }

  /** The rotation about the base taking the handle to where the drag put it: {axis, angle°} or null. */
  rotation() {
    const d = this.drag;
    const a = d.handle.clone().sub(d.pivot), b = this._moved().sub(d.pivot);
    if (a.lengthSq() < 1e-8 || b.lengthSq() < 1e-8) return null;
    const axis = a.clone().cross(b);
    if (axis.lengthSq() < 1e-12) return null;
    axis.normalize();
    const angle = THREE.MathUtils.radToDeg(a.angleTo(b));
    if (angle < 0.5) return null;
    return { axis: [axis.x, axis.y, axis.z].map((x) => Math.round(x * 1e5) / 1e5),
      angle: Math.round(angle * 100) / 100 };
  }

  async end(e) {
    const d = this.drag;
    if (!d || (e && e.pointerId !== d.pointerId)) return null;
    if (e) this.move(e);
    const rot = this.rotation();
    this.drag = null;
    this.line.visible = false;
    try {
      if (!rot) return null;
      const edit = { op: 'bend', node: d.node, axis: rot.axis, angle: rot.angle };
      this.lastBend = edit;
      return await this.session.send([edit]);
    } finally {
      this.viewer.setHighlight('picked', null);
    }
  }
}
