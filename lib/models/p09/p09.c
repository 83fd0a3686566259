/* meristem — one P09 step (P09 Fig. 3 right): environment, basipetal pass,
 * shedding, bud fate, new shoots; a second round in sylleptic mode. The pipe
 * model's diameters are the scene's, after the step (skeleton/pipe.c). See
 * scene.h for the choices made. */
#include "config.h"

#include <assert.h>
#include <stdlib.h>
#include <string.h>

#include <meristem/fate.h>

#include "core/alloc.h"
#include "core/array.h"
#include "core/bytes.h"
#include "models/p09/p09.h"

static mer_result p09_create(const mer_params *p, merp_model **out, mer_error *err)
{
    (void)p;
    assert(out != NULL);
    *out = merp_calloc(1, sizeof **out);
    if (*out == NULL)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the P09 model");
    return MER_OK;
}

static void p09_free(merp_model *m)
{
    if (m == NULL)
        return;
    void *arrays[] = {m->sub,  m->vin,  m->qb,    m->vb,    m->quiet, m->mark,  m->cell,
                      m->bkey, m->bpos, m->bdir,  m->bq,    m->bv,    m->bquiet, m->pq,
                      m->pv,   m->pbuds, m->prank, m->pscr, m->ptarget, m->ax,   m->aend,
                      m->abase};
    for (size_t i = 0; i < sizeof arrays / sizeof arrays[0]; i++)
        merp_free(arrays[i]);
    merp_free(m);
}

static mer_result p09_clone(const merp_model *m, merp_model **out, mer_error *err)
{
    assert(m != NULL && out != NULL);
    merp_model *c = merp_calloc(1, sizeof *c);
    *out = NULL;
    if (c == NULL)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the P09 model");
    /* The per-node state; the per-round scratch starts empty, as in a new model. */
    size_t c1 = m->cap, c3 = 3 * (size_t)m->cap;
    int ok = MERP_DUP(c->sub, m->sub, c1) &&
             MERP_DUP(c->vin, m->vin, c1) && MERP_DUP(c->qb, m->qb, c3) &&
             MERP_DUP(c->vb, m->vb, c3) && MERP_DUP(c->quiet, m->quiet, c3) &&
             MERP_DUP(c->mark, m->mark, c1);
    if (!ok) {
        p09_free(c);
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the P09 model");
    }
    c->n = m->n;
    c->cap = m->cap;
    *out = c;
    return MER_OK;
}

static void p09_save(const merp_model *m, merp_bytes_out *out)
{
    size_t n1 = m->n, n3 = 3 * (size_t)m->n;
    merp_put_u32(out, m->n);
    /* the counts as two arrays, as the state has always been written */
    for (size_t i = 0; i < n1; i++)
        merp_put_u32(out, m->sub[i].nbuds);
    for (size_t i = 0; i < n1; i++)
        merp_put_u32(out, m->sub[i].nint);
    merp_put(out, m->vin, n1 * sizeof *m->vin);
    merp_put(out, m->qb, n3 * sizeof *m->qb);
    merp_put(out, m->vb, n3 * sizeof *m->vb);
    merp_put(out, m->quiet, n3 * sizeof *m->quiet);
    merp_put(out, m->mark, n1 * sizeof *m->mark);
}

/* Reads the subtree counts, saved as two arrays (nbuds, then nint), into a
 * new array of records at *out. Returns 0 when the input is bad or memory runs out
 * (in->bad says which), else 1. */
static int get_counts(merp_bytes_in *in, merp_p09_sub **out, size_t n)
{
    uint32_t *nbuds = NULL, *nint = NULL;
    int ok = MERP_GET_ARRAY(in, nbuds, n) && MERP_GET_ARRAY(in, nint, n);
    if (ok && n > 0 && (*out = merp_calloc(n, sizeof **out)) == NULL) {
        in->bad = 2;
        ok = 0;
    }
    for (size_t i = 0; ok && i < n; i++)
        (*out)[i] = (merp_p09_sub){.q = 0.0f, .nbuds = nbuds[i], .nint = nint[i], .afrom = 0};
    merp_free(nbuds);
    merp_free(nint);
    return ok;
}

static mer_result p09_load(merp_bytes_in *in, uint32_t nodes, merp_model **out, mer_error *err)
{
    *out = NULL;
    merp_model *m = merp_calloc(1, sizeof *m);
    if (m == NULL)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the P09 model");
    uint32_t n = merp_get_u32(in);
    if (n > nodes) /* it has seen at most the skeleton's nodes */
        in->bad = 1;
    size_t n1 = n, n3 = 3 * (size_t)n;
    (void)(get_counts(in, &m->sub, n1) && MERP_GET_ARRAY(in, m->vin, n1) &&
           MERP_GET_ARRAY(in, m->qb, n3) && MERP_GET_ARRAY(in, m->vb, n3) &&
           MERP_GET_ARRAY(in, m->quiet, n3) && MERP_GET_ARRAY(in, m->mark, n1));
    if (in->bad) {
        p09_free(m);
        return in->bad == 2 ? mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the P09 model")
                            : mer_error_set(err, MER_ERR_FORMAT, "model", "damaged P09 state");
    }
    m->n = m->cap = n;
    *out = m;
    return MER_OK;
}

/* Maps the pages of the per-node arrays for the nodes [from, to), about to be
 * written for the first time: one call per array, not a fault per page. */
static void map_nodes(merp_model *m, uint32_t from, uint32_t to)
{
    size_t f1 = from, t1 = to, f3 = 3 * (size_t)from, t3 = 3 * (size_t)to;
    merp_prefault(m->sub, f1 * sizeof *m->sub, t1 * sizeof *m->sub);
    merp_prefault(m->vin, f1 * sizeof *m->vin, t1 * sizeof *m->vin);
    merp_prefault(m->qb, f3 * sizeof *m->qb, t3 * sizeof *m->qb);
    merp_prefault(m->vb, f3 * sizeof *m->vb, t3 * sizeof *m->vb);
    merp_prefault(m->quiet, f3 * sizeof *m->quiet, t3 * sizeof *m->quiet);
    merp_prefault(m->mark, f1, t1);
    if (to <= m->ax_cap) { /* the axes' arrays, under the priority model */
        merp_prefault(m->ax, f1 * sizeof *m->ax, t1 * sizeof *m->ax);
        merp_prefault(m->aend, f1 * sizeof *m->aend, t1 * sizeof *m->aend);
    }
}

/* Gives the nodes made since the last round (by the model's shoots, new plants)
 * their starting per-node state; under the priority model it sizes the axis
 * records too. */
static mer_result p09_sync(merp_model *m, const merp_skeleton *sk, int priority, mer_error *err)
{
    if (sk->cap > m->cap) {
        size_t c1 = sk->cap, c3 = 3 * (size_t)sk->cap;
        if (!MERP_RESIZE(m->sub, c1) || !MERP_RESIZE(m->vin, c1) || !MERP_RESIZE(m->qb, c3) ||
            !MERP_RESIZE(m->vb, c3) || !MERP_RESIZE(m->quiet, c3) || !MERP_RESIZE(m->mark, c1))
            return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for nodes");
        m->cap = sk->cap;
    }
    if (priority && m->ax_cap < sk->n) {
        if (!MERP_RESIZE(m->ax, sk->cap) || !MERP_RESIZE(m->aend, sk->cap) ||
            !MERP_RESIZE(m->abase, sk->cap))
            return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the axes");
        m->ax_cap = sk->cap;
    }
    map_nodes(m, m->n, sk->n);
    for (uint32_t i = m->n; i < sk->n; i++) {
        for (int k = 0; k < 3; k++) {
            m->qb[3 * i + k] = 0.0f;
            m->vb[3 * i + k] = 0.0f;
            m->quiet[3 * i + k] = 0;
        }
        m->sub[i] = (merp_p09_sub){.q = 0.0f, .nbuds = 0, .nint = 1, .afrom = 0};
        m->vin[i] = 0.0f;
        m->mark[i] = 0;
    }
    m->n = sk->n;
    return MER_OK;
}

/* The Q of node i's buds from the light of its voxel (m->light), for the buds
 * that may grow (listed downward in m->bkey, from its last slot, so that the
 * list reads upward in key order), 0 for the others; their v starts at 0. The
 * environment input of a round whose V waits (environment.c). */
static inline void read_light(merp_model *m, const merp_world *w, uint32_t i)
{
    const merp_skeleton *sk = w->sk;
    float q = -1.0f; /* read on the first listed bud */
    for (uint32_t k = 3; k-- > 0;) {
        float qk = 0.0f;
        if (merp_skel_bud_exists(sk, i, k, w->p->buds_per_node) &&
            (m->lit_every || merp_p09_may_grow(m, w, i, k, m->lit_syllepsis))) {
            m->bkey[--m->bfirst] = 3 * i + k;
            if (q < 0.0f)
                q = merp_light_at(&m->light, m->cell[i]);
            qk = q;
        }
        m->qb[3 * i + k] = qk;
        m->vb[3 * i + k] = 0.0f;
    }
}

/* Basipetal pass: light Q of the buds that may grow, the number of living
 * (dormant) buds, and the internode count, per subtree. The priority model sorts
 * branches by Q per living bud (P09 Fig. 8b: 2.1/3), so shaded buds count. Under
 * the priority model it also leaves each node's axis record (m->ax), read while
 * its children's values are at hand. When the environment left the buds' light
 * to it (m->lit_pending), it reads each node's first: the light's random reads
 * of the shadow grid then overlap the sums' work instead of a pass of their own. */
static void basipetal(merp_model *m, const merp_world *w)
{
    merp_skeleton *sk = w->sk;
    uint32_t bpn = w->p->buds_per_node;
    merp_p09_axnode *ax = w->p->fate == MER_FATE_PRIORITY ? m->ax : NULL;
    int lit = m->lit_pending;
    size_t listed_end = m->bfirst;
    for (uint32_t i = sk->n; i-- > 0;) {
        if (i >= MERP_P09_AHEAD) {
            uint32_t j = i - MERP_P09_AHEAD;
            merp_p09_fetch_children(m, sk, j, 0);
            if (ax != NULL) /* a record may straddle two cache lines */
                __builtin_prefetch((const char *)(ax + j) + sizeof *ax - 1, 1);
            if (lit)
                merp_light_prefetch(&m->light, m->cell[j]);
        }
        if (!sk->alive[i])
            continue;
        if (lit)
            read_light(m, w, i);
        float q = 0.0f, qk[3];
        uint32_t nb = 0, ni = 1, nbk[3];
        const uint32_t *child = sk->child + 3 * i;
        for (uint32_t k = 0; k < 3; k++) {
            uint32_t c = child[k];
            qk[k] = 0.0f;
            nbk[k] = 0;
            if (c != MER_NO_NODE) {
                const merp_p09_sub *sc = m->sub + c;
                qk[k] = sc->q;
                nbk[k] = sc->nbuds;
                q += qk[k];
                nb += nbk[k];
                ni += sc->nint;
            } else if (merp_skel_bud_exists(sk, i, k, bpn)) {
                qk[k] = m->qb[3 * i + k];
                nbk[k] = 1;
                q += qk[k];
                nb++;
            }
        }
        sk->q[i] = q;
        merp_p09_sub *s = m->sub + i;
        s->q = q;
        s->nbuds = nb;
        s->nint = ni;
        if (ax != NULL) {
            merp_p09_axnode *a = ax + i;
            a->next = child[0] != MER_NO_NODE ? child[0] : nbk[0] ? MERP_AX_TIP_BUD : MERP_AX_TIP;
            a->q_tip = qk[0];
            /* the items priority.c lists for this node: a lateral branch or
             * bud per slot, the terminal bud at a tip; and the rest of the axis's */
            uint32_t items = a->next == MERP_AX_TIP_BUD;
            for (int k = 0; k < 2; k++) {
                a->child[k] = child[k + 1];
                a->buds[k] = nbk[k + 1];
                a->q[k] = qk[k + 1];
                items += child[k + 1] != MER_NO_NODE || nbk[k + 1] != 0;
            }
            s->afrom = items + (merp_p09_continues(child[0]) ? m->sub[child[0]].afrom : 0);
        }
    }
    if (lit) {
        m->bn = listed_end - m->bfirst;
        m->lit_pending = 0;
    }
}

/* The buds left listed by merp_p09_directions grow their shoots. */
static mer_result grow_buds(merp_model *m, const merp_world *w, mer_error *err)
{
    const merp_skeleton *sk = w->sk;
    size_t nb = m->bn;
    for (size_t b = 0; b < nb; b++) {
        uint32_t key = m->bkey[b];
        uint32_t i = key / 3, k = key % 3;
        if (!sk->alive[i] || sk->bud[key] != MER_BUD_DORMANT)
            continue;
        float l;
        uint32_t n = mer_shoot_size(m->vb[key], w->p->max_shoot, w->p->internode_length, &l);
        if (n == 0)
            continue;
        float V[3];
        memcpy(V, m->bv + 3 * b, sizeof V);
        mer_result rc = merp_p09_grow_shoot(w, i, k, n, l, V, err);
        if (rc != MER_OK)
            return rc;
    }
    return MER_OK;
}

static mer_result round_(merp_model *m, const merp_world *w, int syllepsis, mer_error *err)
{
    /* No shedding while growth is constrained to one bud: the other buds' Q is
     * held at 0 then, which says nothing about their light. */
    int shed = !syllepsis && w->p->shed_threshold > 0.0f && w->sk->con_node == MER_NO_NODE;
    mer_result rc = p09_sync(m, w->sk, w->p->fate == MER_FATE_PRIORITY, err);
    /* Shedding lifts shadows before the shoots grow: V cannot wait for it. */
    if (rc == MER_OK)
        rc = merp_p09_environment(m, w, syllepsis, !shed, err);
    if (rc != MER_OK)
        return rc;
    basipetal(m, w);
    if (shed) {
        uint32_t shed_count;
        rc = merp_p09_shed(m, w, &shed_count, err);
        if (rc != MER_OK)
            return rc;
        if (shed_count > 0)
            basipetal(m, w);
    }
    if (w->p->fate == MER_FATE_PRIORITY)
        rc = merp_p09_allocate_priority(m, w, err);
    else
        merp_p09_allocate_bh(m, w);
    if (rc != MER_OK)
        return rc;
    merp_p09_directions(m, w);
    /* Nothing reads the shadow grid while the shoots grow. */
    merp_env_batch_begin(w->env);
    rc = grow_buds(m, w, err);
    merp_env_batch_end(w->env);
    return rc;
}

static mer_result p09_step(merp_model *m, const merp_world *w, mer_error *err)
{
    assert(m != NULL && w != NULL);
    mer_result rc = round_(m, w, 0, err);
    if (rc == MER_OK && w->p->sylleptic)
        rc = round_(m, w, 1, err);
    return rc;
}

/* Its state is a cache of the last round: the scene hash has never included it. */
static uint64_t p09_hash(const merp_model *m, uint64_t h)
{
    (void)m;
    return h;
}

const merp_model_ops merp_p09_ops = {
    .name = "p09",
    .param_rows = MERP_ROWS_P09,
    .state_version = 1,
    .validate = merp_p09_validate,
    .create = p09_create,
    /* P09 reads its parameters from the world at each step and derives its
     * per-node state anew in each round: nothing to do on a parameter change
     * (set_params) or an edit (nodes_changed). */
    .step = p09_step,
    .hash = p09_hash,
    .free = p09_free,
    .clone = p09_clone,
    .save = p09_save,
    .load = p09_load,
};
