/* meristem — priority model allocation, the acropetal pass over whole axes (P09
 * §4.2, Fig. 8b): the buds and branches along an axis are ranked by light per
 * bud and weighted by the Fig. 8c function, with apical control on schedule. */
#include "config.h"

#include <assert.h>

#include <meristem/fate.h>

#include "core/array.h"
#include "models/p09/p09.h"

static mer_result reserve_items(merp_model *m, size_t want, mer_error *err)
{
    if (want <= m->pcap)
        return MER_OK;
    size_t cap = want * 2 + 16;
    if (!MERP_RESIZE(m->pq, cap) || !MERP_RESIZE(m->pv, cap) || !MERP_RESIZE(m->pbuds, cap) ||
        !MERP_RESIZE(m->prank, cap) || !MERP_RESIZE(m->pscr, cap) ||
        !MERP_RESIZE(m->ptarget, cap))
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the priority lists");
    m->pcap = cap;
    return MER_OK;
}

/* Lists the branches and buds along the axis based at b (lateral ones node by node,
 * the terminal bud last) into pq, pbuds, ptarget. */
static mer_result list_axis(merp_model *m, const merp_world *w, uint32_t b, size_t *count,
                            uint32_t *terminal, mer_error *err)
{
    const merp_skeleton *sk = w->sk;
    uint32_t bpn = w->p->buds_per_node;
    size_t n = 0;
    *terminal = UINT32_MAX;
    for (uint32_t j = b;;) {
        mer_result rc = reserve_items(m, n + 3, err);
        if (rc != MER_OK)
            return rc;
        for (uint32_t k = 1; k < 3; k++) {
            uint32_t c = sk->child[3 * j + k];
            if (c != MER_NO_NODE) {
                m->pq[n] = sk->q[c];
                m->pbuds[n] = m->nbuds[c];
                m->ptarget[n++] = c | MERP_BRANCH_FLAG;
            } else if (merp_skel_bud_exists(sk, j, k, bpn)) {
                m->pq[n] = m->qb[3 * j + k];
                m->pbuds[n] = 1;
                m->ptarget[n++] = 3 * j + k;
            }
        }
        uint32_t next = sk->child[3 * j];
        if (next == MER_NO_NODE) {
            if (merp_skel_bud_exists(sk, j, 0, bpn)) {
                *terminal = (uint32_t)n;
                m->pq[n] = m->qb[3 * j];
                m->pbuds[n] = 1;
                m->ptarget[n++] = 3 * j;
            }
            break;
        }
        j = next;
    }
    *count = n;
    return MER_OK;
}

/* Nothing to share along the axis based at b (a crown's deep shade): every
 * item's share is 0 (v · qw / Σ with finite light), so its branches get 0 and its
 * buds keep the 0 the environment gave them, without listing and sorting. */
static void zero_axis(merp_model *m, const merp_skeleton *sk, uint32_t b)
{
    for (uint32_t j = b;; j = sk->child[3 * j]) {
        for (uint32_t k = 1; k < 3; k++)
            if (sk->child[3 * j + k] != MER_NO_NODE)
                m->vin[sk->child[3 * j + k]] = 0.0f;
        if (sk->child[3 * j] == MER_NO_NODE)
            break;
    }
}

/* Axes are visited by the id of their base node, so an axis is always allocated
 * before the branches it supports. */
mer_result merp_p09_allocate_priority(merp_model *m, const merp_world *w, mer_error *err)
{
    assert(m != NULL && w != NULL && m->n == w->sk->n);
    const merp_skeleton *sk = w->sk;
    const mer_params *p = w->p;
    for (uint32_t b = 0; b < sk->n; b++) {
        if (!sk->alive[b] || (sk->parent[b] != MER_NO_NODE && sk->slot[b] == 0))
            continue;
        float v = sk->parent[b] == MER_NO_NODE ? p->alpha * sk->q[b] : m->vin[b];
        if (v == 0.0f) {
            zero_axis(m, sk, b);
            continue;
        }
        size_t n;
        uint32_t terminal;
        mer_result rc = list_axis(m, w, b, &n, &terminal, err);
        if (rc != MER_OK)
            return rc;
        if (n == 0)
            continue;
        int apical = mer_params_apical_at(p, w->step, sk->order[b]);
        mer_priority_allocate(v, (uint32_t)n, m->pq, m->pbuds, terminal, apical, NULL, p->w_max,
                              p->w_min, p->kappa, m->prank, m->pscr, m->pv);
        for (size_t t = 0; t < n; t++) {
            uint32_t tg = m->ptarget[t];
            if (tg & MERP_BRANCH_FLAG)
                m->vin[tg & ~MERP_BRANCH_FLAG] = m->pv[t];
            else
                m->vb[tg] = m->pv[t];
        }
    }
    return MER_OK;
}
