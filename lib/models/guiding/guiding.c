/* meristem — the guiding-vector model of Xu & Mould 2015 (guiding.h) as a growth
 * model: the graph is built in the first step, and each step is one iteration:
 * least-cost paths from the tree (dijkstra.c), endpoints (endpoints.c), the
 * union of their paths onto the skeleton (tree.c). */
#include "config.h"

#include <assert.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/alloc.h"
#include "core/array.h"
#include "core/bytes.h"
#include "core/hash.h"
#include "models/guiding/guiding.h"

/* More graph nodes than this are refused: about 130 bytes each. */
#define GV_NODES_MAX 2000000.0

/* The box the graph covers, before the plants' first internodes stretch it: the
 * crown volume's box grown by a quarter on every side, down to the ground. */
static void domain(const mer_params *p, float lo[3], float hi[3])
{
    merp_gv_volume_box(p->marker_volume, p->marker_center, p->marker_size, lo, hi);
    for (int a = 0; a < 3; a++) {
        float grow = 0.25f * (hi[a] - lo[a]);
        lo[a] -= grow;
        hi[a] += grow;
    }
    if (p->ground_enabled)
        lo[1] = fmaxf(fminf(lo[1], p->ground), p->ground);
}

static mer_result gv_validate(const mer_params *p, mer_error *err)
{
    if (p->marker_volume == MER_VOLUME_NONE)
        return mer_error_set(err, MER_ERR_INVALID, "marker_volume",
                             "the guiding model grows in the crown volume: set marker_volume "
                             "(1 box .. 5 cone), or start from a gv- preset");
    float lo[3], hi[3];
    domain(p, lo, hi);
    double vol = 1.0;
    for (int a = 0; a < 3; a++)
        vol *= fmax((double)hi[a] - (double)lo[a], 0.0);
    double nodes = vol * (double)p->gv_density;
    if (nodes > GV_NODES_MAX)
        return mer_error_set(err, MER_ERR_LIMIT, "gv_density",
                             "the graph would have about %.0f nodes, more than %.0f; lower "
                             "gv_density or shrink the crown volume", nodes, GV_NODES_MAX);
    return MER_OK;
}

static mer_result gv_create(const mer_params *p, merp_model **out, mer_error *err)
{
    (void)p;
    assert(out != NULL);
    *out = merp_calloc(1, sizeof **out);
    if (*out == NULL)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the guiding model");
    return MER_OK;
}

static void gv_free(merp_model *m)
{
    if (m == NULL)
        return;
    merp_gv_graph_free(&m->graph);
    merp_gv_search_free(&m->search);
    void *arrays[] = {m->skid, m->g, m->hop, m->ends, m->path, m->src, m->src_g, m->src_hop};
    for (size_t i = 0; i < sizeof arrays / sizeof arrays[0]; i++)
        merp_free(arrays[i]);
    merp_free(m);
}

/* The per-node tree arrays for the graph's n nodes, nobody in the tree (those
 * of a build that ran out of memory before are dropped). */
static mer_result alloc_tree(merp_model *m, uint32_t n, mer_error *err)
{
    size_t c = n ? n : 1;
    merp_free(m->skid);
    merp_free(m->g);
    merp_free(m->hop);
    m->skid = merp_malloc(c * sizeof *m->skid);
    m->g = merp_calloc(3 * c, sizeof *m->g);
    m->hop = merp_calloc(c, sizeof *m->hop);
    if (m->skid == NULL || m->g == NULL || m->hop == NULL)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the guiding model");
    for (uint32_t i = 0; i < n; i++)
        m->skid[i] = MER_NO_NODE;
    return MER_OK;
}

static int keep_point(const void *ctx, const float p[3])
{
    return !merp_env_blocked(ctx, p);
}

/* The graph: the plants' first internodes' ends (the sources, guiding vector
 * up), then the jittered grid over the domain stretched to hold them. */
static mer_result build(merp_model *m, const merp_world *w, mer_error *err)
{
    const merp_skeleton *sk = w->sk;
    float lo[3], hi[3], *pts = NULL;
    uint32_t n = 0, cap = 0;
    domain(w->p, lo, hi);
    mer_result rc = MER_OK;
    for (uint32_t k = 0; k < sk->nplants && rc == MER_OK; k++) {
        uint32_t r = sk->roots[k];
        if (!sk->alive[r])
            continue;
        if (n == cap && !MERP_RESIZE(pts, 3 * (size_t)(cap = cap ? 2 * cap : 16)))
            rc = mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the graph");
        else {
            merp_skel_node_end(sk, r, pts + 3 * (size_t)n++);
            for (int a = 0; a < 3; a++) {
                lo[a] = fminf(lo[a], pts[3 * (size_t)(n - 1) + a]);
                hi[a] = fmaxf(hi[a], pts[3 * (size_t)(n - 1) + a]);
            }
        }
    }
    uint32_t roots = n;
    if (rc == MER_OK)
        rc = merp_gv_jitter(lo, hi, w->p->gv_density, w->rng, keep_point, w->env, &pts, &n, &cap,
                            err);
    float h = cbrtf(1.0f / w->p->gv_density);
    if (rc == MER_OK)
        rc = merp_gv_graph_link(&m->graph, pts, n, w->p->gv_cones, 2.0f * h, err);
    merp_free(pts);
    if (rc == MER_OK)
        rc = alloc_tree(m, n, err);
    if (rc != MER_OK)
        return rc;
    for (uint32_t i = 0, k = 0; i < roots; k++)
        if (sk->alive[sk->roots[k]]) {
            m->skid[i] = sk->roots[k];
            m->g[3 * (size_t)i + 1] = 1.0f;
            i++;
        }
    m->built = 1;
    return MER_OK;
}

/* The tree's nodes as the search's sources. */
static mer_result gather_sources(merp_model *m, uint32_t *ns, mer_error *err)
{
    *ns = 0;
    for (uint32_t i = 0; i < m->graph.n; i++) {
        if (m->skid[i] == MER_NO_NODE)
            continue;
        if (*ns == m->src_cap) {
            uint32_t c = m->src_cap ? 2 * m->src_cap : 256;
            if (!MERP_RESIZE(m->src, c) || !MERP_RESIZE(m->src_g, 3 * (size_t)c) ||
                !MERP_RESIZE(m->src_hop, c))
                return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the sources");
            m->src_cap = c;
        }
        m->src[*ns] = i;
        memcpy(m->src_g + 3 * (size_t)*ns, m->g + 3 * (size_t)i, 3 * sizeof *m->g);
        m->src_hop[*ns] = m->hop[i];
        (*ns)++;
    }
    return MER_OK;
}

/* 1 when no step will grow more: the iterations, or the endpoint total, are done. */
static int gv_finished(const merp_model *m, const mer_params *p)
{
    return m->iteration >= p->gv_iterations ||
           (p->gv_endpoints_total > 0 && m->endpoints >= p->gv_endpoints_total);
}

/* The endpoints the next iteration asks for (guiding.h): with a total, the first
 * iteration's capped by it and a later one's share of what is left. */
static uint32_t wanted(const merp_model *m, const mer_params *p)
{
    uint32_t total = p->gv_endpoints_total;
    if (total == 0)
        return m->iteration == 0 ? p->gv_early_endpoints : p->gv_endpoints;
    uint32_t left = total - m->endpoints; /* > 0: not finished */
    if (m->iteration == 0)
        return left < p->gv_early_endpoints ? left : p->gv_early_endpoints;
    uint32_t its = p->gv_iterations - m->iteration; /* >= 1: not finished */
    return left / its + (left % its != 0);
}

static mer_result gv_step(merp_model *m, const merp_world *w, mer_error *err)
{
    assert(m != NULL && w != NULL);
    if (gv_finished(m, w->p))
        return MER_OK;
    mer_result rc = m->built ? MER_OK : build(m, w, err);
    uint32_t ns = 0, nends = 0, grown;
    if (rc == MER_OK)
        rc = gather_sources(m, &ns, err);
    if (rc != MER_OK || ns == 0)
        return rc;
    merp_gv_guide gd = merp_gv_guide_of(w->p);
    rc = merp_gv_dijkstra(&m->search, &m->graph, &gd, m->src, m->src_g, m->src_hop, ns, err);
    if (rc == MER_OK)
        rc = merp_gv_endpoints(w->p, m->iteration, &m->graph, &m->search, m->skid,
                               m->graph.pos + 3 * (size_t)m->src[0], wanted(m, w->p), w->rng,
                               &m->ends, &nends, &m->ends_cap, err);
    if (rc == MER_OK)
        rc = merp_gv_grow_paths(m, w, m->ends, nends, &grown, err);
    if (rc == MER_OK) {
        m->iteration++;
        m->endpoints += nends;
    }
    return rc;
}

/* A pruned node leaves the tree; a bent one stays (its children follow its end). */
static void gv_nodes_changed(merp_model *m, const merp_world *w)
{
    for (uint32_t i = 0; i < m->graph.n; i++)
        if (m->skid[i] != MER_NO_NODE && !w->sk->alive[m->skid[i]])
            m->skid[i] = MER_NO_NODE;
}

static uint64_t gv_hash(const merp_model *m, uint64_t h)
{
    h = merp_fnv_u32le(h, m->iteration);
    h = merp_fnv_u32le(h, m->endpoints);
    h = merp_fnv_u32le(h, m->graph.n);
    if (m->graph.n > 0) {
        h = merp_fnv(h, m->graph.pos, 3 * (size_t)m->graph.n * sizeof *m->graph.pos);
        h = merp_fnv(h, m->skid, m->graph.n * sizeof *m->skid);
    }
    return h;
}

static void gv_save(const merp_model *m, merp_bytes_out *out)
{
    const merp_gv_graph *g = &m->graph;
    uint32_t n = m->built ? g->n : 0, e = m->built ? g->start[n] : 0;
    merp_put_u32(out, (uint32_t)m->built);
    merp_put_u32(out, m->iteration);
    merp_put_u32(out, m->endpoints);
    merp_put_u32(out, n);
    merp_put_u32(out, e);
    if (!m->built)
        return;
    merp_put(out, g->pos, 3 * (size_t)n * sizeof *g->pos);
    merp_put(out, g->start, ((size_t)n + 1) * sizeof *g->start);
    merp_put(out, g->to, (size_t)e * sizeof *g->to);
    merp_put(out, m->skid, (size_t)n * sizeof *m->skid);
    merp_put(out, m->g, 3 * (size_t)n * sizeof *m->g);
    merp_put(out, m->hop, (size_t)n * sizeof *m->hop);
}

/* Checks what a checkpoint gave: edges in order and in range, tree nodes known. */
static int loaded_ok(const merp_model *m, uint32_t nodes)
{
    const merp_gv_graph *g = &m->graph;
    if (g->start[0] != 0)
        return 0;
    for (uint32_t i = 0; i < g->n; i++) {
        if (g->start[i + 1] < g->start[i] || (m->skid[i] != MER_NO_NODE && m->skid[i] >= nodes))
            return 0;
    }
    for (uint32_t t = 0; t < g->start[g->n]; t++)
        if (g->to[t] >= g->n)
            return 0;
    return 1;
}

static mer_result gv_load(merp_bytes_in *in, uint32_t nodes, merp_model **out, mer_error *err)
{
    mer_result rc = gv_create(NULL, out, err);
    if (rc != MER_OK)
        return rc;
    merp_model *m = *out;
    m->built = (int)merp_get_u32(in);
    m->iteration = merp_get_u32(in);
    m->endpoints = merp_get_u32(in);
    uint32_t n = merp_get_u32(in), e = merp_get_u32(in);
    if (m->built) {
        merp_gv_graph *g = &m->graph;
        g->n = n;
        if (MERP_GET_ARRAY(in, g->pos, 3 * (size_t)n) &&
            MERP_GET_ARRAY(in, g->start, (size_t)n + 1) && MERP_GET_ARRAY(in, g->to, e) &&
            MERP_GET_ARRAY(in, m->skid, n) && MERP_GET_ARRAY(in, m->g, 3 * (size_t)n))
            MERP_GET_ARRAY(in, m->hop, n);
        if (!in->bad && (g->start[n] != e || !loaded_ok(m, nodes)))
            in->bad = 1;
    }
    if (in->bad || m->built > 1) {
        int oom = in->bad == 2;
        gv_free(m);
        *out = NULL;
        return oom ? mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the guiding model")
                   : mer_error_set(err, MER_ERR_FORMAT, NULL, "damaged guiding-model state");
    }
    return MER_OK;
}

static mer_result gv_clone(const merp_model *m, merp_model **out, mer_error *err)
{
    merp_bytes_out b = {0};
    gv_save(m, &b);
    mer_result rc;
    if (b.oom)
        rc = mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the guiding model");
    else {
        merp_bytes_in in = {.p = b.buf, .n = b.n};
        rc = gv_load(&in, UINT32_MAX, out, err);
    }
    merp_free(b.buf);
    return rc;
}

static size_t gv_stats(const merp_model *m, mer_model_stat *out, size_t cap)
{
    uint32_t tree = 0;
    for (uint32_t i = 0; i < m->graph.n; i++)
        tree += m->skid[i] != MER_NO_NODE;
    const double v[] = {m->iteration, m->endpoints, m->graph.n,
                        m->built ? m->graph.start[m->graph.n] : 0, tree};
    static const char *const names[] = {"iteration", "endpoints", "graph_nodes", "graph_edges",
                                        "tree_nodes"};
    size_t n = sizeof v / sizeof v[0];
    for (size_t i = 0; i < n && i < cap; i++) {
        snprintf(out[i].name, sizeof out[i].name, "%s", names[i]);
        out[i].value = v[i];
    }
    return n;
}

const merp_model_ops merp_guiding_ops = {
    .name = "guiding",
    .param_rows = MERP_ROWS_GUIDING,
    .state_version = 1,
    .validate = gv_validate,
    .create = gv_create,
    /* No set_params: each step reads w->p (the graph, once built, stays). */
    .step = gv_step,
    .nodes_changed = gv_nodes_changed,
    .hash = gv_hash,
    .clone = gv_clone,
    .save = gv_save,
    .load = gv_load,
    .free = gv_free,
    .stats = gv_stats,
    .finished = gv_finished,
};
