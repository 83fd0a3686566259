/* meristem — one iteration of the space colonization algorithm of Runions, Lane
 * & Prusinkiewicz 2007 per step (runions.h): association (associate.c), then one
 * new node of length D per node with points, then the kill zones of the new
 * nodes. */
#include "config.h"

#include <assert.h>
#include <string.h>

#include "core/alloc.h"
#include "core/array.h"
#include "core/bytes.h"
#include "core/vec.h"
#include "env/noise.h"
#include "models/runions/runions.h"

static mer_result runions_validate(const mer_params *p, mer_error *err)
{
    if (p->environment != MER_ENV_MARKERS)
        return mer_error_set(err, MER_ERR_INVALID, "environment",
                             "the runions model grows towards attraction points: set environment "
                             "to 1 (markers), or start from the preset runions-2007");
    if (!(p->d_k < p->d_i))
        return mer_error_set(err, MER_ERR_RANGE, "d_k",
                             "d_k (%g) must be below d_i (%g): a point is removed before it "
                             "could attract a node", (double)p->d_k, (double)p->d_i);
    return MER_OK;
}

static mer_result runions_create(const mer_params *p, merp_model **out, mer_error *err)
{
    (void)p;
    assert(out != NULL);
    *out = merp_calloc(1, sizeof **out);
    if (*out == NULL)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the runions model");
    return MER_OK;
}

static void runions_free(merp_model *m)
{
    if (m == NULL)
        return;
    void *arrays[] = {m->sum, m->count, m->ok, m->start, m->gid, m->gp, m->pts};
    for (size_t i = 0; i < sizeof arrays / sizeof arrays[0]; i++)
        merp_free(arrays[i]);
    merp_free(m);
}

static mer_result ensure_nodes(merp_model *m, size_t n, mer_error *err)
{
    if (n <= m->node_cap)
        return MER_OK;
    if (!MERP_RESIZE(m->sum, 3 * n) || !MERP_RESIZE(m->count, n) || !MERP_RESIZE(m->ok, n))
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for nodes");
    m->node_cap = n;
    return MER_OK;
}

static int free_slot(const merp_skeleton *sk, uint32_t i)
{
    for (uint32_t k = 0; k < 3; k++)
        if (sk->child[3 * i + k] == MER_NO_NODE)
            return (int)k;
    return -1;
}

/* Which nodes take part in association: alive, with a free slot, and inside the
 * brush constraint's subtree when there is one. */
static mer_result mark_eligible(merp_model *m, merp_skeleton *sk, mer_error *err)
{
    int constrained = sk->con_node != MER_NO_NODE;
    for (uint32_t i = 0; i < sk->n; i++)
        m->ok[i] = !constrained && sk->alive[i] && free_slot(sk, i) >= 0;
    if (!constrained)
        return MER_OK;
    size_t count;
    mer_result rc = merp_skel_subtree(sk, sk->con_node, &count, err);
    if (rc != MER_OK)
        return rc;
    for (size_t t = 0; t < count; t++) {
        uint32_t i = sk->stack[t];
        m->ok[i] = free_slot(sk, i) >= 0;
    }
    return MER_OK;
}

/* The new node c from node i's end along unit d, in i's first free slot. */
static void place(merp_skeleton *sk, const mer_params *p, uint32_t i, uint32_t c,
                  const float start[3], const float d[3], float l)
{
    uint32_t k = (uint32_t)free_slot(sk, i);
    sk->parent[c] = i;
    sk->slot[c] = (uint8_t)k;
    sk->child[3 * i + k] = c;
    memcpy(sk->pos + 3 * c, start, 3 * sizeof *start);
    memcpy(sk->dir + 3 * c, d, 3 * sizeof *d);
    sk->len[c] = l;
    sk->order[c] = sk->order[i] + (k > 0 ? 1u : 0u);
    sk->plant[c] = sk->plant[i];
    merp_side_next(sk->side + 3 * i, d, p->divergence, sk->side + 3 * c);
    merp_skel_bud_set(sk, i, k, MER_BUD_NONE);
    merp_skel_bud_set(sk, c, 0, MER_BUD_DORMANT);
}

/* Step 3 and 4 of runions.h for the nodes [0, n) that have points. */
static mer_result grow(merp_model *m, const merp_world *w, uint32_t n, mer_error *err)
{
    merp_skeleton *sk = w->sk;
    for (uint32_t i = 0; i < n; i++) {
        if (m->count[i] == 0)
            continue;
        float d[3], start[3], end[3], l = w->p->D;
        memcpy(d, m->sum + 3 * i, sizeof d);
        if (!v3_normalize(d))
            continue;
        merp_skel_node_end(sk, i, start);
        merp_noise_internode(w->noise, w->p, start, d, &l);
        for (int a = 0; a < 3; a++)
            end[a] = start[a] + d[a] * l;
        if (merp_env_blocked(w->env, end))
            continue;
        uint32_t c;
        mer_result rc = merp_skel_node_new(sk, w->step, &c, err);
        if (rc != MER_OK)
            return rc;
        place(sk, w->p, i, c, start, d, l);
        mer_markers_remove_sphere(w->env->markers, end, w->p->d_k);
    }
    return MER_OK;
}

static mer_result runions_step(merp_model *m, const merp_world *w, mer_error *err)
{
    assert(m != NULL && w != NULL);
    merp_skeleton *sk = w->sk;
    mer_markers *mk = w->env->markers;
    uint32_t n = sk->n;
    mer_result rc = ensure_nodes(m, n, err);
    if (rc == MER_OK)
        rc = mark_eligible(m, sk, err);
    size_t killed;
    if (rc == MER_OK)
        rc = merp_runions_associate(m, sk, mk, w->p->d_i, w->p->d_k, &killed, err);
    if (rc != MER_OK)
        return rc;
    /* A point is removed where it lies: a sphere of radius 0 around it. */
    for (size_t j = 0; j < killed; j++)
        mer_markers_remove_sphere(mk, m->pts + 3 * j, 0.0f);
    return grow(m, w, n, err);
}

static uint64_t runions_hash(const merp_model *m, uint64_t h)
{
    (void)m;
    return h;
}

static mer_result runions_clone(const merp_model *m, merp_model **out, mer_error *err)
{
    (void)m;
    return runions_create(NULL, out, err);
}

static void runions_save(const merp_model *m, merp_bytes_out *out)
{
    (void)m;
    (void)out;
}

static mer_result runions_load(merp_bytes_in *in, uint32_t nodes, merp_model **out,
                               mer_error *err)
{
    (void)in;
    (void)nodes;
    return runions_create(NULL, out, err);
}

const merp_model_ops merp_runions_ops = {
    .name = "runions",
    .param_rows = MERP_ROWS_RUNIONS,
    .state_version = 1,
    .validate = runions_validate,
    .create = runions_create,
    /* No set_params, no nodes_changed: R07 reads its parameters at each step and
     * keeps nothing between steps. */
    .step = runions_step,
    .hash = runions_hash,
    .free = runions_free,
    .clone = runions_clone,
    .save = runions_save,
    .load = runions_load,
};
