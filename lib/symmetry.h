/* meristem — the copies a brush dab makes under symmetry (edit.h, mer_symmetry):
 * rotational about the vertical axis, mirrored in a plane, tiled on a lattice.
 * Not installed. */
#ifndef MERISTEM_SYMMETRY_H
#define MERISTEM_SYMMETRY_H

#include <stddef.h>
#include <stdint.h>

#include <meristem/edit.h>

#define MERP_SYM_ROTATIONAL_MAX 64u /* n-fold copies about the axis */
#define MERP_SYM_TILES_MAX 1024u    /* tiles[0]·tiles[1] */

/* A mer_symmetry checked and with its defaults applied. */
typedef struct merp_symmetry {
    const mer_symmetry *sym; /* NULL: no copies */
    uint32_t rot, tiles0, tiles1, mirror;
    float n[3]; /* the mirror plane's unit normal */
} merp_symmetry;

/* Checks `sym` (NULL: none) and fills `out`. MER_ERR_RANGE naming the field. */
mer_result merp_symmetry_resolve(const mer_symmetry *sym, merp_symmetry *out, mer_error *err);
/* The number of points each dab point becomes (itself included). */
size_t merp_symmetry_copies(const merp_symmetry *y);
/* Writes the merp_symmetry_copies(y) images of p (3 floats each) to `out`:
 * rotations, each then mirrored, each then tiled. */
void merp_symmetry_apply(const merp_symmetry *y, const float p[3], float *out);

#endif
