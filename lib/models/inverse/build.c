/* meristem — the tree of an inverse-model definition at time t (G04 §4): every
 * branch is the series of its annual shoots (§4.1), its length by year from the
 * silhouettes (eqs (6), (7), (12)) and its scale factor (eqs (10), (13), (15)),
 * its shoots cut into metamers (eq (14)) headed by eqs (8)–(9), its laterals
 * placed by phyllotaxis with the 40° rule and made the year after their shoot
 * where s_b >= s_min, shed at their lifespan (eq (11)); the shoots of the year
 * in progress unfold metamer by metamer (§4.3).
 *
 * The tree is a function of time: it is rebuilt whole for every t, so headings
 * that depend on a branch's current length (eq (8)) bend old wood as the branch
 * grows, as G04's gravity does. Randomness is keyed, not drawn: a branch's key
 * comes from its parent's and its place on it, so each branch keeps its
 * variation from year to year.
 *
 * Choices where G04 leaves a detail open: a lateral's position x for eqs (6) and
 * (10) is the base of its parent shoot (§4.3: laterals "use the position of the
 * shoot along the branch"); the trunk stands up with only the jitter; the
 * longest lateral of a shoot is taken to be its last (phyllotaxis.c). Radius is
 * G04 §4.1's function of position along the branch (radius.c), each node's at
 * its base. */
#include "config.h"

#include <assert.h>
#include <math.h>
#include <string.h>

#include "core/alloc.h"
#include "core/vec.h"
#include "models/inverse/inverse.h"

typedef struct builder {
    const merp_inv_def *d;
    merp_skeleton *sk;
    double t;
    uint32_t year;  /* Y: the year whose shoots are growing at t */
    float f;        /* how much of year Y has passed, (0, 1] */
    uint32_t plant;
    uint32_t reuse; /* the plant's root, the trunk's first metamer */
    float *lens;    /* (order_max + 1) rows of y_max + 1: each depth's lengths by year */
    merp_inv_keys *keys; /* may be NULL */
    mer_error *err;
} builder;

/* A branch being built. */
typedef struct branch {
    uint32_t order, born; /* born: the year of its first shoot */
    float s_b;
    float r_cap;             /* its base radius at most: the parent's there (-1: none) */
    uint64_t key;
    const float *l;          /* its lengths by year */
    uint32_t attach, slot;   /* the node it grows from (MER_NO_NODE: the trunk) */
    float base[3], h0[3], dp[3], side[3];
} branch;

/* A uniform number in [0, 1) for (key, k): a counter, not a stream. */
static float keyed(uint64_t key, uint64_t k)
{
    uint64_t s = key ^ (k * UINT64_C(0x9E3779B97F4A7C15));
    uint64_t v = mer_splitmix64(&s);
    return (float)(v >> 40) * (1.0f / 16777216.0f);
}

static uint64_t child_key(uint64_t key, uint32_t index)
{
    uint64_t s = key + UINT64_C(0xD1B54A32D192ED03) * (index + 1u);
    return mer_splitmix64(&s);
}

/* The metamers of shoot y of b (eq (14), with the 40° rule after the first
 * shoot) and their internode length l_s / m. */
static uint32_t shoot_plan(const builder *bd, const branch *b, uint32_t y, float *l_i)
{
    const merp_inv_def *d = bd->d;
    float l_s = b->l[y] - (y > b->born ? b->l[y - 1] : 0.0f);
    uint32_t m = merp_inv_metamers(&d->g[MERP_G_M], l_s, d->ls_max, d->m_max);
    if (y > b->born)
        m = merp_inv_phyllo_count(m, d->m_max);
    *l_i = l_s / (float)m;
    return m;
}

/* The length of metamer j of m in shoot y at the build's time. */
static float metamer_length(const builder *bd, uint32_t y, uint32_t j, uint32_t m, float l_i)
{
    if (y < bd->year)
        return l_i;
    return l_i * merp_inv_growth(&bd->d->g[MERP_G_E], bd->f, j, m, bd->d->span);
}

/* The branch's length at the build's time: its whole shoots and the part of the
 * growing one. */
static float current_length(const builder *bd, const branch *b)
{
    if (bd->year < b->born)
        return 0.0f;
    float total = bd->year > b->born ? b->l[bd->year - 1] : 0.0f, l_i;
    uint32_t m = shoot_plan(bd, b, bd->year, &l_i);
    for (uint32_t j = 0; j < m; j++)
        total += metamer_length(bd, bd->year, j, m, l_i);
    return total;
}

/* d turned by up to ±jitter/2 degrees about a keyed axis normal to it (§4.1's
 * stochastic variation of orientation). */
static void vary(const builder *bd, uint64_t key, uint32_t k, float d[3])
{
    if (!(bd->d->jitter > 0.0f))
        return;
    float axis[3], turned[3];
    v3_any_perp(d, axis);
    v3_rotate(axis, d, keyed(key, 2 * k) * MERP_TWO_PI, axis);
    float angle = (keyed(key, 2 * k + 1) - 0.5f) * bd->d->jitter * MER_DEG2RAD;
    v3_rotate(d, axis, angle, turned);
    memcpy(d, turned, sizeof turned);
    v3_normalize(d);
}

static mer_result grow_branch(builder *bd, const branch *b);

/* The lateral of the metamer `node` (j of m in shoot y of b, its key `key`),
 * when G04 makes it: its scale factor (eq (15)) reaches s_min, its order is
 * built, it has been born (the year after its shoot) and not shed (eq (11)). */
static mer_result lateral(builder *bd, const branch *b, uint32_t node, uint32_t y, uint32_t j,
                          uint32_t m, uint64_t key, float r_node)
{
    const merp_inv_def *d = bd->d;
    merp_skeleton *sk = bd->sk;
    if (y >= bd->year || b->order >= d->order_max) {
        merp_skel_bud_set(sk, node, 1, y >= bd->year ? MER_BUD_DORMANT : MER_BUD_NONE);
        return MER_OK;
    }
    float x = y > b->born ? b->l[y - 1] : 0.0f; /* the base of the parent shoot */
    float top = b->l[d->y_max] > 0.0f ? b->l[d->y_max] : 1.0f;
    float s_b = merp_inv_scale(&d->g[MERP_G_BS], x / top, b->s_b, &d->g[MERP_G_SS],
                               merp_inv_x_s(j, m));
    float a = merp_inv_lifespan(&d->g[MERP_G_A], s_b, d->a_max);
    if (s_b < d->s_min || !merp_inv_alive_at(a, y + 1, bd->t))
        return MER_OK;
    branch c = {.order = b->order + 1, .born = y + 1, .s_b = s_b, .r_cap = r_node,
                .key = child_key(key, 0), .attach = node, .slot = 1};
    float *l = bd->lens + (size_t)c.order * (d->y_max + 1);
    merp_inv_branch_lengths(d, b->l, x, c.born, c.order, s_b, l);
    c.l = l;
    merp_skel_node_end(sk, node, c.base);
    memcpy(c.dp, sk->dir + 3 * node, sizeof c.dp);
    memcpy(c.side, sk->side + 3 * node, sizeof c.side);
    float beta = merp_inv_branch_angle(d, merp_inv_s_theta(current_length(bd, &c), d->l_max));
    float twist = (keyed(c.key, UINT64_C(1) << 40) - 0.5f) * d->jitter;
    float s[3];
    v3_rotate(c.side, c.dp, twist * MER_DEG2RAD, s);
    float cb = cosf(beta * MER_DEG2RAD), sb = sinf(beta * MER_DEG2RAD);
    for (int k = 0; k < 3; k++)
        c.h0[k] = cb * c.dp[k] + sb * s[k];
    v3_normalize(c.h0);
    return grow_branch(bd, &c);
}

/* Whether the metamer of key `key` was cut (a binary search of the sorted
 * cuts); a cut found is marked hit. */
static int is_cut(merp_inv_keys *keys, uint64_t key)
{
    if (keys == NULL)
        return 0;
    uint32_t lo = 0, hi = keys->ncut;
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (keys->cut[mid] < key)
            lo = mid + 1;
        else
            hi = mid;
    }
    if (lo < keys->ncut && keys->cut[lo] == key) {
        if (keys->hit != NULL)
            keys->hit[lo] = 1;
        return 1;
    }
    return 0;
}

/* Records node id's key, leaf size and radius. */
static mer_result keep_key(builder *bd, uint32_t id, uint64_t key, float leaf, float radius)
{
    merp_inv_keys *k = bd->keys;
    if (k == NULL)
        return MER_OK;
    if (id >= k->cap) {
        uint32_t cap = k->cap ? k->cap : 1024;
        while (cap <= id)
            cap *= 2;
        uint64_t *of = merp_realloc(k->of, (size_t)cap * sizeof *of);
        if (of != NULL)
            k->of = of;
        float *lf = of != NULL ? merp_realloc(k->leaf, (size_t)cap * sizeof *lf) : NULL;
        if (lf != NULL)
            k->leaf = lf;
        float *r = lf != NULL ? merp_realloc(k->radius, (size_t)cap * sizeof *r) : NULL;
        if (r == NULL)
            return mer_error_set(bd->err, MER_ERR_NOMEM, NULL, "out of memory for node keys");
        k->radius = r;
        k->cap = cap;
    }
    k->of[id] = key;
    k->leaf[id] = leaf;
    k->radius[id] = radius;
    if (id >= k->used)
        k->used = id + 1;
    return MER_OK;
}

/* The leaf of metamer j of m in shoot y at the build's time: sized by G_l(x_s)
 * (§4.3) as far as G_lg has grown it; last year's leaves have fallen (Populus
 * is deciduous; Fig. 13's succession is within one year). */
static float leaf_of(const builder *bd, uint32_t y, uint32_t j, uint32_t m)
{
    if (y < bd->year)
        return 0.0f;
    const merp_inv_def *d = bd->d;
    return merp_inv_leaf_size(&d->g[MERP_G_L], merp_inv_x_s(j, m), d->leaf_size) *
           merp_inv_growth(&d->g[MERP_G_LG], bd->f, j, m, d->span);
}

/* A node after `prev` (slot `slot`) with its geometry and key: the plant's
 * root for the trunk's first metamer, else the id the key had in the tree
 * before when that one is free, else a new one. */
static mer_result put_node(builder *bd, const branch *b, uint32_t prev, uint32_t slot,
                           uint32_t y, uint64_t key, float leaf, float radius, uint32_t *out)
{
    merp_skeleton *sk = bd->sk;
    uint32_t id = bd->reuse;
    if (id == MER_NO_NODE) {
        id = bd->keys != NULL ? merp_inv_map_find(bd->keys->ids, key) : MER_NO_NODE;
        if (id != MER_NO_NODE && id < sk->n && !sk->alive[id]) {
            merp_skel_node_renew(sk, id, y);
        } else {
            mer_result rc = merp_skel_node_new(sk, y, &id, bd->err);
            if (rc != MER_OK)
                return rc;
        }
        sk->parent[id] = prev;
        sk->slot[id] = (uint8_t)slot;
        sk->child[3 * prev + slot] = id;
    }
    mer_result rc = keep_key(bd, id, key, leaf, radius);
    if (rc != MER_OK)
        return rc;
    bd->reuse = MER_NO_NODE;
    sk->born[id] = y;
    sk->plant[id] = bd->plant;
    sk->order[id] = b->order;
    *out = id;
    return MER_OK;
}

/* The metamers of b at the build's time, each headed by eqs (8)–(9), with their
 * laterals; the tip keeps a terminal bud. A cut metamer ends the branch. */
static mer_result grow_branch(builder *bd, const branch *b)
{
    const merp_inv_def *d = bd->d;
    merp_skeleton *sk = bd->sk;
    float L = current_length(bd, b);
    if (!(L > 0.0f))
        return MER_OK;
    float s_theta = merp_inv_s_theta(L, d->l_max), pos[3], side[3], along = 0.0f;
    float r_b = merp_inv_base_radius(d, L, b->r_cap);
    memcpy(pos, b->base, sizeof pos);
    memcpy(side, b->side, sizeof side);
    uint32_t prev = b->attach, slot = b->slot, index = 0;
    int cut = 0;
    for (uint32_t y = b->born; y <= bd->year && !cut; y++) {
        float l_i;
        uint32_t m = shoot_plan(bd, b, y, &l_i);
        for (uint32_t j = 0; j < m; j++, index++) {
            float len = metamer_length(bd, y, j, m, l_i);
            if (!(len > 0.0f))
                break; /* it and the metamers above it have not started */
            uint64_t key = child_key(b->key, (y << 10) | j);
            if ((cut = is_cut(bd->keys, key)) != 0)
                break;
            float theta = merp_inv_heading(&d->g[MERP_G_O1], &d->g[MERP_G_O2], s_theta,
                                           (along + 0.5f * len) / L, d->theta_max);
            uint32_t id;
            float r = merp_inv_radius(&d->g[MERP_G_R], along / L, r_b);
            mer_result rc = put_node(bd, b, prev, slot, y, key, leaf_of(bd, y, j, m), r, &id);
            if (rc != MER_OK)
                return rc;
            float *dir = sk->dir + 3 * id;
            merp_inv_orient(b->h0, b->dp, theta, dir);
            vary(bd, b->key, index, dir);
            merp_side_next(side, dir, MERP_INV_DIVERGENCE, side);
            memcpy(sk->side + 3 * id, side, sizeof side);
            memcpy(sk->pos + 3 * id, pos, sizeof pos);
            sk->len[id] = len;
            merp_skel_node_end(sk, id, pos);
            along += len;
            rc = lateral(bd, b, id, y, j, m, key, r);
            if (rc != MER_OK)
                return rc;
            prev = id;
            slot = 0;
        }
    }
    if (prev != b->attach && !cut)
        merp_skel_bud_set(sk, prev, 0, MER_BUD_DORMANT);
    return MER_OK;
}

/* Kills the root's subtree below it and unlinks every node of it: a rebuilt
 * tree is not a shed one, so the pipe model must not remember the old wood,
 * and a node left out of the new tree must not seem cut from a live one. */
static mer_result clear(merp_skeleton *sk, uint32_t root, mer_error *err)
{
    for (uint32_t k = 0; k < 3; k++) {
        uint32_t c = sk->child[3 * root + k];
        size_t cnt;
        if (c != MER_NO_NODE) {
            mer_result rc = merp_skel_subtree(sk, c, &cnt, err);
            if (rc == MER_OK)
                rc = merp_skel_kill(sk, c, err); /* the same walk again: cnt holds */
            if (rc != MER_OK)
                return rc;
            for (size_t t = 0; t < cnt; t++)
                sk->parent[sk->stack[t]] = MER_NO_NODE;
        }
        merp_skel_bud_set(sk, root, k, MER_BUD_NONE);
    }
    return MER_OK;
}

mer_result merp_inv_build(const merp_inv_def *d, double t, uint64_t seed, merp_skeleton *sk,
                          uint32_t root, merp_inv_keys *keys, mer_error *err)
{
    assert(d != NULL && sk != NULL && root < sk->n && sk->alive[root]);
    assert(t >= 0.0 && t <= (double)d->y_max);
    mer_result rc = clear(sk, root, err);
    if (rc != MER_OK)
        return rc;
    builder bd = {.d = d, .sk = sk, .t = t, .plant = sk->plant[root],
                  .reuse = root, .keys = keys, .err = err};
    bd.year = t > 0.0 ? (uint32_t)ceil(t) : 0;
    bd.f = t > 0.0 ? (float)(t - (double)(bd.year - 1)) : 1.0f;
    size_t row = d->y_max + 1;
    bd.lens = merp_malloc((d->order_max + 1) * row * sizeof *bd.lens);
    if (bd.lens == NULL)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for branch lengths");
    merp_inv_trunk_lengths(d, bd.lens);
    branch trunk = {.order = 0, .born = 0, .s_b = 1.0f, .r_cap = -1.0f, .l = bd.lens,
                    .attach = MER_NO_NODE};
    uint64_t s = seed ^ (UINT64_C(0x632BE59BD9B4E019) * (bd.plant + 1u));
    trunk.key = mer_splitmix64(&s);
    memcpy(trunk.base, sk->pos + 3 * root, sizeof trunk.base);
    trunk.h0[1] = trunk.dp[1] = 1.0f;
    /* The first side from the key, not from the root, whose side the build
     * overwrites: each rebuild must start the spiral where the last one did. */
    float azimuth = keyed(trunk.key, 0) * MERP_TWO_PI;
    trunk.side[0] = cosf(azimuth);
    trunk.side[2] = sinf(azimuth);
    rc = grow_branch(&bd, &trunk);
    merp_free(bd.lens);
    return rc;
}
