// Brushing with symmetry (Palubicki et al. 2009, §5, Fig. 17): the brush panel's
// symmetry settings as meristemd takes them, and the copies of a dab they make, for the
// live preview.
import * as THREE from 'three';
import { $, round3 } from '../util.js';

/**
 * The symmetry the brush panel selects, about the base of the first plant (node 0 in
 * the viewer's snapshot, else the origin): {mirror?, rotational?, center?, tiles?,
 * tile_step?} as add_markers takes it, or null.
 */
export function symmetrySettings(viewer) {
  const sym = {};
  const base = treeBase(viewer);
  if ($('#sym-mirror').checked) {
    sym.mirror = { point: base, normal: $('#sym-plane').value === 'x' ? [1, 0, 0] : [0, 0, 1] };
  }
  if ($('#sym-rot').checked) {
    sym.rotational = Math.max(2, Math.min(64, Math.round(Number($('#sym-rot-n').value) || 2)));
    sym.center = base;
  }
  if ($('#sym-tile').checked) {
    const u = Math.max(1, Math.round(Number($('#sym-tile-u').value) || 1));
    const v = Math.max(1, Math.round(Number($('#sym-tile-v').value) || 1));
    const d = Number($('#sym-tile-step').value) || 10;
    sym.tiles = [u, v];
    sym.tile_step = [[d, 0, 0], [0, 0, d]];
  }
  return Object.keys(sym).length ? sym : null;
}

/** The base of the first plant (node 0) on the ground, else the origin. */
function treeBase(viewer) {
  const root = viewer.nodes().get(0);
  return root ? [round3(root.center[0]), 0, round3(root.center[2])] : [0, 0, 0];
}

/** The symmetric copies of point p, in the order the library makes them (lib/symmetry.c). */
export function symmetricCopies(p, sym) {
  if (!sym) return [p.clone()];
  const c = new THREE.Vector3(...(sym.center || [0, 0, 0]));
  const rot = sym.rotational > 1 ? sym.rotational : 1;
  const up = new THREE.Vector3(0, 1, 0);
  const out = [];
  for (let r = 0; r < rot; r++) {
    const pr = p.clone().sub(c).applyAxisAngle(up, (2 * Math.PI * r) / rot).add(c);
    const mirrored = [pr];
    if (sym.mirror) {
      const n = new THREE.Vector3(...sym.mirror.normal).normalize();
      const m0 = new THREE.Vector3(...(sym.mirror.point || [0, 0, 0]));
      const d = pr.clone().sub(m0).dot(n);
      mirrored.push(pr.clone().addScaledVector(n, -2 * d));
    }
    for (const pm of mirrored) {
      const t0 = sym.tiles ? Math.max(1, sym.tiles[0]) : 1, t1 = sym.tiles ? Math.max(1, sym.tiles[1]) : 1;
      for (let i = 0; i < t0; i++) {
        for (let j = 0; j < t1; j++) {
          const q = pm.clone();
          if (sym.tile_step) {
            q.addScaledVector(new THREE.Vector3(...sym.tile_step[0]), i);
            q.addScaledVector(new THREE.Vector3(...sym.tile_step[1]), j);
          }
          out.push(q);
        }
      }
    }
  }
  return out;
}
