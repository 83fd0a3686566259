/* meristem — the marker set S of space colonization (P09 §4.1), on a uniform grid.
 *
 * Markers are points of free space. A marker keeps its index (insertion order) for
 * life; removed markers are flagged and dropped from the grid at the next rebuild,
 * so every query visits markers in a fixed order and the results are deterministic.
 * The grid covers the scene bounds; a point outside is filed in the nearest border
 * cell, so queries stay exact anywhere (only slower far outside).
 *
 * Choices where the paper is open:
 *  - "Within" is inclusive: a marker at distance exactly ρ from a bud is removed,
 *    one at exactly r is perceived, one at exactly θ/2 off the bud axis is inside.
 *  - A marker seen by several buds at exactly the same distance goes to the bud
 *    listed first (lower index).
 *  - A marker at the bud's own position (distance 0) has no direction: it is
 *    removed by the occupancy zone before competition, since ρ > 0.
 */
#ifndef MERISTEM_MARKERS_H
#define MERISTEM_MARKERS_H

#include <stddef.h>
#include <stdint.h>

#include <meristem/result.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct mer_markers mer_markers;

/* Creates an empty set whose grid covers [bmin, bmax] with cubic cells of edge
 * `cell`. `*out` is owned by the caller (mer_markers_free). MER_ERR_RANGE if the
 * box is empty or the grid would exceed MER_GRID_CELLS_MAX cells; MER_ERR_NOMEM. */
mer_result mer_markers_new(const float bmin[3], const float bmax[3], float cell,
                           mer_markers **out, mer_error *err);

/* Frees `m` (NULL is fine). */
void mer_markers_free(mer_markers *m);

/* Appends `count` points (xyz triples in `xyz`, caller-owned). Amortized O(count);
 * the grid is rebuilt lazily at the next query. On MER_ERR_NOMEM nothing changes. */
mer_result mer_markers_add(mer_markers *m, const float *xyz, size_t count, mer_error *err);

/* Markers still in the set. O(1). */
size_t mer_markers_count(const mer_markers *m);

/* Copies the live markers' positions, in index order, into `out` (3 floats each,
 * room for `cap` markers; may be NULL when cap is 0). Returns the number of live
 * markers (which may exceed cap). O(markers ever added). */
size_t mer_markers_positions(const mer_markers *m, float *out, size_t cap);

/* Removes the markers within `radius` of `center` (inclusive). Returns how many. */
size_t mer_markers_remove_sphere(mer_markers *m, const float center[3], float radius);

/* Removes every marker for which `inside(p, ctx)` returns non-zero (obstacles, the
 * ground). O(markers). Returns how many. */
size_t mer_markers_remove_if(mer_markers *m, int (*inside)(const float p[3], void *ctx),
                             void *ctx);

/* 1 if `p` lies in the perception cone of a bud at `apex` pointing along the unit
 * vector `dir`: |p − apex| <= r and the angle to `dir` is at most half of θ, given
 * here as cos(θ/2). The apex itself is outside. O(1). */
int mer_in_cone(const float apex[3], const float dir[3], const float p[3], float r,
                float cos_half_theta);

/* One round of space colonization for `n` buds (positions `pos`, unit directions
 * `dir`, 3 floats each, in a fixed order): first every marker within ρ of any bud
 * is removed, then each remaining marker in the perception cone (θ in degrees, r)
 * of one or more buds is associated with the closest of them. Writes per bud:
 * q[i] = 1 if its set S(A) is non-empty, else 0; v[3i..] = the normalized sum of
 * the unit vectors towards its markers (0 when empty); count[i] (may be NULL) =
 * |S(A)|; quiet[i] (may be NULL) = 1 when no live marker is left in its
 * perception volume: its occupancy zone has just been emptied and markers only
 * leave until more are added, so until then (or until it moves) such a bud can
 * neither see nor remove a marker, and a caller may leave it out of later rounds.
 * O(n · markers in the cells of a perception volume's bounding box). MER_ERR_NOMEM
 * leaves outputs undefined. */
mer_result mer_markers_colonize(mer_markers *m, size_t n, const float *pos, const float *dir,
                                float rho, float r, float theta, float *q, float *v,
                                uint32_t *count, uint8_t *quiet, mer_error *err);

#ifdef __cplusplus
}
#endif

#endif
