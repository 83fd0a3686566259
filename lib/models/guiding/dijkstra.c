/* meristem — Dijkstra's least-cost paths of Xu & Mould 2015's second step
 * (guiding.h), with the edge costs computed lazily: a node's guiding vector is
 * fixed when it is opened (taken from the queue with its final cost), from its
 * parent's, and only then are the costs of its out-edges known. The queue is a
 * binary heap with lazy deletion; ties go to the lower node index, so the
 * result does not depend on the heap's history. */
#include "config.h"

#include <assert.h>
#include <math.h>
#include <string.h>

#include "core/alloc.h"
#include "core/array.h"
#include "models/guiding/guiding.h"

struct merp_gv_heap_entry {
    double d;
    uint32_t node;
};

void merp_gv_search_free(merp_gv_search *s)
{
    if (s == NULL)
        return;
    void *arrays[] = {s->dist, s->pred, s->hop, s->hsrc, s->g, s->done, s->heap};
    for (size_t i = 0; i < sizeof arrays / sizeof arrays[0]; i++)
        merp_free(arrays[i]);
    memset(s, 0, sizeof *s);
}

static int before(const struct merp_gv_heap_entry *a, const struct merp_gv_heap_entry *b)
{
    return a->d < b->d || (a->d == b->d && a->node < b->node);
}

static int push(merp_gv_search *s, double d, uint32_t node)
{
    if (s->heap_n == s->heap_cap) {
        size_t cap = s->heap_cap ? 2 * s->heap_cap : 1024;
        if (!MERP_RESIZE(s->heap, cap))
            return 0;
        s->heap_cap = cap;
    }
    struct merp_gv_heap_entry e = {d, node}, *h = s->heap;
    size_t i = s->heap_n++;
    while (i > 0 && before(&e, &h[(i - 1) / 2])) {
        h[i] = h[(i - 1) / 2];
        i = (i - 1) / 2;
    }
    h[i] = e;
    return 1;
}

static struct merp_gv_heap_entry pop(merp_gv_search *s)
{
    struct merp_gv_heap_entry *h = s->heap, top = h[0], last = h[--s->heap_n];
    size_t i = 0, n = s->heap_n;
    for (;;) {
        size_t c = 2 * i + 1;
        if (c >= n)
            break;
        if (c + 1 < n && before(&h[c + 1], &h[c]))
            c++;
        if (!before(&h[c], &last))
            break;
        h[i] = h[c];
        i = c;
    }
    if (n > 0)
        h[i] = last;
    return top;
}

static mer_result ensure(merp_gv_search *s, uint32_t n, mer_error *err)
{
    if (n <= s->cap)
        return MER_OK;
    if (!MERP_RESIZE(s->dist, n) || !MERP_RESIZE(s->pred, n) || !MERP_RESIZE(s->hop, n) ||
        !MERP_RESIZE(s->hsrc, n) || !MERP_RESIZE(s->g, 3 * (size_t)n) || !MERP_RESIZE(s->done, n))
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the path search");
    s->cap = n;
    return MER_OK;
}

/* Opens node u, reached from its predecessor: fixes its guiding vector. */
static void open_node(merp_gv_search *s, const merp_gv_graph *gr, const merp_gv_guide *gd,
                      uint32_t u)
{
    uint32_t p = s->pred[u];
    if (p == MER_NO_NODE)
        return; /* a source: its guiding vector is given */
    float e[3];
    for (int a = 0; a < 3; a++)
        e[a] = gr->pos[3 * (size_t)u + a] - gr->pos[3 * (size_t)p + a];
    s->hop[u] = s->hop[p] + 1;
    s->hsrc[u] = s->hsrc[p] + 1;
    if (gd->on)
        merp_gv_turn(gd, s->g + 3 * (size_t)p, e, s->hop[u], s->g + 3 * (size_t)u);
}

mer_result merp_gv_dijkstra(merp_gv_search *s, const merp_gv_graph *gr, const merp_gv_guide *gd,
                            const uint32_t *src, const float *src_g, const uint32_t *src_hop,
                            uint32_t ns, mer_error *err)
{
    assert(s != NULL && gr != NULL && gd != NULL && (ns == 0 || (src && src_g && src_hop)));
    mer_result rc = ensure(s, gr->n, err);
    if (rc != MER_OK)
        return rc;
    for (uint32_t i = 0; i < gr->n; i++) {
        s->dist[i] = (double)INFINITY;
        s->pred[i] = MER_NO_NODE;
        s->done[i] = 0;
    }
    s->heap_n = 0;
    for (uint32_t k = 0; k < ns; k++) {
        uint32_t i = src[k];
        assert(i < gr->n);
        s->dist[i] = 0.0;
        s->hop[i] = src_hop[k];
        s->hsrc[i] = 0;
        memcpy(s->g + 3 * (size_t)i, src_g + 3 * (size_t)k, 3 * sizeof *src_g);
        if (!push(s, 0.0, i))
            return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the path search");
    }
    while (s->heap_n > 0) {
        struct merp_gv_heap_entry top = pop(s);
        uint32_t u = top.node;
        if (s->done[u] || top.d > s->dist[u])
            continue;
        s->done[u] = 1;
        open_node(s, gr, gd, u);
        const float *pu = gr->pos + 3 * (size_t)u;
        for (uint32_t t = gr->start[u]; t < gr->start[u + 1]; t++) {
            uint32_t v = gr->to[t];
            if (s->done[v])
                continue;
            const float *pv = gr->pos + 3 * (size_t)v;
            const float e[3] = {pv[0] - pu[0], pv[1] - pu[1], pv[2] - pu[2]};
            double d = s->dist[u] + merp_gv_cost(gd, s->g + 3 * (size_t)u, e);
            if (d < s->dist[v] || (d == s->dist[v] && u < s->pred[v])) {
                s->dist[v] = d;
                s->pred[v] = u;
                if (!push(s, d, v))
                    return mer_error_set(err, MER_ERR_NOMEM, NULL,
                                         "out of memory for the path search");
            }
        }
    }
    return MER_OK;
}
