/* meristem — priority model allocation, the acropetal pass over whole axes (P09
 * §4.2, Fig. 8b): the buds and branches along an axis are ranked by light per
 * bud and weighted by the Fig. 8c function, with apical control on schedule. */
#include "config.h"

#include <assert.h>

#include <meristem/fate.h>

#include "core/array.h"
#include "models/p09/p09.h"

/* Room for `items` listed items and for one axis's `longest` list. */
static mer_result reserve(merp_model *m, size_t items, size_t longest, mer_error *err)
{
    if (items > m->icap) {
        size_t cap = items + items / 2 + 16;
        if (!MERP_RESIZE(m->pq, cap) || !MERP_RESIZE(m->pbuds, cap) ||
            !MERP_RESIZE(m->ptarget, cap))
            return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the priority lists");
        m->icap = cap;
    }
    if (longest > m->pcap) {
        size_t cap = longest * 2 + 16;
        if (!MERP_RESIZE(m->pv, cap) || !MERP_RESIZE(m->prank, cap) || !MERP_RESIZE(m->pscr, cap))
            return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the priority lists");
        m->pcap = cap;
    }
    return MER_OK;
}

/* How many nodes ahead of a pass the values it will read are fetched. */
#define AHEAD 32

/* Whether node i (alive) is the base of an axis. */
static int is_axis_base(const merp_skeleton *sk, uint32_t i)
{
    return sk->parent[i] == MER_NO_NODE || sk->slot[i] != 0;
}

/* The aend of an axis that is not allocated: a lateral one without light. */
#define UNLISTED UINT32_MAX

/* Lists the branches and buds along every axis (lateral ones node by node from
 * base to tip, the terminal bud last) into pq, pbuds, ptarget, one list after
 * another in the order of the axes' bases, and those bases into abase. One pass
 * over the nodes in id order: along an axis ids rise from base to tip (a node's
 * main child is grown after it), so a node's items go where its axis's list
 * ends less the items from it to the tip (sub[].afrom, the basipetal pass's) — the
 * axis's end found at its base and handed up it (aend). Walking each axis from
 * its base instead would jump to a far record at every shoot, each jump waiting
 * on the one before. A lateral axis without light is not allocated (see below),
 * so nothing of it is listed. */
static void list_axes(merp_model *m, const merp_skeleton *sk)
{
    const merp_p09_axnode *ax = m->ax;
    uint32_t run = 0, nb = 0;
    for (uint32_t i = 0; i < sk->n; i++) {
        uint32_t ahead = i + AHEAD;
        if (ahead < sk->n && sk->parent[ahead] != MER_NO_NODE) {
            __builtin_prefetch(m->aend + sk->parent[ahead]);
            __builtin_prefetch(sk->child + 3 * (size_t)sk->parent[ahead]);
        }
        if (!sk->alive[i])
            continue;
        uint32_t end;
        if (is_axis_base(sk, i)) {
            m->abase[nb++] = i;
            int lit = sk->parent[i] == MER_NO_NODE || sk->q[i] != 0.0f;
            end = lit ? (run += m->sub[i].afrom) : UNLISTED;
        } else {
            /* on its parent's axis, as the basipetal pass counted it: the
             * parent lists it first (the skeleton's invariant) */
            uint32_t p = sk->parent[i];
            assert(sk->child[3 * (size_t)p] == i); /* asked for AHEAD nodes back */
            end = m->aend[p];
        }
        m->aend[i] = end;
        if (end == UNLISTED)
            continue;
        uint32_t t = end - m->sub[i].afrom;
        const merp_p09_axnode *a = ax + i;
        for (uint32_t k = 0; k < 2; k++) {
            uint32_t c = a->child[k];
            if (c != MER_NO_NODE) {
                m->pq[t] = a->q[k];
                m->pbuds[t] = a->buds[k];
                m->ptarget[t++] = c | MERP_BRANCH_FLAG;
            } else if (a->buds[k] != 0) {
                m->pq[t] = a->q[k];
                m->pbuds[t] = 1;
                m->ptarget[t++] = 3 * i + k + 1;
            }
        }
        if (a->next == MERP_AX_TIP_BUD) {
            m->pq[t] = a->q_tip;
            m->pbuds[t] = 1;
            m->ptarget[t] = 3 * i;
        }
    }
    m->abase_n = nb;
}

/* Below this resource an axis makes no metamer anywhere: see below. */
#define NO_SHOOT 0.5f

/* Axes are visited by the id of their base node, so an axis is always allocated
 * before the branches it supports. The axis records (m->ax) are the basipetal
 * pass's of this round. A lateral branch without light (a crown's deep shade)
 * gets 0 whatever its axis is given, and so does every branch it bears: its v is
 * set and its axis left unallocated. An axis given less than half a metamer's
 * resource (most of a big crown's: 68 % of table1-left's lists) gives its
 * branches 0 and its buds keep the 0 the environment gave them, without a sort:
 * no bud of it or of the branches it bears could grow. Each share is
 * v · qw / Σ with qw ≤ Σ (a float sum of terms ≥ 0 is at least each term), so
 * in floats it is at most v (1 + 2⁻²³)²: from v < 0.5 down a branch order at
 * a time, a share would need some 2²¹ orders to reach 1. n = ⌊v⌋ is 0 for all
 * of them either way; only the round's record of their v (m->vin, m->vb: a
 * checkpoint's model state, read by no later round) says 0, not a fraction. */
mer_result merp_p09_allocate_priority(merp_model *m, const merp_world *w, mer_error *err)
{
    assert(m != NULL && w != NULL && m->n == w->sk->n);
    const merp_skeleton *sk = w->sk;
    const mer_params *p = w->p;
    /* at most three items a node; the longest list is one axis of every node */
    mer_result rc = reserve(m, 3 * (size_t)sk->n, 0, err);
    if (rc != MER_OK)
        return rc;
    list_axes(m, sk);
    for (uint32_t x = 0; x < m->abase_n; x++) {
        if (x + AHEAD < m->abase_n) {
            uint32_t ahead = m->abase[x + AHEAD];
            __builtin_prefetch(sk->q + ahead);
            __builtin_prefetch(m->vin + ahead);
        }
        uint32_t b = m->abase[x];
        int root = sk->parent[b] == MER_NO_NODE;
        if (!root && sk->q[b] == 0.0f) {
            m->vin[b] = 0.0f;
            continue;
        }
        float v = root ? p->alpha * sk->q[b] : m->vin[b];
        uint32_t n = m->sub[b].afrom, first = m->aend[b] - n;
        const uint32_t *target = m->ptarget + first;
        if (!(v >= NO_SHOOT)) {
            for (uint32_t t = 0; t < n; t++)
                if (target[t] & MERP_BRANCH_FLAG)
                    m->vin[target[t] & ~MERP_BRANCH_FLAG] = 0.0f;
            continue;
        }
        if (n == 0)
            continue;
        rc = reserve(m, 0, n, err);
        if (rc != MER_OK)
            return rc;
        /* the terminal bud, when the axis has one, is its list's last item */
        uint32_t last = target[n - 1];
        uint32_t terminal = !(last & MERP_BRANCH_FLAG) && last % 3 == 0 ? n - 1 : UINT32_MAX;
        int apical = mer_params_apical_at(p, w->step, sk->order[b]);
        mer_priority_allocate(v, n, m->pq + first, m->pbuds + first, terminal, apical, NULL,
                              p->w_max, p->w_min, p->kappa, m->prank, m->pscr, m->pv);
        for (uint32_t t = 0; t < n; t++) {
            uint32_t tg = target[t];
            if (tg & MERP_BRANCH_FLAG)
                m->vin[tg & ~MERP_BRANCH_FLAG] = m->pv[t];
            else
                m->vb[tg] = m->pv[t];
        }
    }
    return MER_OK;
}
