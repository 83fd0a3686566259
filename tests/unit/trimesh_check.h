/* Checks on a triangle mesh shared by the implicit-surface tests: closed
 * 2-manifold with consistent winding (every directed edge once, its reverse
 * once), Euler characteristic, enclosed volume. */
#ifndef MERISTEM_TESTS_TRIMESH_CHECK_H
#define MERISTEM_TESTS_TRIMESH_CHECK_H

#include <stdint.h>
#include <stdlib.h>

typedef struct tm_edge {
    uint32_t a, b;
} tm_edge;

static int tm_edge_cmp(const void *x, const void *y)
{
    const tm_edge *p = x, *q = y;
    if (p->a != q->a)
        return p->a < q->a ? -1 : 1;
    return p->b < q->b ? -1 : p->b > q->b;
}

static int tm_has(const tm_edge *e, size_t n, uint32_t a, uint32_t b)
{
    tm_edge key = {a, b};
    return bsearch(&key, e, n, sizeof *e, tm_edge_cmp) != NULL;
}

/* The directed edges of `tri` without their partner: 0 for a closed,
 * consistently wound mesh. Also counts directed edges seen twice (a
 * non-manifold edge or a flipped neighbour) into *twice, and gives the
 * number of undirected edges. */
static size_t tm_open_edges(const uint32_t *tri, uint32_t triangles, size_t *twice, size_t *edges)
{
    size_t n = (size_t)triangles * 3, open = 0;
    tm_edge *e = malloc(n * sizeof *e);
    for (uint32_t t = 0; t < triangles; t++)
        for (int k = 0; k < 3; k++)
            e[3 * t + k] = (tm_edge){tri[3 * t + k], tri[3 * t + (k + 1) % 3]};
    qsort(e, n, sizeof *e, tm_edge_cmp);
    *twice = 0;
    for (size_t i = 0; i + 1 < n; i++)
        if (tm_edge_cmp(&e[i], &e[i + 1]) == 0)
            (*twice)++;
    for (size_t i = 0; i < n; i++)
        if (!tm_has(e, n, e[i].b, e[i].a))
            open++;
    *edges = (n - open) / 2 + open;
    free(e);
    return open;
}

/* The signed volume enclosed (positive when wound counter-clockwise seen from
 * outside). */
static double tm_volume(const float *pos, const uint32_t *tri, uint32_t triangles)
{
    double v = 0;
    for (uint32_t t = 0; t < triangles; t++) {
        const float *a = pos + 3 * tri[3 * t], *b = pos + 3 * tri[3 * t + 1],
                    *c = pos + 3 * tri[3 * t + 2];
        double ax = a[0], ay = a[1], az = a[2], bx = b[0], by = b[1], bz = b[2];
        double cx = c[0], cy = c[1], cz = c[2];
        v += (ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx)) / 6.0;
    }
    return v;
}

#endif
