// The Bend tool (Palubicki et al. 2009, §5, after Power et al. 1999): drag a branch
// to bend it; the picked node is highlighted, a line shows the handle, and a ghost of the
// branch shows the bend while the drag goes on. The turn is spread over the first
// SPREAD internodes of the branch's axis (the bend edit's `spread`): a curve, not an elbow.
import * as THREE from 'three';
import { NodeTool, subtreeOf } from './hover.js';
import { nodeIdsOf, triangleNode } from '../viewer/picking.js';

const BEND = 0x2f86d6;
/** Internodes a bend is spread over (meristemd's default too). */
export const SPREAD = 3;

export class BendTool extends NodeTool {
  id = 'bend';
  key = 'n';
  icon = '↷';
  label = 'Bend';
  title = 'Bend: drag a branch about its base (N)';
  hint = `Drag a branch to bend it, curving its first ${SPREAD} internodes · right-drag orbits`;

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
    this.ghostMat = new THREE.MeshLambertMaterial({ color: BEND, transparent: true, opacity: 0.55,
      depthWrite: false });
    this.ghost = null;       // the branch as the bend would leave it (a Mesh in world space)
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
    this.leave();   // the hover label and highlight give way to the drag's
    this.viewer.setHighlight('picked', new Set([hit.node]), BEND);
    const info = this.viewer.nodes().get(hit.node);
    const axis = info ? new THREE.Vector3(...info.axis) : start.clone().sub(pivot).normalize();
    const handle = pivot.clone().addScaledVector(axis, Math.max(reach, start.distanceTo(pivot)));
    this.drag = { node: hit.node, pivot, plane, start, end: start.clone(), handle, pointerId: e.pointerId };
    this._drawLine();
    const d = this.drag;
    this.session.skeleton().then((skel) => { if (this.drag === d) this._makeGhost(d, skel); });
    return true;
  }

  /**
   * The ghost: the bark of the subtree that turns (the picked node alone without a
   * skeleton), in world space, each vertex tagged with how many internodes of the
   * bent axis lie at or below its node (each turns it by a share of the angle).
   */
  _makeGhost(d, skel) {
    const ids = skel && skel.byId.has(d.node) ? new Set(subtreeOf(skel, d.node)) : new Set([d.node]);
    const chain = [d.node];
    while (skel && chain.length < SPREAD) {
      const last = skel.byId.get(chain[chain.length - 1]);
      const next = (skel.children.get(last.id) || []).map((c) => skel.byId.get(c)).find((c) => c.order === last.order);
      if (!next) break;
      chain.push(next.id);
    }
    // The pivots: each chain internode's base (the skeleton's); without it, an elbow
    // at the picked node's base as the snapshot shows it.
    let pivots = chain.map((id) => skel?.byId.get(id)?.base);
    if (pivots.some((b) => !b)) { chain.length = 1; pivots = [d.pivot.clone()]; }
    else pivots = pivots.map((b) => new THREE.Vector3(...b));
    // depth[id]: chain internodes at or below node id (1 … chain.length).
    const depth = new Map();
    const depthOf = (id) => {
      if (depth.has(id)) return depth.get(id);
      let k = 1;
      if (skel) {
        const path = [];
        for (let i = id; i !== null && i !== undefined && i !== d.node; i = skel.byId.get(i)?.parent) path.push(i);
        k = chain.filter((c) => c === d.node || path.includes(c)).length;
      }
      depth.set(id, k);
      return k;
    };
    const pos = [], tag = [], index = [];
    const v = new THREE.Vector3();
    for (const mesh of this.viewer.barkMeshes) {
      const g = mesh.geometry, nid = nodeIdsOf(g), p = g.attributes.position;
      if (!nid) continue;
      const remap = new Map();
      const n = g.index ? g.index.count : p.count;
      for (let t = 0; t < n; t += 3) {
        const c = [0, 1, 2].map((k) => (g.index ? g.index.getX(t + k) : t + k));
        const node = triangleNode(nid, c[0], c[1], c[2]);
        if (!ids.has(node)) continue;
        for (const i of c) {
          if (!remap.has(i)) {
            remap.set(i, pos.length / 3);
            v.fromBufferAttribute(p, i).applyMatrix4(mesh.matrixWorld);
            pos.push(v.x, v.y, v.z);
            tag.push(depthOf(Math.round(nid.getX(i))));
          }
          index.push(remap.get(i));
        }
      }
    }
    if (!index.length) return;
    const geo = new THREE.BufferGeometry();
    geo.setAttribute('position', new THREE.Float32BufferAttribute(pos.slice(), 3));
    geo.setIndex(index);
    this.ghost = new THREE.Mesh(geo, this.ghostMat);
    this.ghost.renderOrder = 9;
    this.ghost.userData = { rest: Float32Array.from(pos), tag, pivots, chain };
    this.viewer.preview.add(this.ghost);
    this._drawGhost();
  }

  /** Turns the ghost's vertices as mer_scene_bend_spread would turn the branch. */
  _drawGhost() {
    const gh = this.ghost;
    if (!gh || !this.drag) return;
    const rot = this.rotation();
    const { rest, tag, pivots } = gh.userData;
    const out = gh.geometry.attributes.position;
    const axis = rot ? new THREE.Vector3(...rot.axis) : new THREE.Vector3(0, 1, 0);
    const share = rot ? THREE.MathUtils.degToRad(rot.angle) / pivots.length : 0;
    const q = new THREE.Quaternion().setFromAxisAngle(axis, share);
    const v = new THREE.Vector3();
    for (let i = 0; i < tag.length; i++) {
      v.set(rest[3 * i], rest[3 * i + 1], rest[3 * i + 2]);
      // Highest share first about the pivots where they stand before any turn.
      for (let j = Math.min(tag[i], pivots.length) - 1; j >= 0; j--) v.sub(pivots[j]).applyQuaternion(q).add(pivots[j]);
      out.setXYZ(i, v.x, v.y, v.z);
    }
    out.needsUpdate = true;
    gh.geometry.computeVertexNormals();
    gh.geometry.computeBoundingSphere();
    this.viewer.requestRender();
  }

  _dropGhost() {
    if (!this.ghost) return;
    this.viewer.preview.remove(this.ghost);
    this.ghost.geometry.dispose();
    this.ghost = null;
    this.viewer.requestRender();
  }

  /** A third of the tree's height, at least 2 (10 before the tree has one). */
  _reach() { return Math.max(2, (this.session.state.summary?.height || 10) * 0.3); }

  move(e) {
    const d = this.drag;
    if (!d || e.pointerId !== d.pointerId) return;
    const p = new THREE.Vector3();
    if (this.viewer.ray(e.clientX, e.clientY).intersectPlane(d.plane, p)) d.end = p;
    this._drawLine();
    this._drawGhost();
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
      const edit = { op: 'bend', node: d.node, axis: rot.axis, angle: rot.angle, spread: SPREAD };
      this.lastBend = edit;
      return await this.session.send([edit]);
    } finally {
      this._dropGhost();
      this.viewer.setHighlight('picked', null);
    }
  }
}
