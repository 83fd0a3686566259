// The fork close-up: which fork to look at, and from where. Implicit junctions
// (Galbraith, Mündermann & Wyvill 2004 §3; mesh.h, Junctions) turn the forks of thick
// branches into blended patches with the branch bark ridge in the crotch; this is
// where the page looks to show one.
import * as THREE from 'three';

/** A lateral the mesher puts in a patch is at least this × its parent's diameter,
 * and the parent at least JUNCTION_FRACTION × the tree's thickest (lib/mesh/joints.c). */
const LATERAL_RATIO = 0.25;
const JUNCTION_FRACTION = 0.2;
/** The close-up frames this many parent diameters (and lateral diameters) about the
 * fork: the patch, and a little of the shafts beyond its cuts. */
const FRAME_PARENT = 1.2;
const FRAME_LATERAL = 1.0;

const v3 = (a) => new THREE.Vector3(a[0], a[1], a[2]);

/**
 * The forks of a skeleton (GET …/skeleton nodes): every living lateral at least a
 * quarter as thick as its parent, with its parent and the parent's continuation.
 * Each is {lateral, parent, child, at (the fork point), diameter (the parent's)}.
 */
export function forks(nodes) {
  const byId = new Map(nodes.map((n) => [n.id, n]));
  const main = new Map();   // parent id → the child that continues its axis
  for (const n of nodes) {
    const p = n.parent === null ? null : byId.get(n.parent);
    if (p && n.alive && n.order === p.order) main.set(p.id, n);
  }
  const out = [];
  for (const n of nodes) {
    const p = n.parent === null ? null : byId.get(n.parent);
    if (!p || !n.alive || n.order <= p.order || n.diameter < LATERAL_RATIO * p.diameter) continue;
    out.push({ lateral: n, parent: p, child: main.get(p.id) || null, at: n.base, diameter: p.diameter });
  }
  return out;
}

/** Whether any of `points` (a flat xyz array) lies within `r` of `at`. */
function anyNear(points, at, r) {
  const r2 = r * r;
  for (let i = 0; i < points.length; i += 3) {
    const dx = points[i] - at[0], dy = points[i + 1] - at[1], dz = points[i + 2] - at[2];
    if (dx * dx + dy * dy + dz * dz <= r2) return true;
  }
  return false;
}

/**
 * The fork to look at. `patched`: the ids of the internodes whose tip is a fork the
 * mesher made a patch of (a Set; the GLB's tree node extras.junction_forks), so that
 * only those count; without it, `ridge`: the drawn bark's points with a ridge value
 * (implicit junctions), which tell patched forks only roughly (a fork whose lateral's
 * first internode is short counts by the patch at that internode's tip); `near`: a
 * world point (under the pointer): the fork closest to it. Otherwise the thickest of
 * the forks the mesher would consider (null when the tree has none).
 */
export function chooseFork(nodes, { patched = null, ridge = null, near = null } = {}) {
  let all = forks(nodes);
  if (!all.length) return null;
  if (near) {
    const p = v3(near);
    return all.reduce((a, b) => (v3(b.at).distanceToSquared(p) < v3(a.at).distanceToSquared(p) ? b : a));
  }
  // A patch's ridge values lie about its crotch: within the parent's radius and a
  // lateral's diameter or so of the fork point (the next fork may be an internode away).
  const meshed = patched?.size ? all.filter((f) => patched.has(f.parent.id))
    : ridge?.length ? all.filter((f) => anyNear(ridge, f.at, 0.5 * f.diameter + f.lateral.diameter)) : [];
  if (meshed.length) all = meshed;
  else {
    const thickest = nodes.reduce((m, n) => (n.alive && n.diameter > m ? n.diameter : m), 0);
    const thick = all.filter((f) => f.diameter >= JUNCTION_FRACTION * thickest);
    if (thick.length) all = thick;
  }
  // Thickest parent first; among equals the thicker lateral (the plainer fork).
  return all.reduce((a, b) => (b.diameter > a.diameter ||
    (b.diameter === a.diameter && b.lateral.diameter > a.lateral.diameter) ? b : a));
}

/**
 * Where to look at `fork` from: {center, radius, dir}. The camera looks at the fork
 * point across the plane of parent and lateral (so the two show as a Y with the
 * crotch between them), turned a little towards the lateral's side and from a
 * little above, into the crotch where the bark ridge forms; of the two sides of that
 * plane, the one towards `light` (the sun's direction), so the crotch is lit.
 * `radius` is the region to fill the view: the patch, a few parent radii.
 */
export function forkView(fork, { light = [0.4, 0.8, 0.35] } = {}) {
  const p = fork.parent, l = fork.lateral;
  const a = v3(p.tip).sub(v3(p.base)).normalize();
  const b = v3(l.tip).sub(v3(l.base)).normalize();
  if (a.lengthSq() < 0.5) a.set(0, 1, 0);
  // The lateral's direction away from the parent's axis.
  const side = b.clone().addScaledVector(a, -b.dot(a));
  if (side.lengthSq() < 1e-6) side.set(1, 0, 0).addScaledVector(a, -a.x);
  side.normalize();
  const normal = new THREE.Vector3().crossVectors(a, side).normalize();
  if (normal.dot(v3(light)) < 0) normal.negate();
  const dir = normal.clone().addScaledVector(side, 0.45).addScaledVector(a, 0.3).normalize();
  const r = 0.5 * p.diameter;
  // The patch reaches further along the lateral than across the parent: centre the
  // view a little into the crotch.
  const center = v3(fork.at).addScaledVector(side, 0.8 * r).addScaledVector(a, 0.6 * r);
  return { center: center.toArray(), radius: FRAME_PARENT * p.diameter + FRAME_LATERAL * l.diameter, dir: dir.toArray() };
}
