/* meristem — the inverse model's tree shown at time t, whole (G04 §4: the
 * tree is a function of time), with what the user did to the trees before it.
 *
 * A node's id is its key's (build.c) in the tree before, when that tree had
 * the key: the same botanical node keeps its id through steps and function
 * changes, and new nodes get new ids. The ids are renumbered in build order
 * only when dead ones outnumber the live (rebuilds under other functions leave
 * nodes behind) or a new node would precede its parent, so they stay bounded
 * by the live tree. Prunes are kept as the keys they cut, bends as their key
 * and their axis in the node's own frame; both are made again on every tree
 * that has their node, and dropped by the first that does not. */
#include "config.h"

#include <assert.h>
#include <string.h>

#include "core/alloc.h"
#include "models/inverse/inverse.h"
#include "scene_private.h"

/* Every plant at t, ids from the tree before. */
static mer_result build_all(merp_model *m, merp_skeleton *sk, double t, mer_error *err)
{
    /* A node left dead by an earlier tree or prune is nobody's child now. */
    for (uint32_t i = 0; i < sk->n; i++)
        if (!sk->alive[i])
            sk->parent[i] = MER_NO_NODE;
    mer_result rc = merp_inv_map_build(&m->ids, &m->keys, sk, err);
    if (rc != MER_OK)
        return rc;
    if (m->keys.ncut > 0)
        memset(m->hit, 0, m->keys.ncut);
    m->keys.hit = m->hit;
    m->keys.ids = &m->ids;
    for (uint32_t r = 0; r < sk->nplants && rc == MER_OK; r++) {
        uint32_t root = sk->roots[r];
        if (sk->alive[root])
            rc = merp_inv_build(&m->def, t, m->seed, sk, root, &m->keys, err);
    }
    m->keys.ids = NULL;
    m->keys.hit = NULL;
    return rc;
}

/* Every id given up: the skeleton emptied but for a new root per plant at its
 * old base, the keys forgotten. */
static mer_result renumber(merp_model *m, merp_skeleton *sk, mer_error *err)
{
    uint32_t n = sk->nplants;
    float *bases = merp_malloc((size_t)(n ? n : 1) * 3 * sizeof *bases);
    if (bases == NULL)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for renumbering");
    for (uint32_t r = 0; r < n; r++)
        memcpy(bases + 3 * r, sk->pos + 3 * sk->roots[r], 3 * sizeof *bases);
    merp_skel_reset(sk);
    m->keys.used = 0;
    mer_result rc = MER_OK;
    for (uint32_t r = 0; r < n && rc == MER_OK; r++) {
        uint32_t id;
        rc = merp_skel_node_new(sk, 0, &id, err);
        if (rc == MER_OK) {
            memcpy(sk->pos + 3 * id, bases + 3 * r, 3 * sizeof *bases);
            sk->dir[3 * id + 1] = 1.0f;
            rc = merp_skel_add_root(sk, id, err);
        }
    }
    merp_free(bases);
    return rc;
}

/* The cuts this tree did not reach, dropped. */
static uint32_t drop_cuts(merp_model *m)
{
    uint32_t kept = 0, n = m->keys.ncut;
    for (uint32_t k = 0; k < n; k++)
        if (m->hit[k])
            m->cuts[kept++] = m->cuts[k];
    m->keys.ncut = kept;
    return n - kept;
}

/* Each bend made again at its node, in the order they were made; those whose
 * node this tree lacks are dropped. */
static mer_result bend_again(merp_model *m, const merp_world *w, uint32_t *dropped,
                             mer_error *err)
{
    if (m->nbends == 0)
        return MER_OK;
    mer_result rc = merp_inv_map_build(&m->ids, &m->keys, w->sk, err);
    uint32_t kept = 0;
    for (uint32_t k = 0; k < m->nbends && rc == MER_OK; k++) {
        const merp_inv_bend *b = &m->bends[k];
        uint32_t id = merp_inv_map_find(&m->ids, b->key);
        if (id == MER_NO_NODE) {
            (*dropped)++;
            continue;
        }
        float ax[3];
        merp_inv_bend_axis(w->sk, id, b, ax);
        rc = merp_bend_apply(w->sk, w->env, id, ax, b->angle, b->spread, err);
        m->bends[kept++] = *b;
    }
    if (rc == MER_OK)
        m->nbends = kept;
    return rc;
}

mer_result merp_inv_show(merp_model *m, const merp_world *w, double t, mer_error *err)
{
    merp_skeleton *sk = w->sk;
    if (!m->seeded) {
        m->seed = mer_rng_next(w->rng);
        m->seeded = 1;
    }
    mer_result rc = build_all(m, sk, t, err);
    if (rc == MER_OK && merp_inv_needs_renumbering(sk)) {
        rc = renumber(m, sk, err);
        if (rc == MER_OK)
            rc = build_all(m, sk, t, err);
    }
    if (rc != MER_OK)
        return rc;
    uint32_t dropped = drop_cuts(m);
    rc = bend_again(m, w, &dropped, err);
    m->dropped = dropped;
    m->t = t;
    /* A branch of order k starts where a node of order k has a parent of a lower one. */
    memset(m->branches, 0, sizeof m->branches);
    for (uint32_t i = 0; i < sk->n; i++) {
        uint32_t p = sk->parent[i], k = sk->order[i];
        if (sk->alive[i] && p != MER_NO_NODE && sk->order[p] < k && k <= MERP_INV_ORDER_MAX)
            m->branches[k]++;
    }
    return rc;
}

mer_result merp_inv_record_bend(merp_model *m, const merp_skeleton *sk, uint32_t id,
                                const float ax[3], float angle, uint32_t spread,
                                mer_error *err)
{
    assert(m != NULL && sk != NULL && id < sk->n);
    uint64_t key = m->seeded && id < m->keys.used ? m->keys.of[id] : 0;
    if (key == 0)
        return MER_OK; /* the seedling before the first tree: nothing to make again */
    if (m->nbends == m->cap_bends) {
        uint32_t cap = m->cap_bends ? 2 * m->cap_bends : 8;
        merp_inv_bend *b = merp_realloc(m->bends, (size_t)cap * sizeof *b);
        if (b == NULL)
            return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for a bend");
        m->bends = b;
        m->cap_bends = cap;
    }
    m->bends[m->nbends++] = merp_inv_bend_record(sk, id, key, ax, angle, spread);
    return MER_OK;
}
