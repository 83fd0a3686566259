/* meristem — the self-organizing tree model of Palubicki et al. 2009 (P09), the
 * first growth model: its state and the passes of one round (P09 Fig. 3 right).
 * Not installed. The files of this folder follow the paper's parts:
 *   environment.c    environment input: Q and V of the buds that may grow (§4.1)
 *   p09.c            the round: environment, basipetal pass, shedding, fate, shoots
 *   borchert_honda.c extended Borchert-Honda allocation (§4.2, Fig. 8a)
 *   priority.c       priority model allocation (§4.2, Fig. 8b)
 *   fate.c           the BH and priority kernels (public: meristem/fate.h)
 *   schedule.c       apical control, λ and η over time (Fig. 10, 11, 13, 20)
 *   shoot.c          new shoots: phyllotaxis and tropism (§4.3)
 *   shedding.c       shedding branches that do not pay (§4.4)
 *   params_p09.c     the checks across P09's parameters */
#ifndef MERISTEM_P09_H
#define MERISTEM_P09_H

#include <stddef.h>
#include <stdint.h>

#include "models/model.h"

#define MERP_BRANCH_FLAG UINT32_C(0x80000000)

/* The `next` of an axis node at the tip of its axis: with a terminal bud, without. */
#define MERP_AX_TIP_BUD UINT32_C(0xFFFFFFFF)
#define MERP_AX_TIP UINT32_C(0xFFFFFFFE)

/* One node's part of its axis's list for the priority model (P09 Fig. 8b), as
 * the basipetal pass leaves it: what list_axis needs of the node in one record,
 * so walking an axis reads one record a node rather than the skeleton's and the
 * model's arrays at the node and at each lateral branch. */
typedef struct merp_p09_axnode {
    uint32_t next;      /* the main child, or MERP_AX_TIP_BUD / MERP_AX_TIP */
    uint32_t child[2];  /* lateral slots 1, 2: the branch, or MER_NO_NODE */
    uint32_t buds[2];   /* the branch's living buds; else 1 for a bud, 0 for none */
    float q[2];         /* the branch's light Q, or the bud's */
    float q_tip;        /* the terminal bud's Q (at a tip with one) */
} merp_p09_axnode;

/* What the basipetal pass reads of a node at its parent, in one record: a
 * lateral child lies far from its parent (grown steps later), and one cache
 * line read there beats three. */
typedef struct merp_p09_sub {
    float q;          /* the subtree's light Q (a copy of sk->q) */
    uint32_t nbuds;   /* eligible buds in the subtree */
    uint32_t nint;    /* live internodes in the subtree */
    uint32_t afrom;   /* priority model: the items listed from the node to its axis's tip */
} merp_p09_sub;

struct merp_model {
    /* Per node, for the nodes [0, n) seen so far (p09_sync gives new ones their
     * starting values); the subtree light Q lives in the skeleton (sk->q). */
    uint32_t n, cap;
    merp_p09_sub *sub; /* the subtree's counts, last pass */
    float *vin;        /* resource entering the node, last pass (0 where none could grow) */
    float *qb, *vb;    /* 3 per node: Q and v of each bud, last pass */
    uint32_t *quiet;   /* 3 per node: epoch + 1 when the bud's marker neighbourhood was empty */
    uint8_t *mark;     /* scratch: under the brush constraint */
    /* scratch under shadow propagation: the voxel of each node's end (its buds'),
     * cell[0, cell_n), kept while the environment's epoch (cell_epoch − 1) stays */
    uint32_t *cell;
    uint32_t cell_n, cell_cap, cell_epoch;

    /* per-round scratch: the buds that may grow, bkey[bfirst, bfirst + bn) */
    uint32_t *bkey;    /* 3·node + slot */
    float *bpos, *bdir, *bq, *bv;
    uint8_t *bquiet;
    size_t bn, bcap, bfirst;
    int v_deferred;    /* bv is not computed yet (merp_p09_directions) */
    /* the buds' Q is left to the basipetal pass (shadow propagation while V
     * waits), read from this view of the grid; lit_every: no bud held back */
    int lit_pending, lit_every, lit_syllepsis;
    merp_light light;
    /* per-round scratch under the priority model, [0, n): each node's axis
     * record; where the items from the node to its axis's tip (sub[].afrom) end
     * in the round's lists (aend); the axes' bases in id order, abase[0, abase_n) */
    merp_p09_axnode *ax;
    uint32_t *aend, *abase;
    uint32_t ax_cap, abase_n;
    /* priority lists: every axis's items, pq, pbuds, ptarget [0, icap), axes by
     * their base's id, each from base to tip; and one axis's scratch, pcap long */
    float *pq, *pv;
    uint32_t *pbuds, *prank, *pscr, *ptarget;
    size_t icap, pcap;
};

/* How many nodes ahead of a pass over the nodes (basipetal, Borchert-Honda) the
 * values of a node's children are asked of the memory. */
#define MERP_P09_AHEAD 16

/* Prefetches what such a pass reads of node i's children: their light and
 * counts (basipetal), or their light Q and their resource (acropetal, to be
 * written). A lateral child was grown steps after its parent, far from it in
 * memory: asked ahead, the misses overlap instead of being waited on in turn. */
static inline void merp_p09_fetch_children(const merp_model *m, const merp_skeleton *sk,
                                           uint32_t i, int acropetal)
{
    for (uint32_t k = 0; k < 3; k++) {
        uint32_t c = sk->child[3 * i + k];
        if (c == MER_NO_NODE)
            continue;
        if (acropetal) {
            __builtin_prefetch(sk->q + c);
            __builtin_prefetch(m->vin + c, 1);
        } else {
            __builtin_prefetch(m->sub + c);
        }
    }
}

/* Whether bud k of node i may grow this round: in a sylleptic round only the
 * lateral buds made this step; under the brush constraint only buds at or
 * above it (m->mark). */
static inline int merp_p09_may_grow(const merp_model *m, const merp_world *w, uint32_t i,
                                    uint32_t k, int syllepsis)
{
    const merp_skeleton *sk = w->sk;
    int ok = 1;
    if (syllepsis)
        ok = k > 0 && sk->born[i] == w->step;
    if (ok && sk->con_node != MER_NO_NODE)
        ok = m->mark[i] || (i == sk->con_node && k == sk->con_slot);
    return ok;
}

/* Whether node c, living node i's main child (its first child slot), goes on
 * i's axis: whenever there is one. By the skeleton's invariant (skeleton.h) a
 * listed child lives and names i as its parent in slot 0, so the check reads
 * nothing of c: c lies far from i when it began a later shoot, and its links
 * would be a wait of their own. The axis lists (priority.c) place a node's
 * items by its axis's count (sub[].afrom), so both passes ask this. */
static inline int merp_p09_continues(uint32_t c)
{
    return c != MER_NO_NODE;
}

/* environment.c */
/* Q of every bud that may grow this round, and V too unless `defer_v` lets it
 * wait (shadow propagation only) until merp_p09_directions, which must run
 * before the shadow grid changes: between them nothing may cast or lift a
 * shadow. While V waits, Q is read by the basipetal pass that follows
 * (m->lit_pending), node by node beside the sums it feeds. */
mer_result merp_p09_environment(merp_model *m, const merp_world *w, int syllepsis,
                                int defer_v, mer_error *err);
/* Keeps listed only the buds whose resource (m->vb) makes a shoot, in order, and
 * computes their V if it was deferred. */
void merp_p09_directions(merp_model *m, const merp_world *w);
/* borchert_honda.c */
void merp_p09_allocate_bh(merp_model *m, const merp_world *w);
/* priority.c */
mer_result merp_p09_allocate_priority(merp_model *m, const merp_world *w, mer_error *err);
/* shoot.c */
mer_result merp_p09_grow_shoot(const merp_world *w, uint32_t i, uint32_t k, uint32_t n, float l,
                               const float *V, mer_error *err);
/* shedding.c */
mer_result merp_p09_shed(merp_model *m, const merp_world *w, uint32_t *count, mer_error *err);
/* params_p09.c */
mer_result merp_p09_validate(const mer_params *p, mer_error *err);

#endif
