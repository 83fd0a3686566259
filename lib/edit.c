/* meristem — prune, bend and the growth constraint (P09 §5): edits of the skeleton,
 * whatever model grew it. The brush is brush.c. */
#include "config.h"

#include <assert.h>
#include <string.h>

#include <meristem/edit.h>

#include "core/vec.h"
#include "scene_private.h"

static mer_result live_node(const mer_scene *s, uint32_t node, mer_error *err)
{
    const merp_skeleton *sk = &s->sk;
    if (node >= sk->n)
        return mer_error_set(err, MER_ERR_NOT_FOUND, "node",
                             "node %u was never part of this tree (ids are 0 to %u)",
                             (unsigned)node, sk->n ? (unsigned)(sk->n - 1) : 0u);
    if (!sk->alive[node])
        return mer_error_set(err, MER_ERR_GONE, "node", "node %u was pruned or shed",
                             (unsigned)node);
    return MER_OK;
}

static void nodes_changed(mer_scene *s)
{
    if (s->ops->nodes_changed == NULL)
        return;
    merp_world w = merp_scene_world(s);
    s->ops->nodes_changed(s->model, &w);
}

mer_result mer_scene_prune(mer_scene *s, uint32_t node, mer_error *err)
{
    assert(s != NULL);
    mer_result rc = live_node(s, node, err);
    // A plant without its first internode has nothing left to grow from, for good.
    if (rc == MER_OK && s->sk.parent[node] == MER_NO_NODE)
        rc = mer_error_set(err, MER_ERR_ROOT, "node",
                           "node %u is the first internode of plant %u; pruning it would "
                           "remove the whole plant for good",
                           (unsigned)node, (unsigned)s->sk.plant[node]);
    if (rc == MER_OK)
        rc = merp_skel_kill(&s->sk, node, err);
    if (rc == MER_OK)
        nodes_changed(s);
    return rc;
}

/* Tells the environment that the dormant buds of the first `cnt` nodes of the
 * subtree walk go (-1) or come back (+1). */
static void cast_subtree(const merp_skeleton *sk, merp_env *env, size_t cnt, int sign)
{
    for (size_t t = 0; t < cnt; t++) {
        uint32_t i = sk->stack[t];
        float e[3];
        merp_skel_node_end(sk, i, e);
        for (int k = 0; k < 3; k++)
            if (sk->bud[3 * i + k] == MER_BUD_DORMANT)
                merp_env_bud_changed(env, e, sign);
    }
}

/* Turns the subtree walk's nodes about `ax` through the base of `node`. */
static void rotate_subtree(merp_skeleton *sk, uint32_t node, size_t cnt, const float ax[3],
                           float rad)
{
    float o[3];
    memcpy(o, sk->pos + 3 * node, sizeof o);
    for (size_t t = 0; t < cnt; t++) {
        uint32_t i = sk->stack[t];
        float rel[3] = {sk->pos[3 * i] - o[0], sk->pos[3 * i + 1] - o[1],
                        sk->pos[3 * i + 2] - o[2]};
        v3_rotate(rel, ax, rad, rel);
        for (int a = 0; a < 3; a++)
            sk->pos[3 * i + a] = o[a] + rel[a];
        v3_rotate(sk->dir + 3 * i, ax, rad, sk->dir + 3 * i);
        v3_normalize(sk->dir + 3 * i);
        v3_rotate(sk->side + 3 * i, ax, rad, sk->side + 3 * i);
        v3_normalize(sk->side + 3 * i);
    }
}

mer_result mer_scene_bend(mer_scene *s, uint32_t node, const float axis[3], float angle,
                          mer_error *err)
{
    return mer_scene_bend_spread(s, node, axis, angle, 1, err);
}

/* The first `spread` internodes of the axis from `node` up (node, its terminal
 * child, that one's, ...) into `chain`; returns how many there are. */
static uint32_t axis_chain(const merp_skeleton *sk, uint32_t node, uint32_t spread,
                           uint32_t *chain)
{
    uint32_t n = 0;
    for (uint32_t i = node; n < spread && i != MER_NO_NODE && sk->alive[i]; i = sk->child[3 * i])
        chain[n++] = i;
    return n;
}

mer_result mer_scene_bend_spread(mer_scene *s, uint32_t node, const float axis[3], float angle,
                                 uint32_t spread, mer_error *err)
{
    assert(s != NULL && axis != NULL);
    mer_result rc = live_node(s, node, err);
    if (rc != MER_OK)
        return rc;
    float ax[3] = {axis[0], axis[1], axis[2]};
    if (!v3_normalize(ax))
        return mer_error_set(err, MER_ERR_RANGE, "axis", "axis must not be the zero vector");
    if (!(angle == angle))
        return mer_error_set(err, MER_ERR_RANGE, "angle", "angle must be a number");
    if (spread < 1 || spread > MER_BEND_SPREAD_MAX)
        return mer_error_set(err, MER_ERR_RANGE, "spread", "spread must be from 1 to %u, got %u",
                             (unsigned)MER_BEND_SPREAD_MAX, (unsigned)spread);
    if (s->ops->bending != NULL) {
        merp_world w = merp_scene_world(s);
        rc = s->ops->bending(s->model, &w, node, ax, angle, spread, err);
    }
    if (rc == MER_OK)
        rc = merp_bend_apply(&s->sk, &s->env, node, ax, angle, spread, err);
    if (rc == MER_OK)
        nodes_changed(s);
    return rc;
}

mer_result merp_bend_apply(merp_skeleton *sk, merp_env *env, uint32_t node, const float ax[3],
                           float angle, uint32_t spread, mer_error *err)
{
    assert(node < sk->n && sk->alive[node] && spread >= 1 && spread <= MER_BEND_SPREAD_MAX);
    uint32_t chain[MER_BEND_SPREAD_MAX];
    uint32_t n = axis_chain(sk, node, spread, chain);
    /* Each internode of the chain turns its own subtree about its own base by an
     * equal share, lowest first: the axis curves, and its tip turns by `angle`. */
    float share = angle / (float)n * MER_DEG2RAD;
    for (uint32_t j = 0; j < n; j++) {
        size_t cnt;
        /* Only the first walk can fail (its buffer is sized by the node count,
         * not the subtree): a refusal changes nothing. */
        mer_result rc = merp_skel_subtree(sk, chain[j], &cnt, err);
        if (rc != MER_OK)
            return rc;
        cast_subtree(sk, env, cnt, -1);
        rotate_subtree(sk, chain[j], cnt, ax, share);
        cast_subtree(sk, env, cnt, 1);
    }
    merp_env_buds_moved(env); /* moved buds see other markers */
    return MER_OK;
}

mer_result mer_scene_constrain(mer_scene *s, uint32_t node, uint32_t slot, mer_error *err)
{
    assert(s != NULL);
    mer_result rc = live_node(s, node, err);
    if (rc != MER_OK)
        return rc;
    merp_skeleton *sk = &s->sk;
    if (slot > s->p.buds_per_node)
        return mer_error_set(err, MER_ERR_RANGE, "slot", "slot must be from 0 to %u, got %u",
                             (unsigned)s->p.buds_per_node, (unsigned)slot);
    uint8_t st = sk->bud[3 * node + slot];
    if (st != MER_BUD_DORMANT && sk->child[3 * node + slot] == MER_NO_NODE)
        return mer_error_set(err, MER_ERR_RANGE, "slot",
                             "bud %u of node %u is neither dormant nor grown out",
                             (unsigned)slot, (unsigned)node);
    sk->con_node = node;
    sk->con_slot = slot;
    return MER_OK;
}

void mer_scene_unconstrain(mer_scene *s) { s->sk.con_node = MER_NO_NODE; }

int mer_scene_constraint(const mer_scene *s, uint32_t *node, uint32_t *slot)
{
    if (s->sk.con_node == MER_NO_NODE)
        return 0;
    if (node != NULL)
        *node = s->sk.con_node;
    if (slot != NULL)
        *slot = s->sk.con_slot;
    return 1;
}
