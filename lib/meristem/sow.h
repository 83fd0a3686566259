/* meristem — placing plants with natural spacing (the survey's §VII-B): Poisson-
 * disk sampling after R. Bridson, "Fast Poisson disk sampling in arbitrary
 * dimensions" (SIGGRAPH 2007 sketches), and the Voronoi cells of the placed
 * plants, which can bound each plant's share of space (its markers) so that
 * neighbours do not overlap. Pure functions: no scene, no I/O.
 *
 * Points are (x, z) pairs on the ground plane (y is up). */
#ifndef MERISTEM_SOW_H
#define MERISTEM_SOW_H

#include <stddef.h>
#include <stdint.h>

#include <meristem/result.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The most grid cells (of edge r/√2) mer_poisson_disk works over. */
#define MER_SOW_CELLS_MAX (UINT32_C(4) * 1024 * 1024)

/* `count` points in the rectangle [lo, hi] (x then z), no two closer than `r`,
 * into `out` (2 floats each, room for `count`); `*placed` says how many. Bridson's
 * algorithm (30 candidates per active point, in the annulus [r, 2r]) fills the
 * rectangle up to a maximal set of M points, all drawn from `seed`; `count` of
 * them are then chosen uniformly (listed in the order they were made), so that a
 * sparse forest spreads over the whole area rather than around the first point.
 * Errors: MER_ERR_RANGE for r <= 0, an empty or non-finite rectangle, or a grid
 * of more than MER_SOW_CELLS_MAX cells (field "min_distance" or "area");
 * MER_ERR_LIMIT when the area holds only M < count points at this spacing: then
 * the M points are in `out` (`*placed` = M) and the message names M;
 * MER_ERR_NOMEM. Deterministic: the same arguments give the same bytes. Cost
 * O(cells + M) expected. */
mer_result mer_poisson_disk(const float lo[2], const float hi[2], float r, uint32_t count,
                            uint64_t seed, float *out, uint32_t *placed, mer_error *err);

/* The Voronoi cell that (x, z) point `p` lies in: the index of the nearest of the
 * `n` sites (2 floats each; n >= 1), ties to the lower index. O(n). */
uint32_t mer_voronoi_cell(const float *sites, uint32_t n, const float p[2]);

/* Keeps, in order, the `count` 3-D points of `xyz` (x, y, z) whose (x, z) lies
 * in the Voronoi cell of site `cell`, moving them to the front; returns how many
 * were kept. The cells of all sites partition the plane: clipping one point set
 * to every cell in turn gives each point to exactly one site. O(count · n). */
size_t mer_voronoi_clip(const float *sites, uint32_t n, uint32_t cell, float *xyz, size_t count);

#ifdef __cplusplus
}
#endif

#endif
