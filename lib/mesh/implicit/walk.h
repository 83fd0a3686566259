/* meristem — the lattice under the polygonizers of implicit/ (mtet.c, dc.c):
 * samples of a field on a grid (regular or graded), evaluated lazily, and a
 * walk over the cells the surface crosses, from seeds, so that a polygonizer
 * costs in the surface's area, not the grid's volume. Private to
 * lib/mesh/implicit/. */
#ifndef MERISTEM_MESH_IMPLICIT_WALK_H
#define MERISTEM_MESH_IMPLICIT_WALK_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "mesh/implicit/implicit.h"

typedef struct merp_walk {
    const merp_grid *g;
    merp_field_fn f;
    merp_gradient_fn grad; /* ∇f, or NULL: merp_walk_normal differences f */
    const void *data;
    uint32_t sx, sy;  /* samples along x, y */
    uint32_t corner[8]; /* a cell's corner c (bits x = 1, y = 2, z = 4): its sample's from the lowest's */
    float *value;     /* per sample, valid where `known` has its bit */
    uint32_t *known;  /* a bit per sample */
    uint32_t *seen;   /* a bit per cell: queued once */
    uint64_t *queue;  /* cells to march, as i | j << 21 | k << 42 (no division to take one) */
    uint32_t head, tail;
} merp_walk;

/* Corner c of a cell (bits x = 1, y = 2, z = 4) and the corners of its six
 * faces (−x, +x, −y, +y, −z, +z) as bit masks over the eight corners. */
extern const uint8_t merp_walk_face[6];

/* Sets w up for g (no sample is evaluated yet): g has fewer than 2^21 cells
 * along each axis (the queue packs a cell's (i, j, k) in one word; patches
 * are far smaller). Errors: MER_ERR_NOMEM. Cost: O(samples / 8) bytes cleared. */
mer_result merp_walk_init(merp_walk *w, const merp_grid *g, merp_field_fn f, const void *data,
                          mer_error *err);
void merp_walk_free(merp_walk *w);

/* The polygonizers' prologue: merp_walk_init, `scratch_count` words of
 * scratch into *scratch (not cleared: the caller sets a cell's word when it
 * takes a crossed cell, and reads it only for a cell merp_walk_queued says
 * the walk took and that lies round a crossed edge, hence crossed itself —
 * a queued cell with all corners in or out keeps garbage; merp_free'd by
 * the caller), the walk started from `seeds` (merp_walk_start) and `out`
 * emptied. Errors: MER_ERR_NOMEM, with nothing left allocated. */
mer_result merp_walk_begin(merp_walk *w, const merp_grid *g, merp_field_fn f, const void *data,
                           const float (*seeds)[3], uint32_t nseeds, size_t scratch_count, uint32_t **scratch,
                           merp_trimesh *out, mer_error *err);

/* Whether cell c (its index, x fastest) was queued. */
static inline bool merp_walk_queued(const merp_walk *w, uint32_t c)
{
    return w->seen[c >> 5] >> (c & 31) & 1u;
}

static inline uint32_t merp_walk_sample(const merp_walk *w, uint32_t i, uint32_t j, uint32_t k)
{
    return i + w->sx * (j + w->sy * k);
}

/* f at sample (i, j, k), evaluated on first use. */
float merp_walk_value(merp_walk *w, uint32_t i, uint32_t j, uint32_t k);

/* The corners' values of cell (i, j, k) into cf; returns the mask of the
 * corners inside (f ≥ c): 0 or 0xff when the surface does not cross it. */
uint8_t merp_walk_corners(merp_walk *w, const uint32_t cell[3], float cf[8]);

/* Queues the first cell crossed by the surface from p's cell onwards along
 * +x (p clamped into the grid); nothing when the row has none. A seed inside
 * a solid finds that solid's surface. */
void merp_walk_seed(merp_walk *w, const float p[3]);

/* Queues every cell of the grid (a dense walk: every crossed cell is found,
 * whatever the seeds). */
void merp_walk_all(merp_walk *w);

/* Queues every cell when `seeds` is NULL, else each seed's first crossed cell. */
void merp_walk_start(merp_walk *w, const float (*seeds)[3], uint32_t nseeds);

/* Takes the next queued cell whose corners differ in sign into cell, cf and
 * *mask, queueing its neighbours across the faces whose corners differ (the
 * surface goes on there); false when none is left. The order is that of the
 * seeds and a breadth-first walk: deterministic. */
bool merp_walk_next(merp_walk *w, uint32_t cell[3], float cf[8], uint8_t *mask);

/* The surface point p on the segment from pa (inside, fa ≥ c) to pb
 * (outside): regula falsi with the Illinois modification, keeping the
 * bracket, until p is within 1e-4 of the segment's length from the surface.
 * Returns f(p). Cost: a few evaluations. */
float merp_walk_solve(const merp_walk *w, const float pa[3], float fa, const float pb[3], float fb,
                      float p[3]);

/* The surface point p on the segment from pa (inside, fa ≥ c) to pb
 * (outside) and the normal n = −∇f / |∇f| there (pb − pa, normalized,
 * where ∇f vanishes), to merp_walk_solve's tolerance. Without w->grad,
 * merp_walk_solve and merp_walk_normal. With it, each step evaluates f and
 * ∇f together and takes Newton's step along the segment, or regula falsi's
 * where Newton's would leave the bracket; a Newton step under 1 % of the
 * segment is the last, taken without evaluating again (its error is below
 * the tolerance where f is smooth, within the step across a crease), and n
 * is the last evaluation's: about 1.6 gradient evaluations, where solving
 * and differencing took six field evaluations. */
void merp_walk_crossing(const merp_walk *w, const float pa[3], float fa, const float pb[3], float fb,
                        float p[3], float n[3]);

/* −∇f / |∇f| at p, where f(p) = fp: from w->grad, or without it by forward
 * differences over h / 50 (three evaluations); `fallback` (normalized)
 * where ∇f vanishes. */
void merp_walk_normal(const merp_walk *w, const float p[3], float fp, const float fallback[3], float n[3]);

#endif
