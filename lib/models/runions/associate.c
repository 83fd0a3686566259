/* meristem — R07's association (Runions et al. 2007, §3): each attraction point
 * influences the closest tree node within the radius of influence d_i, and is
 * removed once a node is within the kill distance d_k. The closest node is found
 * through a uniform grid of the node ends (counting sort into cells, in id order),
 * so a point looks at the nodes of a few cells, not at every node; and only the
 * points the marker grid files near a node end are looked at, not every point. */
#include "config.h"

#include <assert.h>
#include <math.h>
#include <string.h>

#include "core/array.h"
#include "env/markers_near.h"
#include "models/runions/runions.h"

#define NONE UINT32_MAX

typedef struct grid {
    float lo[3], hi[3], inv;
    int dim[3];
    size_t cells, n;
} grid;

/* The box of the live node ends, and a cell edge of at least d_i that keeps the
 * cells to a few per node however far apart the plants stand. */
static void grid_shape(const merp_skeleton *sk, float d_i, grid *g)
{
    for (int a = 0; a < 3; a++) {
        g->lo[a] = INFINITY;
        g->hi[a] = -INFINITY;
    }
    g->n = 0;
    for (uint32_t i = 0; i < sk->n; i++) {
        if (!sk->alive[i])
            continue;
        float e[3];
        merp_skel_node_end(sk, i, e);
        for (int a = 0; a < 3; a++) {
            g->lo[a] = fminf(g->lo[a], e[a]);
            g->hi[a] = fmaxf(g->hi[a], e[a]);
        }
        g->n++;
    }
    if (g->n == 0)
        for (int a = 0; a < 3; a++)
            g->lo[a] = g->hi[a] = 0.0f;
    double cell = (double)d_i, cap = 4.0 * (double)g->n + 64.0, cells;
    for (;;) {
        cells = 1.0;
        for (int a = 0; a < 3; a++)
            cells *= floor(((double)g->hi[a] - (double)g->lo[a]) / cell) + 1.0;
        if (cells <= cap)
            break;
        cell *= 2.0;
    }
    g->inv = (float)(1.0 / cell);
    for (int a = 0; a < 3; a++)
        g->dim[a] = (int)(floor(((double)g->hi[a] - (double)g->lo[a]) / cell) + 1.0);
    g->cells = (size_t)cells;
}

static int coord(const grid *g, float x, int a)
{
    float f = floorf((x - g->lo[a]) * g->inv);
    if (!(f >= 0.0f))
        return 0;
    return f >= (float)g->dim[a] ? g->dim[a] - 1 : (int)f;
}

static size_t cell_of(const grid *g, const float p[3])
{
    return ((size_t)coord(g, p[2], 2) * (size_t)g->dim[1] + (size_t)coord(g, p[1], 1)) *
               (size_t)g->dim[0] +
           (size_t)coord(g, p[0], 0);
}

/* The live node ends into cells: m->start (CSR), m->gid and m->gp. */
static mer_result grid_build(merp_model *m, const merp_skeleton *sk, const grid *g,
                             mer_error *err)
{
    if (g->cells + 1 > m->start_cap) {
        if (!MERP_RESIZE(m->start, g->cells + 1))
            return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the node grid");
        m->start_cap = g->cells + 1;
    }
    if (g->n > m->grid_cap) {
        if (!MERP_RESIZE(m->gid, g->n) || !MERP_RESIZE(m->gp, 3 * g->n))
            return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the node grid");
        m->grid_cap = g->n;
    }
    memset(m->start, 0, (g->cells + 1) * sizeof *m->start);
    float e[3];
    for (uint32_t i = 0; i < sk->n; i++)
        if (sk->alive[i]) {
            merp_skel_node_end(sk, i, e);
            m->start[cell_of(g, e) + 1]++;
        }
    for (size_t c = 0; c < g->cells; c++)
        m->start[c + 1] += m->start[c];
    for (uint32_t i = 0; i < sk->n; i++)
        if (sk->alive[i]) {
            merp_skel_node_end(sk, i, e);
            uint32_t t = m->start[cell_of(g, e)]++;
            m->gid[t] = i;
            memcpy(m->gp + 3 * t, e, sizeof e);
        }
    for (size_t c = g->cells; c > 0; c--)
        m->start[c] = m->start[c - 1];
    m->start[0] = 0;
    return MER_OK;
}

/* The closest node that may grow within d_i of p (NONE if none, ties to the
 * lower id) and its squared distance; 1 when some live node is within d_k. */
static int closest(const merp_model *m, const grid *g, const float p[3], float d_i, float d_k,
                   uint32_t *best, float *best_d2)
{
    *best = NONE;
    for (int a = 0; a < 3; a++)
        if (p[a] < g->lo[a] - d_i || p[a] > g->hi[a] + d_i)
            return 0;
    int lo[3], hi[3];
    for (int a = 0; a < 3; a++) {
        lo[a] = coord(g, p[a] - d_i, a);
        hi[a] = coord(g, p[a] + d_i, a);
    }
    float ri2 = d_i * d_i, rk2 = d_k * d_k, bd2 = 0.0f;
    for (int z = lo[2]; z <= hi[2]; z++)
        for (int y = lo[1]; y <= hi[1]; y++)
            for (int x = lo[0]; x <= hi[0]; x++) {
                size_t c = ((size_t)z * (size_t)g->dim[1] + (size_t)y) * (size_t)g->dim[0] + (size_t)x;
                for (uint32_t t = m->start[c]; t < m->start[c + 1]; t++) {
                    const float *e = m->gp + 3 * t;
                    float dx = p[0] - e[0], dy = p[1] - e[1], dz = p[2] - e[2];
                    float d2 = dx * dx + dy * dy + dz * dz;
                    if (d2 <= rk2)
                        return 1;
                    uint32_t id = m->gid[t];
                    if (m->ok[id] && d2 <= ri2 &&
                        (*best == NONE || d2 < bd2 || (d2 == bd2 && id < *best))) {
                        *best = id;
                        bd2 = d2;
                    }
                }
            }
    *best_d2 = bd2;
    return 0;
}

mer_result merp_runions_associate(merp_model *m, const merp_skeleton *sk, mer_markers *mk,
                                  float d_i, float d_k, size_t *killed, mer_error *err)
{
    assert(m != NULL && sk != NULL && mk != NULL && killed != NULL);
    assert(m->node_cap >= sk->n && d_k > 0.0f && d_k < d_i);
    *killed = 0;
    grid g;
    grid_shape(sk, d_i, &g);
    mer_result rc = grid_build(m, sk, &g, err);
    if (rc != MER_OK)
        return rc;
    /* Only a point within d_i of a node can be killed or associated; the
     * margin covers the rounding of closest()'s squared distances. */
    size_t n;
    rc = merp_markers_near(mk, m->gp, g.n, d_i * 1.001f, &m->pts, &m->pts_cap, &n, err);
    if (rc != MER_OK)
        return rc;
    float *pts = m->pts;
    memset(m->sum, 0, 3 * (size_t)sk->n * sizeof *m->sum);
    memset(m->count, 0, (size_t)sk->n * sizeof *m->count);
    size_t k = 0;
    for (size_t j = 0; j < n; j++) {
        float *p = pts + 3 * j;
        uint32_t best;
        float d2;
        if (closest(m, &g, p, d_i, d_k, &best, &d2)) {
            float tmp[3];
            memcpy(tmp, pts + 3 * k, sizeof tmp);
            memcpy(pts + 3 * k, p, sizeof tmp);
            memcpy(p, tmp, sizeof tmp);
            k++;
            continue;
        }
        if (best == NONE)
            continue;
        float end[3], inv = 1.0f / sqrtf(d2);
        merp_skel_node_end(sk, best, end);
        for (int a = 0; a < 3; a++)
            m->sum[3 * best + a] += (p[a] - end[a]) * inv;
        m->count[best]++;
    }
    *killed = k;
    return MER_OK;
}
