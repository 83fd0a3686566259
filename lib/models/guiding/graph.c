/* meristem — the graph of Xu & Mould 2015's first step (guiding.h): nodes on a
 * jittered grid over the volume the tree may occupy, linked as a Yao graph (the
 * nearest neighbour in each of k cones). Neighbours are found through a uniform
 * grid of cells of edge radius/2, so a node looks at the 125 cells around it. */
#include "config.h"

#include <assert.h>
#include <math.h>
#include <string.h>

#include "core/alloc.h"
#include "core/array.h"
#include "core/vec.h"
#include "models/guiding/guiding.h"

void merp_gv_graph_free(merp_gv_graph *g)
{
    if (g == NULL)
        return;
    merp_free(g->pos);
    merp_free(g->start);
    merp_free(g->to);
    memset(g, 0, sizeof *g);
}

void merp_gv_cone_axes(uint32_t k, float *axes)
{
    assert(k >= 1 && axes != NULL);
    /* A Fibonacci lattice: k points at equal-area heights, turned by the golden
     * angle, so the cones are of about equal solid angle. */
    const double golden = 2.399963229728653;
    for (uint32_t i = 0; i < k; i++) {
        double y = 1.0 - (2.0 * i + 1.0) / k;
        double r = sqrt(1.0 - y * y);
        axes[3 * i] = (float)(r * cos(golden * i));
        axes[3 * i + 1] = (float)y;
        axes[3 * i + 2] = (float)(r * sin(golden * i));
    }
}

uint32_t merp_gv_cone_of(const float *axes, uint32_t k, const float d[3])
{
    assert(axes != NULL && k >= 1);
    uint32_t best = 0;
    float bd = v3_dot(axes, d);
    for (uint32_t c = 1; c < k; c++) {
        float t = v3_dot(axes + 3 * c, d);
        if (t > bd) {
            bd = t;
            best = c;
        }
    }
    return best;
}

mer_result merp_gv_jitter(const float lo[3], const float hi[3], float density, mer_rng *rng,
                          int (*keep)(const void *ctx, const float p[3]), const void *ctx,
                          float **pts, uint32_t *n, uint32_t *cap, mer_error *err)
{
    assert(lo != NULL && hi != NULL && density > 0.0f && rng != NULL && pts != NULL);
    float h = cbrtf(1.0f / density);
    uint32_t c[3];
    for (int a = 0; a < 3; a++)
        c[a] = (uint32_t)fmaxf(1.0f, ceilf((hi[a] - lo[a]) / h));
    for (uint32_t z = 0; z < c[2]; z++)
        for (uint32_t y = 0; y < c[1]; y++)
            for (uint32_t x = 0; x < c[0]; x++) {
                const uint32_t cell[3] = {x, y, z};
                float q[3];
                for (int a = 0; a < 3; a++)
                    q[a] = lo[a] + ((float)cell[a] + mer_rng_float(rng)) * h;
                if (keep != NULL && !keep(ctx, q))
                    continue;
                if (*n == *cap) {
                    uint32_t nc = *cap ? 2 * *cap : 1024;
                    if (!MERP_RESIZE(*pts, 3 * (size_t)nc))
                        return mer_error_set(err, MER_ERR_NOMEM, NULL,
                                             "out of memory for the graph's nodes");
                    *cap = nc;
                }
                memcpy(*pts + 3 * (size_t)*n, q, sizeof q);
                (*n)++;
            }
    return MER_OK;
}

/* The uniform grid of the points: cell per point, points sorted by cell (CSR). */
typedef struct grid {
    float lo[3], cell;
    uint32_t dim[3];
    uint32_t *start, *idx;
} grid;

static uint32_t cell_coord(const grid *gr, const float *p, int a)
{
    float f = floorf((p[a] - gr->lo[a]) / gr->cell);
    return f < 0.0f ? 0u : f >= (float)gr->dim[a] ? gr->dim[a] - 1 : (uint32_t)f;
}

static size_t cell_of(const grid *gr, const float *p)
{
    return cell_coord(gr, p, 0) +
           (size_t)gr->dim[0] * (cell_coord(gr, p, 1) + (size_t)gr->dim[1] * cell_coord(gr, p, 2));
}

static mer_result grid_build(grid *gr, const float *pos, uint32_t n, float cell, mer_error *err)
{
    float hi[3];
    for (int a = 0; a < 3; a++)
        gr->lo[a] = hi[a] = pos[a];
    for (uint32_t i = 1; i < n; i++)
        for (int a = 0; a < 3; a++) {
            gr->lo[a] = fminf(gr->lo[a], pos[3 * i + a]);
            hi[a] = fmaxf(hi[a], pos[3 * i + a]);
        }
    gr->cell = cell;
    size_t cells = 1;
    for (int a = 0; a < 3; a++) {
        gr->dim[a] = (uint32_t)((hi[a] - gr->lo[a]) / cell) + 1;
        cells *= gr->dim[a];
    }
    gr->start = merp_calloc(cells + 1, sizeof *gr->start);
    gr->idx = merp_malloc((n ? n : 1) * sizeof *gr->idx);
    if (gr->start == NULL || gr->idx == NULL)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the graph's grid");
    for (uint32_t i = 0; i < n; i++)
        gr->start[cell_of(gr, pos + 3 * (size_t)i) + 1]++;
    for (size_t c = 0; c < cells; c++)
        gr->start[c + 1] += gr->start[c];
    /* Filled in index order, so each cell lists its points by increasing index. */
    for (uint32_t i = 0; i < n; i++)
        gr->idx[gr->start[cell_of(gr, pos + 3 * (size_t)i)]++] = i;
    for (size_t c = cells; c > 0; c--)
        gr->start[c] = gr->start[c - 1];
    gr->start[0] = 0;
    return MER_OK;
}

/* Point i's nearest neighbour in each cone into best[] (UINT32_MAX: none). */
static void nearest_per_cone(const grid *gr, const float *pos, uint32_t i, const float *axes,
                             uint32_t k, float r2, uint32_t *best, float *bd)
{
    const float *p = pos + 3 * (size_t)i;
    for (uint32_t c = 0; c < k; c++) {
        best[c] = UINT32_MAX;
        bd[c] = r2;
    }
    uint32_t cc[3];
    for (int a = 0; a < 3; a++)
        cc[a] = cell_coord(gr, p, a);
    for (uint32_t z = cc[2] > 2 ? cc[2] - 2 : 0; z <= cc[2] + 2 && z < gr->dim[2]; z++)
        for (uint32_t y = cc[1] > 2 ? cc[1] - 2 : 0; y <= cc[1] + 2 && y < gr->dim[1]; y++)
            for (uint32_t x = cc[0] > 2 ? cc[0] - 2 : 0; x <= cc[0] + 2 && x < gr->dim[0]; x++) {
                size_t c = x + (size_t)gr->dim[0] * (y + (size_t)gr->dim[1] * z);
                for (uint32_t t = gr->start[c]; t < gr->start[c + 1]; t++) {
                    uint32_t j = gr->idx[t];
                    const float *q = pos + 3 * (size_t)j;
                    float d[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
                    float dd = v3_dot(d, d);
                    if (j == i || !(dd > 0.0f) || dd > r2)
                        continue;
                    uint32_t cone = merp_gv_cone_of(axes, k, d);
                    if (dd < bd[cone] || (dd == bd[cone] && j < best[cone])) {
                        bd[cone] = dd;
                        best[cone] = j;
                    }
                }
            }
}

static mer_result link_all(merp_gv_graph *g, const grid *gr, uint32_t k, float radius,
                           mer_error *err)
{
    float axes[3 * 64], bd[64];
    uint32_t best[64];
    assert(k <= 64);
    merp_gv_cone_axes(k, axes);
    size_t m = 0, cap = (size_t)g->n * 4 + 16;
    if (!MERP_RESIZE(g->to, cap))
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the graph's edges");
    for (uint32_t i = 0; i < g->n; i++) {
        g->start[i] = (uint32_t)m;
        nearest_per_cone(gr, g->pos, i, axes, k, radius * radius, best, bd);
        for (uint32_t c = 0; c < k; c++) {
            if (best[c] == UINT32_MAX)
                continue;
            if (m == cap) {
                cap *= 2;
                if (!MERP_RESIZE(g->to, cap))
                    return mer_error_set(err, MER_ERR_NOMEM, NULL,
                                         "out of memory for the graph's edges");
            }
            g->to[m++] = best[c];
        }
    }
    g->start[g->n] = (uint32_t)m;
    return MER_OK;
}

mer_result merp_gv_graph_link(merp_gv_graph *g, const float *pos, uint32_t n, uint32_t k,
                              float radius, mer_error *err)
{
    assert(g != NULL && (pos != NULL || n == 0) && k >= 1 && k <= 64 && radius > 0.0f);
    merp_gv_graph_free(g);
    g->n = n;
    g->pos = merp_malloc(3 * (size_t)(n ? n : 1) * sizeof *g->pos);
    g->start = merp_malloc(((size_t)n + 1) * sizeof *g->start);
    if (g->pos == NULL || g->start == NULL) {
        merp_gv_graph_free(g);
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the graph");
    }
    if (n > 0)
        memcpy(g->pos, pos, 3 * (size_t)n * sizeof *pos);
    g->start[0] = 0;
    if (n == 0)
        return MER_OK;
    grid gr = {0};
    mer_result rc = grid_build(&gr, g->pos, n, radius / 2.0f, err);
    if (rc == MER_OK)
        rc = link_all(g, &gr, k, radius, err);
    merp_free(gr.start);
    merp_free(gr.idx);
    if (rc != MER_OK)
        merp_gv_graph_free(g);
    return rc;
}
