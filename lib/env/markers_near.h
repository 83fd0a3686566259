/* meristem — the live markers near a set of points (markers_near.c), for models
 * that would otherwise read every marker each step. Not installed. */
#ifndef MERISTEM_ENV_MARKERS_NEAR_H
#define MERISTEM_ENV_MARKERS_NEAR_H

#include <stddef.h>

#include <meristem/markers.h>

/* markers_near.c: the positions of the live markers in the grid cells near the
 * `n` points `pts` (3 floats each) — every live marker within `radius` of one of
 * them, and some farther — in index order, into `*xyz` (3 floats each; grown as
 * needed, `*cap` markers, caller frees with merp_free); their number into
 * `*count`. O(n + markers and cells within about radius + a cell of the points
 * + markers ever added / 64). MER_ERR_NOMEM. */
mer_result merp_markers_near(mer_markers *m, const float *pts, size_t n, float radius,
                             float **xyz, size_t *cap, size_t *count, mer_error *err);

#endif
