/* meristem — Xu & Mould 2015's fourth step onto the shared skeleton (guiding.h):
 * the union of the least-cost paths to an iteration's endpoints joins the tree,
 * each new tree edge an internode from its parent's end. A node's first child
 * continues its axis (slot 0); the others are laterals in slot 1 of the node or
 * of a chain of joints (length 0) hung in slot 2. */
#include "config.h"

#include <assert.h>
#include <string.h>

#include "core/array.h"
#include "core/vec.h"
#include "env/noise.h"
#include "models/guiding/guiding.h"

/* Where the next child of skeleton node s goes: (*at, *slot). A full node gets
 * a joint in slot 2, in the order of its laterals. */
static mer_result find_slot(const merp_world *w, uint32_t s, uint32_t *at, uint32_t *slot,
                            mer_error *err)
{
    merp_skeleton *sk = w->sk;
    if (sk->child[3 * s] == MER_NO_NODE) {
        *at = s;
        *slot = 0;
        return MER_OK;
    }
    for (;;) {
        if (sk->child[3 * s + 1] == MER_NO_NODE) {
            *at = s;
            *slot = 1;
            return MER_OK;
        }
        uint32_t j = sk->child[3 * s + 2];
        if (j != MER_NO_NODE) {
            s = j;
            continue;
        }
        mer_result rc = merp_skel_node_new(sk, w->step, &j, err);
        if (rc != MER_OK)
            return rc;
        sk->parent[j] = s;
        sk->slot[j] = 2;
        sk->child[3 * s + 2] = j;
        merp_skel_node_end(sk, s, sk->pos + 3 * j);
        memcpy(sk->dir + 3 * j, sk->dir + 3 * s, 3 * sizeof *sk->dir);
        memcpy(sk->side + 3 * j, sk->side + 3 * s, 3 * sizeof *sk->side);
        sk->len[j] = 0.0f;
        sk->order[j] = sk->order[s];
        sk->plant[j] = sk->plant[s];
        s = j;
    }
}

/* Graph node v joins the tree as the child of graph node u (in the tree). */
static mer_result add_edge(merp_model *m, const merp_world *w, uint32_t u, uint32_t v,
                           int *made, mer_error *err)
{
    merp_skeleton *sk = w->sk;
    const merp_gv_graph *gr = &m->graph;
    uint32_t s = m->skid[u];
    float start[3], end[3], d[3];
    for (int a = 0; a < 3; a++)
        d[a] = gr->pos[3 * (size_t)v + a] - gr->pos[3 * (size_t)u + a];
    float l = v3_len(d);
    v3_normalize(d);
    merp_skel_node_end(sk, s, start);
    merp_noise_internode(w->noise, w->p, start, d, &l);
    for (int a = 0; a < 3; a++)
        end[a] = start[a] + d[a] * l;
    *made = 0;
    if (merp_env_blocked(w->env, end))
        return MER_OK;
    uint32_t at, slot, c;
    mer_result rc = find_slot(w, s, &at, &slot, err);
    if (rc == MER_OK)
        rc = merp_skel_node_new(sk, w->step, &c, err);
    if (rc != MER_OK)
        return rc;
    sk->parent[c] = at;
    sk->slot[c] = (uint8_t)slot;
    sk->child[3 * at + slot] = c;
    memcpy(sk->pos + 3 * c, start, sizeof start);
    memcpy(sk->dir + 3 * c, d, sizeof d);
    sk->len[c] = l;
    sk->order[c] = sk->order[s] + (slot > 0 ? 1u : 0u);
    sk->plant[c] = sk->plant[s];
    merp_side_next(sk->side + 3 * s, d, w->p->divergence, sk->side + 3 * c);
    if (slot == 0)
        merp_skel_bud_set(sk, s, 0, MER_BUD_NONE);
    merp_skel_bud_set(sk, c, 0, MER_BUD_DORMANT);
    m->skid[v] = c;
    memcpy(m->g + 3 * (size_t)v, m->search.g + 3 * (size_t)v, 3 * sizeof *m->g);
    m->hop[v] = m->search.hop[v];
    *made = 1;
    return MER_OK;
}

mer_result merp_gv_grow_paths(merp_model *m, const merp_world *w, const uint32_t *ends, uint32_t n,
                              uint32_t *grown, mer_error *err)
{
    assert(m != NULL && w != NULL && (ends != NULL || n == 0) && grown != NULL);
    const merp_gv_search *s = &m->search;
    *grown = 0;
    for (uint32_t e = 0; e < n; e++) {
        /* The path back from the endpoint to the first node already in the tree. */
        uint32_t len = 0;
        for (uint32_t v = ends[e]; m->skid[v] == MER_NO_NODE; v = s->pred[v]) {
            if (s->pred[v] == MER_NO_NODE)
                break; /* not reached from the tree (cannot happen for an endpoint) */
            if (len == m->path_cap) {
                uint32_t c = m->path_cap ? 2 * m->path_cap : 256;
                if (!MERP_RESIZE(m->path, c))
                    return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for a path");
                m->path_cap = c;
            }
            m->path[len++] = v;
        }
        /* Forwards from the tree; a node that cannot be made (blocked) ends the path. */
        for (uint32_t k = len; k-- > 0;) {
            uint32_t v = m->path[k], u = s->pred[v];
            if (m->skid[u] == MER_NO_NODE)
                break;
            int made;
            mer_result rc = add_edge(m, w, u, v, &made, err);
            if (rc != MER_OK)
                return rc;
            if (!made)
                break;
            (*grown)++;
        }
    }
    return MER_OK;
}
