/* meristem — P09's environment input (P09 §4.1): the light Q and optimal growth
 * direction V of every bud that may grow this round, from the shared environment.
 * Buds that may not grow still clear their occupancy zone of markers, and cast
 * shadow. */
#include "config.h"

#include <assert.h>
#include <string.h>

#include <meristem/fate.h>

#include "core/array.h"
#include "models/p09/p09.h"

static mer_result reserve_buds(merp_model *m, size_t want, mer_error *err)
{
    if (want <= m->bcap)
        return MER_OK;
    size_t cap = want + want / 2 + 64;
    if (!MERP_RESIZE(m->bkey, cap) || !MERP_RESIZE(m->bpos, 3 * cap) ||
        !MERP_RESIZE(m->bdir, 3 * cap) || !MERP_RESIZE(m->bv, 3 * cap) ||
        !MERP_RESIZE(m->bq, cap) || !MERP_RESIZE(m->bquiet, cap))
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for buds");
    m->bcap = cap;
    return MER_OK;
}

/* Marks (m->mark) the nodes whose buds may grow under the brush constraint. */
static void mark_constraint(merp_model *m, const merp_skeleton *sk)
{
    uint32_t c = sk->child[3 * sk->con_node + sk->con_slot];
    for (uint32_t i = 0; i < sk->n; i++) {
        uint32_t p = sk->parent[i];
        m->mark[i] = sk->alive[i] && (i == c || (p != MER_NO_NODE && m->mark[p]));
    }
}

/* The voxel of every node's end (m->cell), under shadow propagation: computed
 * for the new nodes only while the epoch stays, as nothing else moves a bud then. */
static mer_result update_cells(merp_model *m, const merp_world *w, mer_error *err)
{
    const merp_skeleton *sk = w->sk;
    uint32_t now = merp_env_epoch(w->env) + 1;
    if (m->cell_epoch != now) {
        m->cell_n = 0;
        m->cell_epoch = now;
    }
    if (sk->n > m->cell_cap) {
        if (!MERP_RESIZE(m->cell, sk->cap))
            return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for buds");
        m->cell_cap = sk->cap;
    }
    for (uint32_t i = m->cell_n; i < sk->n; i++) {
        float e[3];
        merp_skel_node_end(sk, i, e);
        m->cell[i] = merp_env_cell(w->env, e);
    }
    m->cell_n = sk->n;
    return MER_OK;
}

/* Under shadow propagation while V waits: the voxels of the buds, and room
 * for every bud in the list the basipetal pass makes as it reads their light
 * (p09.c: it lists them downward from bkey[3n], each node's last slot first). */
static mer_result defer_lit(merp_model *m, const merp_world *w, int syllepsis, mer_error *err)
{
    const merp_skeleton *sk = w->sk;
    mer_result rc = update_cells(m, w, err);
    if (rc == MER_OK)
        rc = reserve_buds(m, 3 * (size_t)sk->n, err);
    if (rc != MER_OK)
        return rc;
    m->light = merp_env_light(w->env);
    m->lit_every = !syllepsis && sk->con_node == MER_NO_NODE;
    m->lit_syllepsis = syllepsis;
    m->lit_pending = 1;
    m->bfirst = 3 * (size_t)sk->n;
    m->bn = 0;
    return MER_OK;
}

/* Lists the buds that may grow into the round's scratch (bkey, bpos and bdir),
 * when V is not deferred. */
static mer_result collect_buds(merp_model *m, const merp_world *w, int syllepsis,
                               mer_error *err)
{
    const merp_skeleton *sk = w->sk;
    int markers = w->p->environment == MER_ENV_MARKERS;
    uint32_t quiet_now = merp_env_epoch(w->env) + 1;
    m->bn = 0;
    m->bfirst = 0;
    for (uint32_t i = 0; i < sk->n; i++) {
        if (!sk->alive[i])
            continue;
        for (uint32_t k = 0; k < 3; k++) {
            m->qb[3 * i + k] = 0.0f;
            m->vb[3 * i + k] = 0.0f;
            if (!merp_skel_bud_exists(sk, i, k, w->p->buds_per_node))
                continue;
            int ok = merp_p09_may_grow(m, w, i, k, syllepsis);
            /* A bud known to have no marker near it, with no marker added and no
             * bud moved since, can neither take nor remove one: Q = 0, skip it. */
            if (markers && m->quiet[3 * i + k] == quiet_now)
                continue;
            float e[3];
            merp_skel_node_end(sk, i, e);
            if (!ok) {
                merp_env_occupy(w->env, e);
                continue;
            }
            mer_result rc = reserve_buds(m, m->bn + 1, err);
            if (rc != MER_OK)
                return rc;
            size_t b = m->bn++;
            m->bkey[b] = 3 * i + k;
            memcpy(m->bpos + 3 * b, e, sizeof e);
            merp_skel_bud_dir(sk, i, k, m->bdir + 3 * b);
        }
    }
    return MER_OK;
}

mer_result merp_p09_environment(merp_model *m, const merp_world *w, int syllepsis,
                                int defer_v, mer_error *err)
{
    assert(m != NULL && w != NULL && m->n == w->sk->n);
    if (w->sk->con_node != MER_NO_NODE)
        mark_constraint(m, w->sk);
    /* Under shadow propagation most buds get no resource: V waits for the few
     * that grow (merp_p09_directions), read from this same grid. */
    m->v_deferred = defer_v && w->p->environment == MER_ENV_SHADOW;
    if (m->v_deferred)
        return defer_lit(m, w, syllepsis, err);
    mer_result rc = collect_buds(m, w, syllepsis, err);
    if (rc == MER_OK)
        rc = merp_env_perceive(w->env, m->bn, m->bpos, m->bdir, m->bq, m->bv, m->bquiet, err);
    if (rc != MER_OK)
        return rc;
    if (w->p->environment == MER_ENV_MARKERS) {
        uint32_t quiet_now = merp_env_epoch(w->env) + 1;
        for (size_t b = 0; b < m->bn; b++)
            m->quiet[m->bkey[b]] = m->bquiet[b] ? quiet_now : 0;
    }
    for (size_t b = 0; b < m->bn; b++)
        m->qb[m->bkey[b]] = m->bq[b];
    return MER_OK;
}

/* How many growing buds ahead merp_p09_directions asks for a bud's neighbours. */
#define DIRECTION_AHEAD 4

void merp_p09_directions(merp_model *m, const merp_world *w)
{
    assert(m != NULL && w != NULL);
    /* Only the buds whose resource makes a shoot stay listed, in order (their V
     * moved along): the growth pass then reads no bud that cannot grow. */
    size_t g = 0;
    for (size_t b = 0; b < m->bn; b++) {
        uint32_t key = m->bkey[m->bfirst + b]; /* read before bkey[g ≤ b] is written */
        if (mer_shoot_size(m->vb[key], w->p->max_shoot, w->p->internode_length, NULL) == 0)
            continue;
        m->bkey[g] = key;
        if (!m->v_deferred && g != b)
            memcpy(m->bv + 3 * g, m->bv + 3 * b, 3 * sizeof *m->bv);
        g++;
    }
    m->bn = g;
    m->bfirst = 0;
    /* V read from the grid now, for the few that grow; the voxels (m->cell) are
     * this round's, and each bud's 26 neighbours lie in nine rows far apart:
     * asked for a few buds ahead. */
    const float cone = m->v_deferred ? merp_env_cone(w->env) : 0.0f;
    for (size_t b = 0; m->v_deferred && b < g; b++) {
        uint32_t key = m->bkey[b];
        if (b + DIRECTION_AHEAD < g)
            merp_env_direction_ahead(w->env, m->cell[m->bkey[b + DIRECTION_AHEAD] / 3]);
        merp_skel_bud_dir(w->sk, key / 3, key % 3, m->bdir + 3 * b);
        merp_env_direction_cell(w->env, m->cell[key / 3], m->bdir + 3 * b, cone, m->bv + 3 * b);
    }
    m->v_deferred = 0;
}
