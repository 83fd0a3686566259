/* meristem — the shadow-propagation voxel grid (P09 §4.1, Fig. 5).
 *
 * Each voxel (i, j, k) holds a shadow value s. A bud in voxel (I, J, K) adds
 * Δs = a·b^(−q) to every voxel (I+di, J−q, K+dk) with |di|, |dk| <= q, for
 * q = 0..q_max: a square pyramid opening downwards (y is up). The light of a bud
 * is Q = max(C − s + a, 0): the + a cancels the bud's own shadow.
 *
 * The grid is kept up to date incrementally: a bud's pyramid is added when the
 * bud appears and subtracted when it goes. Values are stored in fixed point
 * (units of a/4096, in unsigned 32-bit arithmetic), so a subtraction undoes an
 * addition exactly and an incrementally kept grid equals one rebuilt from scratch,
 * bit for bit, whatever the order of events.
 *
 * Choices where the paper is open:
 *  - A point outside the grid belongs to the nearest border voxel (clamped), for
 *    casting and for light alike: a tree that outgrows the scene bounds crowds
 *    the border voxels and stops, rather than escaping into unlimited light.
 *  - The least-shadowed-neighbour direction looks at the 26 neighbours whose
 *    direction from the bud's voxel lies in the perception cone (θ); among equally
 *    shadowed ones the one closest to the bud's own direction wins (then the first
 *    in (dk, dj, di) = (−1..1) order), so an unshaded bud keeps its course;
 *    neighbours outside the grid have s = 0. No neighbour in the cone gives V = 0.
 *  - The gradient is the central difference over the 6 face neighbours.
 */
#ifndef MERISTEM_SHADOW_H
#define MERISTEM_SHADOW_H

#include <stdint.h>

#include <meristem/result.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct mer_shadow mer_shadow;

/* Creates a zero grid covering [bmin, bmax] with cubic voxels of edge `voxel`,
 * shadow parameters a > 0, b > 1 and depth q_max (0..32). `*out` is owned by the
 * caller (mer_shadow_free). MER_ERR_RANGE / MER_ERR_LIMIT / MER_ERR_NOMEM. Costs
 * O(voxels) memory at 4 bytes each. */
mer_result mer_shadow_new(const float bmin[3], const float bmax[3], float voxel, float a,
                          float b, uint32_t q_max, mer_shadow **out, mer_error *err);

/* Frees `sh` (NULL is fine). */
void mer_shadow_free(mer_shadow *sh);

/* Resets every voxel to 0. O(voxels). */
void mer_shadow_clear(mer_shadow *sh);

/* Grid size in voxels; `dim` has 3 entries. */
void mer_shadow_dims(const mer_shadow *sh, int dim[3]);

/* The voxel containing `p`: fills `ijk` and returns 1; for a point outside the
 * grid fills the nearest border voxel and returns 0. */
int mer_shadow_voxel_of(const mer_shadow *sh, const float p[3], int ijk[3]);

/* Adds (sign > 0) or subtracts (sign < 0) the pyramid of a bud in voxel `ijk`,
 * clipped to the grid. `weight` scales Δs (1 for a bud). O(q_max³). */
void mer_shadow_cast(mer_shadow *sh, const int ijk[3], int sign, float weight);

/* Same, for a bud at point `p` (clamped to the grid). */
void mer_shadow_cast_at(mer_shadow *sh, const float p[3], int sign);

/* Adds `amount` (may be negative, same fixed point) to one voxel only (obstacle
 * interiors). Nothing if out of the grid. */
void mer_shadow_add_voxel(mer_shadow *sh, const int ijk[3], float amount);

/* The shadow value s of voxel `ijk` (0 outside the grid). O(1). */
float mer_shadow_value(const mer_shadow *sh, const int ijk[3]);

/* Q = max(C − s + a, 0) at point `p` (clamped to the grid). O(1). */
float mer_shadow_light(const mer_shadow *sh, const float p[3], float c);

/* The optimal growth direction V at `p` for a bud pointing along unit `dir` with
 * perception angle θ (degrees), by `mode` (mer_shadow_dir of params.h). Writes a
 * unit vector or 0 to `out`. O(1). */
void mer_shadow_direction(const mer_shadow *sh, const float p[3], const float dir[3],
                          float theta, uint32_t mode, float out[3]);

/* A hash of the grid contents (FNV-1a over the voxels), for tests. O(voxels). */
uint64_t mer_shadow_hash(const mer_shadow *sh);

#ifdef __cplusplus
}
#endif

#endif
