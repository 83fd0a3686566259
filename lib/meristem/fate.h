/* meristem — bud fate: the resource-allocation kernels of P09 §4.2.
 *
 * These are the pure formulas; lib/models/p09/ applies them to a whole tree. They are
 * public so the server, tests and other tools can show a worked allocation.
 *
 * Extended Borchert-Honda (BH): at a branching point the resource v is split
 *   v_m = v·λQ_m / (λQ_m + (1−λ)Q_l),  v_l = v·(1−λ)Q_l / (λQ_m + (1−λ)Q_l).
 * With two lateral buds per node (opposite phyllotaxis) Q_l is their sum and v_l is
 * shared between them in proportion to their Q (our generalisation). When the
 * denominator is 0 nothing flows on (v_m = v_l = 0).
 *
 * A bud that receives v makes n = ⌊v⌋ metamers of length l = v/n (in units of the
 * internode length l0). n is capped at `max_n`; the length is still v/⌊v⌋, so a
 * cap limits the count, not the internode length (the excess resource is lost).
 *
 * Priority model: the N buds and branches an axis supports are sorted by light per
 * bud Q_i/b_i (descending; ties by original index, so the order is deterministic),
 * the terminal bud is moved to the front while the axis has apical control, and
 *   v_i = v·Q_i·w_i / Σ_j Q_j·w_j
 * with w_i the weight of the item's position (mer_priority_weight, P09 Fig. 8c).
 */
#ifndef MERISTEM_FATE_H
#define MERISTEM_FATE_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* BH split of `v` with λ = `lambda` between the main axis (light `q_main`) and the
 * lateral branch (`q_lat`). Outputs not NULL. O(1). */
void mer_bh_split(float v, float lambda, float q_main, float q_lat, float *v_main, float *v_lat);

/* BH split with two lateral buds (see above). `v_lat` has 2 entries. O(1). */
void mer_bh_split2(float v, float lambda, float q_main, const float q_lat[2], float *v_main,
                   float v_lat[2]);

/* n = min(⌊v⌋, max_n) metamers; `*length` (may be NULL) gets l0·v/⌊v⌋, or 0 when
 * n = 0. v < 1, negative or NaN gives 0. O(1). */
uint32_t mer_shoot_size(float v, uint32_t max_n, float l0, float *length);

/* The Fig. 8c weight of list position `i` (0-based) of `n` items: w_max at i = 0,
 * linear down to w_min at i = κ·n, w_min beyond (see params.h). O(1). */
float mer_priority_weight(uint32_t i, uint32_t n, float w_max, float w_min, float kappa);

/* Priority allocation over `n` items with light `q[i]` and bud counts `buds[i]`
 * (a bud counts 1; 0 is read as 1). `terminal` is the index of the axis's terminal
 * bud, or UINT32_MAX when it has none; `apical` != 0 puts it first. `weights` gives
 * the weight per position, or NULL for mer_priority_weight(w_max, w_min, κ).
 * Writes the resulting list (item indices, first = highest priority) to `rank` and
 * the allocations to `out_v`; `scratch` needs n entries. All arrays caller-owned,
 * not NULL when n > 0; `out_v` does not overlap `q`. O(n log n). */
void mer_priority_allocate(float v, uint32_t n, const float *q, const uint32_t *buds,
                           uint32_t terminal, int apical, const float *weights, float w_max,
                           float w_min, float kappa, uint32_t *rank, uint32_t *scratch,
                           float *out_v);

#ifdef __cplusplus
}
#endif

#endif
