// Graphically defined functions (G04 §4) as the page draws and sends them: the curve of
// a control polygon as lib/models/inverse/gfunc.c evaluates it (lpfg's clamped uniform
// cubic B-spline, every point repeated by its multiplicity; or the polyline itself for
// kind "linear"), and the .fset text of functions (funcfile.c reads it back).

/**
 * What each function of the inverse model controls, by G04's symbol: [a short name,
 * what it is in the paper, its x].
 */
export const FUNCTION_INFO = {
  G_h: ['trunk height', 'trunk length by the tree\'s age (§4)', 'age / y_max'],
  G_s1: ['young silhouette', 'branch length by its place on the parent, young tree (eq. 6)', 'position on the parent'],
  G_s2: ['mature silhouette', 'branch length by its place on the parent, mature tree (eq. 6)', 'position on the parent'],
  G_o1: ['heading, short', 'heading along a branch of length 0 (eq. 9)', 'along the branch'],
  G_o2: ['heading, long', 'heading along a branch of length l_max (eq. 9)', 'along the branch'],
  G_bs: ['branch scale', 'branch scale by its place on the parent (eqs. 10, 13)', 'position on the parent'],
  G_ss: ['shoot scale', 'branch scale by its place on the shoot (eq. 15)', 'position on the shoot'],
  G_a: ['shedding age', 'the age a branch is shed at, by its scale s_b (eq. 11)', 'branch scale s_b'],
  G_m: ['metamers', 'metamers of a shoot by its length (eq. 14)', 'shoot length / l_smax'],
  G_l: ['leaf size', 'leaf size by place on the shoot (§4.3)', 'position on the shoot'],
  G_e: ['elongation', 'internode elongation over its growing time (Fig. 12)', 'time in its growth'],
  G_lg: ['leaf growth', 'leaf growth over its growing time (Fig. 13)', 'time in its growth'],
  G_bg: ['bud growth', 'bud growth over its growing time (§4.3)', 'time in its growth'],
  G_r: ['radius', 'radius along the branch, times r_max·L/h_max (§4.1)', 'position on the branch'],
};

/** The clamped uniform knot t_i for n control points of degree 3 (gfunc.c's). */
function knot(i, n) {
  if (i <= 3) return 0;
  if (i >= n) return n - 3;
  return i - 3;
}

/** De Boor's algorithm at parameter s ∈ [0, n − 3] over the expanded polygon. */
function deBoor(px, py, s) {
  const n = px.length;
  const k = Math.min(Math.floor(s) + 3, n - 1);
  const dx = [0, 1, 2, 3].map((j) => px[k - 3 + j]);
  const dy = [0, 1, 2, 3].map((j) => py[k - 3 + j]);
  for (let r = 1; r <= 3; r++) {
    for (let j = 3; j >= r; j--) {
      const i = k - 3 + j;
      const lo = knot(i, n), hi = knot(i + 4 - r, n);
      const a = hi > lo ? (s - lo) / (hi - lo) : 0;
      dx[j] = (1 - a) * dx[j - 1] + a * dx[j];
      dy[j] = (1 - a) * dy[j - 1] + a * dy[j];
    }
  }
  return [dx[3], dy[3]];
}

/** Points [x, y] along function f ({kind, points: [[x, y, m]]}), `count` of them. */
export function curve(f, count = 64) {
  if (f.kind === 'linear') return f.points.map(([x, y]) => [x, y]);
  const px = [], py = [];
  for (const [x, y, m = 1] of f.points) for (let k = 0; k < m; k++) { px.push(x); py.push(y); }
  if (px.length < 4) return px.map((x, i) => [x, py[i]]);
  return Array.from({ length: count + 1 }, (_, i) => deBoor(px, py, (i / count) * (px.length - 3)));
}

/** A number as the .fset text writes it: short, exact to a float. */
const num = (v) => String(Number(v.toPrecision(7)));

/** The .fset text (a function gallery) of functions `fs`. */
export function fsetText(fs) {
  const parts = [`funcgalleryver 1 1\nitems: ${fs.length}\n`];
  for (const f of fs) {
    parts.push(`fver 1 1\nname: ${f.name}\nsamples: ${f.samples}\nflip: off\n`);
    if (f.kind === 'linear') parts.push('kind: linear\n');
    parts.push(`points: ${f.points.length}\n`);
    for (const [x, y, m = 1] of f.points) parts.push(m !== 1 ? `${num(x)} ${num(y)} ${m}\n` : `${num(x)} ${num(y)}\n`);
  }
  return parts.join('');
}
