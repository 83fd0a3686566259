/* Checks on a triangle mesh shared by the implicit-surface tests: closed
 * 2-manifold with consistent winding (every directed edge once, its reverse
 * once), Euler characteristic, enclosed volume; with implicit.h, a
 * polygonizer's output and its closed genus-0 check. */
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

#ifdef MERISTEM_MESH_IMPLICIT_H
/* A polygonizer's output with the bounds it was sized by (for the tests that
 * include implicit.h and cmocka). */
typedef struct mesh_out {
    merp_trimesh m;
    uint64_t vmax, tmax;
} mesh_out;

static inline void mesh_alloc(mesh_out *o, uint64_t vertices, uint64_t triangles)
{
    o->vmax = vertices, o->tmax = triangles;
    o->m = (merp_trimesh){.positions = malloc(vertices * 3 * sizeof(float)),
                          .normals = malloc(vertices * 3 * sizeof(float)),
                          .triangles = malloc(triangles * 3 * sizeof(uint32_t))};
}

static inline void mesh_free(mesh_out *o)
{
    free(o->m.positions);
    free(o->m.normals);
    free(o->m.triangles);
}

/* Closed, consistently wound, genus 0 (V − E + F = 2), positive volume. */
static inline void assert_closed_genus0(const mesh_out *o)
{
    size_t twice, edges;
    assert_int_equal(tm_open_edges(o->m.triangles, o->m.triangle_count, &twice, &edges), 0);
    assert_int_equal(twice, 0);
    long chi = (long)o->m.vertex_count - (long)edges + (long)o->m.triangle_count;
    assert_int_equal(chi, 2);
    assert_true(tm_volume(o->m.positions, o->m.triangles, o->m.triangle_count) > 0);
}
#endif

#endif
