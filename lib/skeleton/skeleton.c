/* meristem — the skeleton: metamer storage, buds, subtrees, plants (P09 §3). */
#include "config.h"

#include <assert.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "core/array.h"
#include "core/hash.h"
#include "core/vec.h"
#include "skeleton/skeleton.h"

#define ARRAY(field, per_node) {offsetof(merp_skeleton, field), per_node * sizeof *((merp_skeleton *)0)->field}
const merp_skel_array merp_skel_arrays[MERP_SKEL_ARRAYS] = {
    ARRAY(parent, 1), ARRAY(child, 3), ARRAY(bud, 3), ARRAY(slot, 1), ARRAY(alive, 1),
    ARRAY(plant, 1),  ARRAY(order, 1), ARRAY(born, 1), ARRAY(pos, 3), ARRAY(dir, 3),
    ARRAY(side, 3),   ARRAY(len, 1),   ARRAY(q, 1),    ARRAY(dn, 1)};
#undef ARRAY

void *merp_skel_array_data(const merp_skeleton *sk, size_t a)
{
    assert(a < MERP_SKEL_ARRAYS);
    void *data; /* copied, not cast: the field is a float * or a uint32_t * */
    memcpy(&data, (const char *)sk + merp_skel_arrays[a].at, sizeof data);
    return data;
}

void merp_skel_init(merp_skeleton *sk, const mer_params *p, merp_bud_fn on_bud, void *ctx)
{
    assert(sk != NULL && p != NULL);
    memset(sk, 0, sizeof *sk);
    merp_skel_init_angles(sk, p);
    sk->pipe_n = p->pipe_n;
    sk->con_node = MER_NO_NODE;
    sk->on_bud = on_bud;
    sk->on_bud_ctx = ctx;
}

void merp_skel_init_angles(merp_skeleton *sk, const mer_params *p)
{
    assert(sk != NULL && p != NULL);
    sk->cos_beta = cosf(p->branch_angle * MER_DEG2RAD);
    sk->sin_beta = sinf(p->branch_angle * MER_DEG2RAD);
}

void merp_skel_free(merp_skeleton *sk)
{
    if (sk == NULL)
        return;
    for (size_t a = 0; a < MERP_SKEL_ARRAYS; a++)
        merp_free(merp_skel_array_data(sk, a));
    merp_free(sk->roots);
    merp_free(sk->stack);
    memset(sk, 0, sizeof *sk);
}

mer_result merp_skel_clone(const merp_skeleton *src, merp_skeleton *dst, merp_bud_fn on_bud,
                           void *ctx, mer_error *err)
{
    assert(src != NULL && dst != NULL);
    memset(dst, 0, sizeof *dst);
    /* Whole capacities, so that growth reallocates exactly when the original would. */
    int ok = 1;
    for (size_t a = 0; ok && a < MERP_SKEL_ARRAYS; a++)
        ok = merp_array_dup(merp_skel_array_slot(dst, a), merp_skel_array_data(src, a), src->cap,
                            merp_skel_arrays[a].bytes);
    ok = ok && MERP_DUP(dst->roots, src->roots, src->cap_plants);
    if (!ok) {
        merp_skel_free(dst);
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for a copy of the nodes");
    }
    dst->n = src->n;
    dst->cap = src->cap;
    dst->pipe_n = src->pipe_n;
    dst->cos_beta = src->cos_beta;
    dst->sin_beta = src->sin_beta;
    dst->nplants = src->nplants;
    dst->cap_plants = src->cap_plants;
    dst->con_node = src->con_node;
    dst->con_slot = src->con_slot;
    dst->on_bud = on_bud; /* the stack is scratch: it starts empty */
    dst->on_bud_ctx = ctx;
    return MER_OK;
}

static mer_result reserve(merp_skeleton *sk, uint32_t want, mer_error *err)
{
    if (want <= sk->cap)
        return MER_OK;
    if (want > MER_NODES_MAX)
        return mer_error_set(err, MER_ERR_LIMIT, "nodes",
                             "the scene would exceed %u internodes", (unsigned)MER_NODES_MAX);
    uint32_t cap = sk->cap ? sk->cap : 256;
    while (cap < want)
        cap = cap > MER_NODES_MAX / 2 ? MER_NODES_MAX : cap * 2;
    /* Each resize either succeeds or leaves the old block: a failure midway leaves
     * some arrays longer than sk->cap, which is harmless. */
    for (size_t a = 0; a < MERP_SKEL_ARRAYS; a++)
        if (!merp_array_resize(merp_skel_array_slot(sk, a), cap, merp_skel_arrays[a].bytes))
            return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for nodes");
    sk->cap = cap;
    return MER_OK;
}

/* Nodes whose pages are mapped at once, ahead of the new nodes. */
#define MAP_AHEAD 16384u

/* Maps the pages of the next MAP_AHEAD nodes of every array: a tree of a million
 * nodes would otherwise take a page fault every 1,024 nodes in each of them. */
static void map_ahead(merp_skeleton *sk)
{
    uint32_t from = sk->mapped > sk->n ? sk->mapped : sk->n;
    uint32_t to = sk->cap - from > MAP_AHEAD ? from + MAP_AHEAD : sk->cap;
    for (size_t a = 0; a < MERP_SKEL_ARRAYS; a++) {
        size_t bytes = merp_skel_arrays[a].bytes;
        merp_prefault(merp_skel_array_data(sk, a), bytes * from, bytes * to);
    }
    sk->mapped = to;
}

mer_result merp_skel_node_new(merp_skeleton *sk, uint32_t step, uint32_t *id, mer_error *err)
{
    assert(sk != NULL && id != NULL);
    mer_result rc = reserve(sk, sk->n + 1, err);
    if (rc != MER_OK)
        return rc;
    if (sk->n >= sk->mapped)
        map_ahead(sk);
    *id = sk->n++;
    merp_skel_node_renew(sk, *id, step);
    return MER_OK;
}

void merp_skel_node_renew(merp_skeleton *sk, uint32_t i, uint32_t step)
{
    assert(sk != NULL && i < sk->n);
    sk->parent[i] = MER_NO_NODE;
    for (int k = 0; k < 3; k++) {
        sk->child[3 * i + k] = MER_NO_NODE;
        sk->bud[3 * i + k] = MER_BUD_NONE;
        sk->pos[3 * i + k] = sk->dir[3 * i + k] = sk->side[3 * i + k] = 0.0f;
    }
    sk->slot[i] = 0;
    sk->alive[i] = 1;
    sk->plant[i] = 0;
    sk->order[i] = 0;
    sk->born[i] = step;
    sk->len[i] = 0.0f;
    sk->q[i] = 0.0f;
    sk->dn[i] = 0.0f;
}

static mer_result reserve_plant(merp_skeleton *sk, mer_error *err)
{
    if (sk->nplants == sk->cap_plants) {
        uint32_t cap = sk->cap_plants ? 2 * sk->cap_plants : 8;
        if (!MERP_RESIZE(sk->roots, cap))
            return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for plants");
        sk->cap_plants = cap;
    }
    return MER_OK;
}

mer_result merp_skel_add_root(merp_skeleton *sk, uint32_t id, mer_error *err)
{
    assert(sk != NULL && id < sk->n && sk->parent[id] == MER_NO_NODE);
    mer_result rc = reserve_plant(sk, err);
    if (rc != MER_OK)
        return rc;
    sk->plant[id] = sk->nplants;
    sk->roots[sk->nplants++] = id;
    return MER_OK;
}

void merp_skel_reset(merp_skeleton *sk)
{
    assert(sk != NULL);
    for (uint32_t i = 0; i < sk->n; i++)
        for (uint32_t k = 0; k < 3; k++)
            merp_skel_bud_set(sk, i, k, MER_BUD_NONE);
    sk->n = 0;
    sk->nplants = 0;
    sk->con_node = MER_NO_NODE;
}

mer_result merp_skel_add_plant(merp_skeleton *sk, const mer_params *p, uint32_t step,
                               const float base[3], mer_rng *rng, uint32_t *root,
                               mer_error *err)
{
    assert(sk != NULL && p != NULL && base != NULL && rng != NULL);
    mer_result rc = reserve_plant(sk, err);
    if (rc != MER_OK)
        return rc;
    uint32_t id;
    rc = merp_skel_node_new(sk, step, &id, err);
    if (rc != MER_OK)
        return rc;
    memcpy(sk->pos + 3 * id, base, 3 * sizeof *base);
    sk->dir[3 * id + 1] = 1.0f;
    float azimuth = mer_rng_float(rng) * MERP_TWO_PI;
    sk->side[3 * id] = cosf(azimuth);
    sk->side[3 * id + 2] = sinf(azimuth);
    sk->len[id] = p->internode_length;
    /* A seedling is a leaf-bearing tip: the pipe model's leaf diameter from the
     * start, not only after its first step. */
    sk->dn[id] = merp_pipe_leaf(sk, p);
    sk->plant[id] = sk->nplants;
    sk->roots[sk->nplants++] = id;
    merp_skel_bud_set(sk, id, 0, MER_BUD_DORMANT);
    for (uint32_t k = 1; k <= p->buds_per_node; k++)
        merp_skel_bud_set(sk, id, k, MER_BUD_DORMANT);
    if (root != NULL)
        *root = id;
    return MER_OK;
}

void merp_skel_bud_dir(const merp_skeleton *sk, uint32_t i, uint32_t k, float out[3])
{
    assert(i < sk->n && k < 3);
    const float *d = sk->dir + 3 * i, *sd = sk->side + 3 * i;
    if (k == 0) {
        memcpy(out, d, 3 * sizeof *out);
        return;
    }
    float c = sk->cos_beta, sn = k == 1 ? sk->sin_beta : -sk->sin_beta;
    for (int a = 0; a < 3; a++)
        out[a] = c * d[a] + sn * sd[a];
    v3_normalize(out);
}

void merp_skel_bud_set(merp_skeleton *sk, uint32_t i, uint32_t k, uint8_t state)
{
    assert(i < sk->n && k < 3);
    uint8_t old = sk->bud[3 * i + k];
    if (old == state)
        return;
    sk->bud[3 * i + k] = state;
    if (sk->on_bud == NULL || !sk->alive[i])
        return;
    if (old == MER_BUD_DORMANT || state == MER_BUD_DORMANT) {
        float e[3];
        merp_skel_node_end(sk, i, e);
        sk->on_bud(sk->on_bud_ctx, e, state == MER_BUD_DORMANT ? 1 : -1);
    }
}

void merp_skel_cast_buds(const merp_skeleton *sk)
{
    if (sk->on_bud == NULL)
        return;
    for (uint32_t i = 0; i < sk->n; i++) {
        if (!sk->alive[i])
            continue;
        for (int k = 0; k < 3; k++)
            if (sk->bud[3 * i + k] == MER_BUD_DORMANT) {
                float e[3];
                merp_skel_node_end(sk, i, e);
                sk->on_bud(sk->on_bud_ctx, e, 1);
            }
    }
}

mer_result merp_skel_subtree(merp_skeleton *sk, uint32_t root, size_t *count, mer_error *err)
{
    assert(root < sk->n && count != NULL);
    size_t top = 0, out = 0;
    /* The output is written to the front of the array while the work stack grows
     * from the same array's back half: use one buffer of 2·cap entries. */
    if (sk->stack_cap < 2 * (size_t)sk->n + 2) {
        size_t cap = 2 * (size_t)sk->n + 64;
        if (!MERP_RESIZE(sk->stack, cap))
            return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for a subtree walk");
        sk->stack_cap = cap;
    }
    uint32_t *work = sk->stack + sk->n + 1;
    work[top++] = root;
    while (top > 0) {
        uint32_t i = work[--top];
        sk->stack[out++] = i;
        for (int k = 2; k >= 0; k--) {
            uint32_t c = sk->child[3 * i + k];
            if (c != MER_NO_NODE && sk->alive[c])
                work[top++] = c;
        }
    }
    *count = out;
    return MER_OK;
}

mer_result merp_skel_kill(merp_skeleton *sk, uint32_t root, mer_error *err)
{
    size_t cnt;
    mer_result rc = merp_skel_subtree(sk, root, &cnt, err);
    if (rc != MER_OK)
        return rc;
    for (size_t t = 0; t < cnt; t++) {
        uint32_t i = sk->stack[t];
        for (uint32_t k = 0; k < 3; k++)
            merp_skel_bud_set(sk, i, k, MER_BUD_NONE);
        sk->alive[i] = 0;
    }
    uint32_t p = sk->parent[root];
    if (p != MER_NO_NODE)
        sk->child[3 * p + sk->slot[root]] = MER_NO_NODE;
    if (sk->con_node != MER_NO_NODE && !sk->alive[sk->con_node])
        sk->con_node = MER_NO_NODE;
    return MER_OK;
}

void merp_side_next(const float side_prev[3], const float d[3], float divergence_deg,
                    float out[3])
{
    /* Carry the previous side vector onto the plane normal to d, then turn it. */
    float t[3];
    float dot = v3_dot(side_prev, d);
    for (int a = 0; a < 3; a++)
        t[a] = side_prev[a] - dot * d[a];
    if (!v3_normalize(t))
        v3_any_perp(d, t);
    v3_rotate(t, d, divergence_deg * MER_DEG2RAD, out);
    v3_normalize(out);
}

uint64_t merp_skel_hash(const merp_skeleton *sk, uint64_t h)
{
    for (uint32_t i = 0; i < sk->n; i++) {
        h = merp_fnv(h, &sk->alive[i], 1);
        h = merp_fnv(h, &sk->parent[i], 4);
        h = merp_fnv(h, sk->child + 3 * i, 12);
        h = merp_fnv(h, sk->bud + 3 * i, 3);
        h = merp_fnv(h, &sk->order[i], 4);
        h = merp_fnv(h, &sk->plant[i], 4);
        h = merp_fnv(h, &sk->born[i], 4);
        h = merp_fnv(h, sk->pos + 3 * i, 12);
        h = merp_fnv(h, sk->dir + 3 * i, 12);
        h = merp_fnv(h, sk->side + 3 * i, 12);
        h = merp_fnv(h, &sk->len[i], 4);
        h = merp_fnv(h, &sk->dn[i], 4);
    }
    return h;
}
