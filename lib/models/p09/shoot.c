/* meristem — new shoots (P09 §4.3): a bud given resource v grows n metamers; each
 * turns towards the optimal growth direction V (weight ξ) and by tropism (weight
 * η), and its buds are placed by phyllotaxis. */
#include "config.h"

#include <assert.h>
#include <string.h>

#include "core/vec.h"
#include "env/noise.h"
#include "models/p09/p09.h"

/* Tropism (P09 §4.3, Fig. 12): the direction T is up, and η's sign and size (by
 * step and branch order, schedule.c) bend shoots up (η > 0) or down (η < 0). */
static float tropism(const mer_params *p, uint32_t step, uint32_t order, float T[3])
{
    T[0] = 0.0f;
    T[1] = 1.0f;
    T[2] = 0.0f;
    return mer_params_eta_at(p, step, order);
}

/* The direction of the next metamer: the default d_prev + ξV + ηT, normalized (the
 * default itself when that sum vanishes). */
static void shoot_direction(const float d_prev[3], float xi, const float V[3], float eta,
                            const float T[3], float d[3])
{
    for (int a = 0; a < 3; a++)
        d[a] = d_prev[a] + xi * V[a] + eta * T[a];
    if (!v3_normalize(d))
        memcpy(d, d_prev, 3 * sizeof *d);
}

/* Links metamer c into the shoot after `cur` and gives it its buds (phyllotaxis:
 * its side vector turns by the divergence angle from the previous one). */
static void place_metamer(merp_skeleton *sk, const mer_params *p, uint32_t c, uint32_t cur,
                          uint32_t slot, uint32_t from, const float start[3], const float d[3],
                          float l, uint32_t order, const float side_prev[3])
{
    sk->parent[c] = cur;
    sk->slot[c] = (uint8_t)slot;
    sk->child[3 * cur + slot] = c;
    memcpy(sk->pos + 3 * c, start, 3 * sizeof *start);
    memcpy(sk->dir + 3 * c, d, 3 * sizeof *d);
    sk->len[c] = l;
    sk->order[c] = order;
    sk->plant[c] = sk->plant[from];
    merp_side_next(side_prev, d, p->divergence, sk->side + 3 * c);
    for (uint32_t kk = 1; kk <= p->buds_per_node; kk++)
        merp_skel_bud_set(sk, c, kk, MER_BUD_DORMANT);
}

mer_result merp_p09_grow_shoot(const merp_world *w, uint32_t i, uint32_t k, uint32_t n, float l,
                               const float *V, mer_error *err)
{
    assert(w != NULL && i < w->sk->n && k < 3 && V != NULL);
    merp_skeleton *sk = w->sk;
    const mer_params *p = w->p;
    uint32_t order = sk->order[i] + (k > 0 ? 1u : 0u);
    float T[3];
    float eta = tropism(p, w->step, order, T);
    float d_prev[3], start[3], side_prev[3];
    merp_skel_bud_dir(sk, i, k, d_prev);
    merp_skel_node_end(sk, i, start);
    memcpy(side_prev, sk->side + 3 * i, sizeof side_prev);
    uint32_t cur = i, made = 0;
    for (uint32_t j = 0; j < n; j++) {
        float d[3], lj = l;
        shoot_direction(d_prev, p->xi, V, eta, T, d);
        merp_noise_internode(w->noise, p, start, d, &lj);
        float end[3];
        for (int a = 0; a < 3; a++)
            end[a] = start[a] + d[a] * lj;
        if (merp_env_blocked(w->env, end))
            break;
        uint32_t c;
        mer_result rc = merp_skel_node_new(sk, w->step, &c, err);
        if (rc != MER_OK)
            return rc;
        uint32_t slot = j == 0 ? k : 0;
        if (j == 0)
            merp_skel_bud_set(sk, i, k, MER_BUD_NONE);
        place_metamer(sk, p, c, cur, slot, i, start, d, lj, order, side_prev);
        memcpy(start, end, sizeof start);
        memcpy(d_prev, d, sizeof d);
        memcpy(side_prev, sk->side + 3 * c, sizeof side_prev);
        cur = c;
        made++;
    }
    if (made > 0) {
        uint8_t tip = MER_BUD_DORMANT;
        if (p->sympodial)
            tip = p->sympodial_abort ? MER_BUD_ABORTED : MER_BUD_FLOWER;
        merp_skel_bud_set(sk, cur, 0, tip);
    }
    return MER_OK;
}
