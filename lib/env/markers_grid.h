/* meristem — the marker set's storage, shared by its files (markers.c: the set,
 * the grid, removals and P09's competition, mer_markers_colonize; markers_near.c:
 * the markers near a set of points). Not installed. */
#ifndef MERISTEM_ENV_MARKERS_GRID_H
#define MERISTEM_ENV_MARKERS_GRID_H

#include <stddef.h>
#include <stdint.h>

#include <meristem/markers.h>

/* The bud that holds a marker so far in the competition, and its distance². */
typedef struct merp_claim {
    uint32_t bud;
    float d2;
} merp_claim;

/* A marker as filed in the grid: its position (copied, so a cell's markers are
 * contiguous in memory) and its index. */
typedef struct merp_marker_entry {
    float p[3];
    uint32_t id;
} merp_marker_entry;

struct mer_markers {
    float bmin[3];
    float cell, inv_cell;
    int dim[3];
    size_t ncells;
    /* markers, by index */
    float *p;          /* 3 per marker */
    uint8_t *dead;
    size_t n, cap, alive;
    /* CSR grid over live markers; stale when `dirty`. Cell c's live markers are
     * items[start[c], end[c]): removals compact the cell in place (keeping index
     * order), so that queries never step over the dead markers of a crown's
     * consumed inside. */
    uint32_t *start;   /* ncells + 1 */
    uint32_t *end;     /* ncells */
    merp_marker_entry *items; /* live markers in cell order, positions copied for locality */
    size_t items_cap;
    int dirty;
    /* colonization scratch, per grid entry (items): a cell's markers are
     * neighbours in memory, where claims for them land too */
    merp_claim *best;
    size_t scratch_cap;
    uint32_t *touched;
    size_t touched_cap;
    /* markers_near.c's scratch: a stamp per cell, a bit per marker index */
    uint32_t *stamp;
    uint32_t epoch;
    uint64_t *bits;    /* all zero between calls */
    size_t bits_cap;
    uint32_t *near_cells;
    size_t near_cap;
};

/* The grid's cell coordinate on axis a of x; points outside the bounds are filed
 * in the nearest border cell. */
static inline int merp_markers_coord(const mer_markers *m, float x, int a)
{
    float f = (x - m->bmin[a]) * m->inv_cell;
    if (!(f >= 0.0f))
        return 0;
    if (f >= (float)m->dim[a])
        return m->dim[a] - 1;
    return (int)f;
}

/* The grid cell of p. */
static inline size_t merp_markers_cell(const mer_markers *m, const float *p)
{
    int i = merp_markers_coord(m, p[0], 0), j = merp_markers_coord(m, p[1], 1),
        k = merp_markers_coord(m, p[2], 2);
    return ((size_t)k * (size_t)m->dim[1] + (size_t)j) * (size_t)m->dim[0] + (size_t)i;
}

/* Rebuilds the grid when stale. 0 when out of memory. */
int merp_markers_ensure_grid(mer_markers *m);

#endif
