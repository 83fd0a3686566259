// Highlights: named sets of internodes drawn in a colour over their bark triangles (the
// node under the pointer, the picked one, the constrained subtree).
import * as THREE from 'three';
import { nodeIdsOf, triangleNode } from './picking.js';

export class Highlighter {
  /**
   * @param viewer the Viewer: its barkMeshes, bark, and overlay (the group the
   *   highlights are drawn in, beside the bark)
   */
  constructor(viewer) {
    this.viewer = viewer;
    this.highlights = new Map();   // name → {ids: Set|function(id), color}
    this.materials = new Map();    // colour → material
  }

  /** Sets (ids: a Set or a predicate on node ids) or clears (ids null) highlight `name`. */
  set(name, ids, color) {
    if (!ids) this.highlights.delete(name); else this.highlights.set(name, { ids, color });
    this.apply();
  }

  /** Rebuilds the overlay for the current bark (after a set, or a new snapshot). */
  apply() {
    const { overlay, bark, barkMeshes } = this.viewer;
    // An overlay borrows its bark's attributes (which twig lines share too): free only
    // its own index, or three.js would drop the bark's buffers and upload them again.
    for (const o of overlay.children) {
      o.geometry.deleteAttribute('position');
      o.geometry.deleteAttribute('normal');
      o.geometry.dispose();
    }
    overlay.clear();
    if (!bark || !this.highlights.size) return;
    // The chunks share their parent node (the quantization grid) and have no transform
    // of their own, so the overlay sits beside them with the first one's.
    overlay.position.copy(bark.position);
    overlay.quaternion.copy(bark.quaternion);
    overlay.scale.copy(bark.scale);
    let order = 0;
    for (const { ids: want, color } of this.highlights.values()) {
      const has = typeof want === 'function' ? want : (id) => want.has(id);
      const mat = this._material(color, order);
      for (const mesh of barkMeshes) {
        const index = triangles(mesh.geometry, has);
        if (!index.length) continue;
        const hg = new THREE.BufferGeometry();
        hg.setAttribute('position', mesh.geometry.attributes.position);
        hg.setAttribute('normal', mesh.geometry.attributes.normal);
        hg.setIndex(index);
        const m = new THREE.Mesh(hg, mat);
        m.renderOrder = 2 + order;
        overlay.add(m);
      }
      order++;
    }
  }

  _material(color, order) {
    let mat = this.materials.get(color);
    if (!mat) {
      mat = new THREE.MeshLambertMaterial({ color, emissive: color, emissiveIntensity: 0.35,
        polygonOffset: true, polygonOffsetFactor: -1 - order, polygonOffsetUnits: -4 });
      this.materials.set(color, mat);
    }
    return mat;
  }
}

/** The corners of the triangles of `g` whose node satisfies `has`, as an index list. */
function triangles(g, has) {
  const ids = nodeIdsOf(g), index = g.index;
  const out = [];
  const n = index ? index.count : g.attributes.position.count;
  for (let t = 0; t < n; t += 3) {
    const a = index ? index.getX(t) : t, b = index ? index.getX(t + 1) : t + 1,
      c = index ? index.getX(t + 2) : t + 2;
    if (has(triangleNode(ids, a, b, c))) out.push(a, b, c);
  }
  return out;
}
