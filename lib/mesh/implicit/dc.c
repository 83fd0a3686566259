/* meristem — dual contouring (Ju, Losasso, Schaefer & Warren 2002) over a
 * regular grid (implicit.h): one vertex per crossed cell, placed by the
 * quadratic error function of the cell's edge crossings and normals (Hermite
 * data), so that a crease through the cell (the branch bark ridge) keeps its
 * vertex on it; one quad per crossed edge. */
#include "config.h"

#include <assert.h>
#include <math.h>
#include <string.h>

#include "core/alloc.h"
#include "core/vec.h"
#include "mesh/implicit/implicit.h"
#include "mesh/implicit/walk.h"

/* The QEF's pull towards the crossings' mass point, relative to one plane's
 * weight: small, so it only decides the directions no plane constrains (along
 * a crease, across a flat face). */
#define QEF_LAMBDA 0.02f

/* The two cube corners of each of a cell's 12 edges (bits x = 1, y = 2, z = 4). */
static const uint8_t cube_edge[12][2] = {
    {0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3}, {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7},
};

void merp_dc_bound(const merp_grid *g, uint64_t *vertices, uint64_t *triangles)
{
    uint64_t samples = (uint64_t)(g->n[0] + 1) * (g->n[1] + 1) * (g->n[2] + 1);
    *vertices = (uint64_t)g->n[0] * g->n[1] * g->n[2];
    *triangles = samples * 3 * 2;
}

typedef struct qef {
    float ata[6]; /* AᵀA: xx, xy, xz, yy, yz, zz */
    float atb[3];
    float mass[3];
    int count;
} qef;

static void qef_add(qef *q, const float p[3], const float n[3])
{
    float d = v3_dot(n, p);
    q->ata[0] += n[0] * n[0], q->ata[1] += n[0] * n[1], q->ata[2] += n[0] * n[2];
    q->ata[3] += n[1] * n[1], q->ata[4] += n[1] * n[2], q->ata[5] += n[2] * n[2];
    for (int k = 0; k < 3; k++) {
        q->atb[k] += n[k] * d;
        q->mass[k] += p[k];
    }
    q->count++;
}

/* argmin Σ (n·x − n·p)² + λ|x − m|² (m the mass point): (AᵀA + λI) y =
 * Aᵀb − AᵀA m with x = m + y, by Cramer's rule (the matrix is positive
 * definite). */
static void qef_solve(const qef *q, float x[3])
{
    float m[3] = {q->mass[0] / (float)q->count, q->mass[1] / (float)q->count, q->mass[2] / (float)q->count};
    float l = QEF_LAMBDA * (float)q->count;
    float a = q->ata[0] + l, b = q->ata[1], c = q->ata[2], d = q->ata[3] + l, e = q->ata[4], f = q->ata[5] + l;
    float r[3] = {q->atb[0] - (q->ata[0] * m[0] + b * m[1] + c * m[2]),
                  q->atb[1] - (b * m[0] + q->ata[3] * m[1] + e * m[2]),
                  q->atb[2] - (c * m[0] + e * m[1] + q->ata[5] * m[2])};
    float c00 = d * f - e * e, c01 = c * e - b * f, c02 = b * e - c * d;
    float det = a * c00 + b * c01 + c * c02;
    float c11 = a * f - c * c, c12 = b * c - a * e, c22 = a * d - b * b;
    x[0] = m[0] + (c00 * r[0] + c01 * r[1] + c02 * r[2]) / det;
    x[1] = m[1] + (c01 * r[0] + c11 * r[1] + c12 * r[2]) / det;
    x[2] = m[2] + (c02 * r[0] + c12 * r[1] + c22 * r[2]) / det;
}

typedef struct dc {
    merp_walk *w;
    uint32_t *cell_v; /* per cell: vertex + 1, 0 when none */
    merp_trimesh *out;
    uint32_t *cells; /* per vertex: its cell, or NULL */
} dc;

static void corner_sample(const uint32_t cell[3], uint8_t c, uint32_t s[3])
{
    s[0] = cell[0] + (c & 1), s[1] = cell[1] + (c >> 1 & 1), s[2] = cell[2] + (c >> 2 & 1);
}

/* The cell's vertex: its crossings' QEF minimum, clamped into the cell. */
static void cell_vertex(dc *d, const uint32_t cell[3], const float cf[8], uint8_t mask)
{
    const merp_grid *g = d->w->g;
    qef q;
    memset(&q, 0, sizeof q);
    for (int e = 0; e < 12; e++) {
        uint8_t c1 = cube_edge[e][0], c2 = cube_edge[e][1];
        if ((mask >> c1 & 1) == (mask >> c2 & 1))
            continue;
        uint32_t s1[3], s2[3];
        corner_sample(cell, c1, s1);
        corner_sample(cell, c2, s2);
        float p1[3], p2[3], p[3], n[3], dir[3];
        for (int k = 0; k < 3; k++) {
            p1[k] = g->origin[k] + (float)s1[k] * g->h;
            p2[k] = g->origin[k] + (float)s2[k] * g->h;
        }
        bool in1 = mask >> c1 & 1;
        float fp = in1 ? merp_walk_solve(d->w, p1, cf[c1], p2, cf[c2], p) : merp_walk_solve(d->w, p2, cf[c2], p1, cf[c1], p);
        for (int k = 0; k < 3; k++)
            dir[k] = in1 ? p2[k] - p1[k] : p1[k] - p2[k];
        merp_walk_normal(d->w, p, fp, dir, n);
        qef_add(&q, p, n);
    }
    float x[3];
    qef_solve(&q, x);
    for (int k = 0; k < 3; k++) {
        float lo = g->origin[k] + (float)cell[k] * g->h;
        x[k] = x[k] < lo ? lo : x[k] > lo + g->h ? lo + g->h : x[k];
    }
    merp_trimesh *o = d->out;
    uint32_t v = o->vertex_count++;
    memcpy(o->positions + 3 * (size_t)v, x, sizeof x);
    if (o->normals != NULL) { /* a caller may shade from another field */
        float fallback[3] = {x[0] - q.mass[0] / (float)q.count, x[1] - q.mass[1] / (float)q.count,
                             x[2] - q.mass[2] / (float)q.count};
        if (!v3_normalize(fallback))
            fallback[0] = 1.0f;
        merp_walk_normal(d->w, x, d->w->f(x, d->w->data), fallback, o->normals + 3 * (size_t)v);
    }
    uint32_t idx = cell[0] + g->n[0] * (cell[1] + g->n[1] * cell[2]);
    d->cell_v[idx] = v + 1;
    if (d->cells != NULL)
        d->cells[v] = idx;
}

static uint32_t vertex_of(const dc *d, uint32_t i, uint32_t j, uint32_t k)
{
    const merp_grid *g = d->w->g;
    return d->cell_v[i + g->n[0] * (j + g->n[1] * k)];
}

/* The quads of the cell's three edges from its corner 0 (each interior
 * crossed edge is corner 0's edge of exactly one cell): the four cells
 * around the edge, counter-clockwise about +axis, reversed when the edge's
 * far end is the inside one, split along the diagonal that folds least. */
static void cell_quads(dc *d, const uint32_t cell[3], uint8_t mask)
{
    const float *pos = d->out->positions;
    for (int a = 0; a < 3; a++) {
        uint8_t far = (uint8_t)(1u << a);
        if ((mask & 1) == (mask >> far & 1))
            continue;
        int b = (a + 1) % 3, c = (a + 2) % 3;
        if (cell[b] == 0 || cell[c] == 0)
            continue; /* on the grid's face: the surface leaves it here */
        uint32_t q[4][3];
        for (int t = 0; t < 4; t++)
            memcpy(q[t], cell, sizeof q[t]);
        q[0][b]--, q[0][c]--; /* (−, −), (0, −), (0, 0), (−, 0) in the (b, c) plane */
        q[1][c]--;
        q[3][b]--;
        uint32_t v[4];
        for (int t = 0; t < 4; t++) {
            v[t] = vertex_of(d, q[t][0], q[t][1], q[t][2]);
            if (v[t] == 0)
                return; /* a neighbour the walk did not reach */
            v[t]--;
        }
        if (!(mask & 1)) { /* the inside is at the far end: face −axis */
            uint32_t s = v[1];
            v[1] = v[3], v[3] = s;
        }
        /* Split along 0–2 or 1–3: the one whose two triangles' normals agree more. */
        float n[4][3];
        for (int t = 0; t < 4; t++) {
            const float *p0 = pos + 3 * (size_t)v[t], *p1 = pos + 3 * (size_t)v[(t + 1) % 4],
                        *p2 = pos + 3 * (size_t)v[(t + 3) % 4];
            float e1[3], e2[3];
            for (int k = 0; k < 3; k++)
                e1[k] = p1[k] - p0[k], e2[k] = p2[k] - p0[k];
            v3_cross(e1, e2, n[t]);
            v3_normalize(n[t]);
        }
        /* n[t] is the normal of the triangle at corner t: split 0–2 makes the
         * triangles at corners 1 and 3. */
        int s = v3_dot(n[1], n[3]) >= v3_dot(n[0], n[2]) ? 0 : 1;
        uint32_t *t = d->out->triangles + 3 * (size_t)d->out->triangle_count;
        t[0] = v[s], t[1] = v[s + 1], t[2] = v[(s + 2) % 4];
        t[3] = v[s], t[4] = v[(s + 2) % 4], t[5] = v[(s + 3) % 4];
        d->out->triangle_count += 2;
    }
}

mer_result merp_dc_polygonize(const merp_grid *g, merp_field_fn f, const void *data, const float (*seeds)[3],
                              uint32_t nseeds, merp_trimesh *out, uint32_t *cells, mer_error *err)
{
    merp_walk w;
    dc d = {&w, NULL, out, cells};
    if (merp_walk_begin(&w, g, f, data, seeds, nseeds, (size_t)g->n[0] * g->n[1] * g->n[2], &d.cell_v, out,
                        err) != MER_OK)
        return MER_ERR_NOMEM;
    uint32_t cell[3];
    float cf[8];
    uint8_t mask;
    while (merp_walk_next(&w, cell, cf, &mask))
        cell_vertex(&d, cell, cf, mask);
    /* Every crossed cell has its vertex: now the quads, in the walk's order. */
    for (uint32_t i = 0; i < w.tail; i++) {
        uint32_t c = w.queue[i];
        merp_walk_cell(&w, c, cell);
        if (d.cell_v[c] == 0)
            continue;
        mask = merp_walk_corners(&w, cell, cf);
        cell_quads(&d, cell, mask);
    }
    merp_walk_free(&w);
    merp_free(d.cell_v);
    return MER_OK;
}
