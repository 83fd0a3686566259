// Picking, and reading a snapshot back: which internode is under the pointer (by the
// _NODE_ID of the bark's vertices, mesh.h, Picking), where each internode is and which
// way it points, and where the markers are.
import * as THREE from 'three';

/** GLTFLoader names a custom attribute by its glTF name in lower case. */
export const NODE_ID = '_node_id';

/** b = F_b of implicit junctions, per bark vertex (mesh.h, Junctions): 0 on tubes. */
export const RIDGE = '_ridge';

/** The per-vertex node ids of a snapshot geometry (a BufferAttribute), or undefined. */
export const nodeIdsOf = (geometry) => geometry.userData.nodeIds;

/**
 * The internode a triangle covers: the smallest id among its vertices (mesh.h,
 * Picking; the rule holds whatever order the decoder gave the corners in).
 */
export const triangleNode = (ids, a, b, c) => Math.round(Math.min(ids.getX(a), ids.getX(b), ids.getX(c)));

/**
 * The tree under a client position: {node, point} (the hit triangle's node, from
 * _NODE_ID), else the nearest bark vertex within `slop` px, else null.
 */
export function pick(viewer, clientX, clientY, slop = 8) {
  const { camera, raycaster } = viewer;
  // Twigs drawn as lines are picked on their prisms, hidden or not.
  const targets = [...(viewer.showBark ? viewer.barkMeshes : []),
    ...(viewer.showLeaves ? viewer.leafMeshes : [])];
  if (!targets.length) return null;
  raycaster.setFromCamera(viewer.ndc(clientX, clientY), camera);
  const hits = raycaster.intersectObjects(targets, false);
  for (const h of hits) {
    const ids = nodeIdsOf(h.object.geometry);
    if (ids && h.face) return { node: triangleNode(ids, h.face.a, h.face.b, h.face.c), point: h.point.clone() };
  }
  if (!viewer.bark || !viewer.showBark) return null;
  // Thin twigs are hard to hit: take the nearest bark vertex on screen.
  const rect = viewer.renderer.domElement.getBoundingClientRect();
  const v = new THREE.Vector3();
  let best = null, bestD = slop * slop, bestZ = Infinity;
  for (const mesh of viewer.barkMeshes) {
    const pos = mesh.geometry.attributes.position;
    const m = new THREE.Matrix4().multiplyMatrices(camera.projectionMatrix,
      camera.matrixWorldInverse).multiply(mesh.matrixWorld);
    for (let i = 0; i < pos.count; i++) {
      v.fromBufferAttribute(pos, i).applyMatrix4(m);
      if (v.z < -1 || v.z > 1) continue;
      const dx = rect.left + (v.x + 1) / 2 * rect.width - clientX;
      const dy = rect.top + (1 - v.y) / 2 * rect.height - clientY;
      const d = dx * dx + dy * dy;
      if (d < bestD || (d === bestD && v.z < bestZ)) { best = { mesh, i }; bestD = d; bestZ = v.z; }
    }
  }
  if (!best) return null;
  const point = new THREE.Vector3().fromBufferAttribute(best.mesh.geometry.attributes.position, best.i)
    .applyMatrix4(best.mesh.matrixWorld);
  return { node: Math.round(nodeIdsOf(best.mesh.geometry).getX(best.i)), point };
}

/**
 * Per-node centroid and principal axis (world space) from the bark vertices:
 * Map id → {center, axis, count, ymin, ymax}.
 */
export function nodeTable(barkMeshes) {
  const info = new Map();
  const v = new THREE.Vector3(), n = new THREE.Vector3();
  const acc = new Map();
  for (const mesh of barkMeshes) {
    const g = mesh.geometry, pos = g.attributes.position, nrm = g.attributes.normal;
    const ids = nodeIdsOf(g), mw = mesh.matrixWorld;
    for (let i = 0; i < pos.count; i++) {
      const id = Math.round(ids.getX(i));
      v.fromBufferAttribute(pos, i).applyMatrix4(mw);
      n.fromBufferAttribute(nrm, i).normalize();   // the node transform is translate + uniform scale
      let a = acc.get(id);
      if (!a) acc.set(id, (a = { k: 0, s: [0, 0, 0], nn: [0, 0, 0, 0, 0, 0], ymin: Infinity, ymax: -Infinity }));
      a.k++;
      a.s[0] += v.x; a.s[1] += v.y; a.s[2] += v.z;
      a.nn[0] += n.x * n.x; a.nn[1] += n.y * n.y; a.nn[2] += n.z * n.z;
      a.nn[3] += n.x * n.y; a.nn[4] += n.x * n.z; a.nn[5] += n.y * n.z;
      a.ymin = Math.min(a.ymin, v.y); a.ymax = Math.max(a.ymax, v.y);
    }
  }
  const b = new THREE.Matrix3(), d = new THREE.Vector3();
  for (const [id, a] of acc) {
    const c = a.s.map((x) => x / a.k);
    // Bark normals are perpendicular to the internode's axis: the axis is the
    // direction the normals vary least along, whatever the internode's thickness.
    const m = a.nn.map((x) => x / a.k);
    const tr = m[0] + m[1] + m[2];
    b.set(tr - m[0], -m[3], -m[4], -m[3], tr - m[1], -m[5], -m[4], -m[5], tr - m[2]);
    d.set(0.05, 1, 0.03);
    for (let k = 0; k < 40; k++) {
      d.applyMatrix3(b);
      if (d.lengthSq() < 1e-20) { d.set(0, 1, 0); break; }
      d.normalize();
    }
    if (d.y < 0) d.negate();
    info.set(id, { center: c, axis: [d.x, d.y, d.z], count: a.k, ymin: a.ymin, ymax: a.ymax });
  }
  return info;
}

/** Largest node id in the bark (-1 without bark). */
export function maxNodeId(barkMeshes) {
  let m = -1;
  for (const mesh of barkMeshes) {
    const ids = nodeIdsOf(mesh.geometry);
    for (let i = 0; i < ids.count; i++) m = Math.max(m, ids.getX(i));
  }
  return Math.round(m);
}

/** World positions of a marker cloud (THREE.Points, or null: none). */
export function markerPositions(markers) {
  if (!markers) return [];
  const pos = markers.geometry.attributes.position, mw = markers.matrixWorld;
  const v = new THREE.Vector3(), out = [];
  for (let i = 0; i < pos.count; i++) {
    v.fromBufferAttribute(pos, i).applyMatrix4(mw);
    out.push([v.x, v.y, v.z]);
  }
  return out;
}

/** World positions of the bark vertices with a ridge value above 0, as a flat xyz array. */
export function ridgePoints(barkMeshes) {
  const out = [];
  const v = new THREE.Vector3();
  for (const mesh of barkMeshes) {
    const b = mesh.geometry.userData.ridge, pos = mesh.geometry.attributes.position;
    if (!b) continue;
    for (let i = 0; i < b.count; i++) {
      if (!(b.getX(i) > 0)) continue;
      v.fromBufferAttribute(pos, i).applyMatrix4(mesh.matrixWorld);
      out.push(v.x, v.y, v.z);
    }
  }
  return out;
}
