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
 * the terminal bud last) into pq, pbuds, ptarget, from the axis records. */
static mer_result list_axis(merp_model *m, uint32_t b, size_t *count, uint32_t *terminal,
                            mer_error *err)
{
    const merp_p09_axnode *ax = m->ax;
    size_t n = 0;
    *terminal = UINT32_MAX;
    for (uint32_t j = b;;) {
        mer_result rc = reserve_items(m, n + 3, err);
        if (rc != MER_OK)
            return rc;
        const merp_p09_axnode *a = ax + j;
        for (uint32_t k = 0; k < 2; k++) {
            uint32_t c = a->child[k];
            if (c != MER_NO_NODE) {
                m->pq[n] = a->q[k];
                m->pbuds[n] = a->buds[k];
                m->ptarget[n++] = c | MERP_BRANCH_FLAG;
            } else if (a->buds[k] != 0) {
                m->pq[n] = a->q[k];
                m->pbuds[n] = 1;
                m->ptarget[n++] = 3 * j + k + 1;
            }
        }
        if (a->next >= MERP_AX_TIP) {
            if (a->next == MERP_AX_TIP_BUD) {
                *terminal = (uint32_t)n;
                m->pq[n] = a->q_tip;
                m->pbuds[n] = 1;
                m->ptarget[n++] = 3 * j;
            }
            break;
        }
        j = a->next;
    }
    *count = n;
    return MER_OK;
}

/* Nothing to share along the axis based at b: every item's share is 0 (v · qw / Σ
 * with finite light), so its branches get 0 and its buds keep the 0 the
 * environment gave them, without listing and sorting. */
static void zero_axis(merp_model *m, uint32_t b)
{
    const merp_p09_axnode *ax = m->ax;
    for (uint32_t j = b;; j = ax[j].next) {
        for (uint32_t k = 0; k < 2; k++)
            if (ax[j].child[k] != MER_NO_NODE)
                m->vin[ax[j].child[k]] = 0.0f;
        if (ax[j].next >= MERP_AX_TIP)
            break;
    }
}

/* How many nodes ahead of the allocation the axis records are fetched. */
#define AHEAD 32

/* Whether node b is alive and the base of an axis. */
static int is_axis_base(const merp_skeleton *sk, uint32_t b)
{
    return sk->alive[b] && (sk->parent[b] == MER_NO_NODE || sk->slot[b] != 0);
}

/* Axes are visited by the id of their base node, so an axis is always allocated
 * before the branches it supports. The axis records (m->ax) are the basipetal
 * pass's of this round. A lateral branch without light (a crown's deep shade)
 * gets 0 whatever its axis is given, and so does every branch it bears: its v is
 * set and its axis left unlisted. */
mer_result merp_p09_allocate_priority(merp_model *m, const merp_world *w, mer_error *err)
{
    assert(m != NULL && w != NULL && m->n == w->sk->n);
    const merp_skeleton *sk = w->sk;
    const mer_params *p = w->p;
    for (uint32_t b = 0; b < sk->n; b++) {
        /* An axis's second node lies far from its base (grown in a later step):
         * fetch it while earlier axes are allocated. */
        uint32_t ahead = b + AHEAD;
        if (ahead < sk->n && is_axis_base(sk, ahead) && m->ax[ahead].next < MERP_AX_TIP)
            __builtin_prefetch(m->ax + m->ax[ahead].next);
        if (!is_axis_base(sk, b))
            continue;
        int root = sk->parent[b] == MER_NO_NODE;
        if (!root && sk->q[b] == 0.0f) {
            m->vin[b] = 0.0f;
            continue;
        }
        float v = root ? p->alpha * sk->q[b] : m->vin[b];
        if (v == 0.0f) {
            zero_axis(m, b);
            continue;
        }
        size_t n;
        uint32_t terminal;
        mer_result rc = list_axis(m, b, &n, &terminal, err);
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
