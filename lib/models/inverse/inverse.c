/* meristem — the inverse model of G04 §4 as a growth model (model.h): one step
 * is one year, and the tree after n steps is its definition at year n, rebuilt
 * whole (the model is a function of time, build.c). The seed of its variation is
 * drawn once from the scene's stream, at the first tree it shows.
 *
 * Prunes and bends outlive the rebuilds (regrow.c): when nodes are removed, the
 * keys of the metamers cut (build.c) are kept, and a bend is recorded by its
 * node's key; every later tree ends those branches there and makes the bends
 * again, in any year and under any definition where the metamer still exists. */
#include "config.h"

#include <assert.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <meristem/edit.h>

#include "core/alloc.h"
#include "core/bytes.h"
#include "core/hash.h"
#include "models/inverse/inverse.h"
#include "scene_private.h"


/* The definition's text again, after def changed. */
static void retext(merp_model *m)
{
    merp_free(m->text);
    m->text = merp_inv_def_write(&m->def, &m->tlen);
    if (m->text == NULL)
        m->tlen = 0;
}

static mer_result inverse_create(const mer_params *p, merp_model **out, mer_error *err)
{
    (void)p;
    merp_model *m = merp_calloc(1, sizeof *m);
    if (m == NULL)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the inverse model");
    mer_result rc = merp_inv_populus(&m->def, err);
    if (rc != MER_OK) {
        merp_free(m);
        return rc;
    }
    retext(m);
    *out = m;
    return MER_OK;
}

static mer_result inverse_step(merp_model *m, const merp_world *w, mer_error *err)
{
    uint32_t year = w->step + 1;
    if (year > m->def.y_max)
        return mer_error_set(err, MER_ERR_LIMIT, "count",
                             "this tree is defined for %u years", m->def.y_max);
    return merp_inv_show(m, w, (double)year, err);
}

/* Adds `key` to the sorted cuts; 0 when out of memory. */
static int add_cut(merp_model *m, uint64_t key)
{
    uint32_t at = 0, n = m->keys.ncut;
    while (at < n && m->cuts[at] < key)
        at++;
    if (at < n && m->cuts[at] == key)
        return 1;
    if (n == m->cap_cuts) {
        uint32_t cap = m->cap_cuts ? 2 * m->cap_cuts : 16;
        uint64_t *cuts = merp_realloc(m->cuts, (size_t)cap * sizeof *cuts);
        if (cuts != NULL)
            m->cuts = cuts;
        uint8_t *hit = cuts != NULL ? merp_realloc(m->hit, cap) : NULL;
        if (hit == NULL)
            return 0;
        m->hit = hit;
        m->cap_cuts = cap;
    }
    memmove(m->cuts + at + 1, m->cuts + at, (size_t)(n - at) * sizeof *m->cuts);
    m->cuts[at] = key;
    m->keys.cut = m->cuts;
    m->keys.ncut = n + 1;
    return 1;
}

/* A removed node whose parent lives is where a prune cut: its key joins the
 * cuts. Out of memory, a cut is forgotten at the next rebuild (this hook cannot
 * fail); the tree shown now keeps it either way. O(nodes of the last build). */
static void inverse_nodes_changed(merp_model *m, const merp_world *w)
{
    const merp_skeleton *sk = w->sk;
    for (uint32_t i = 0; i < sk->n && i < m->keys.used; i++) {
        uint32_t p = sk->parent[i];
        if (!sk->alive[i] && p != MER_NO_NODE && sk->alive[p])
            (void)add_cut(m, m->keys.of[i]);
    }
}

/* After the pipe model's: every node the last build made gets the diameter of
 * G04 §4.1's radius function (radius.c). O(nodes). */
static void inverse_diameters(const merp_model *m, const merp_world *w)
{
    merp_skeleton *sk = w->sk;
    for (uint32_t i = 0; i < sk->n && i < m->keys.used; i++)
        if (sk->alive[i] && m->keys.of[i] != 0)
            sk->dn[i] = powf(2.0f * m->keys.radius[i], sk->pipe_n);
}

static uint64_t inverse_hash(const merp_model *m, uint64_t h)
{
    h = merp_fnv(h, &m->def, sizeof m->def);
    h = merp_fnv(h, &m->seed, sizeof m->seed);
    h = merp_fnv(h, &m->t, sizeof m->t);
    h = merp_fnv(h, m->cuts, (size_t)m->keys.ncut * sizeof *m->cuts);
    for (uint32_t k = 0; k < m->nbends; k++) {
        const merp_inv_bend *b = &m->bends[k];
        h = merp_fnv(h, &b->key, sizeof b->key);
        h = merp_fnv(h, b->axis, sizeof b->axis);
        h = merp_fnv(h, &b->angle, sizeof b->angle);
        h = merp_fnv(h, &b->spread, sizeof b->spread);
    }
    return h;
}

static mer_result inverse_bending(merp_model *m, const merp_world *w, uint32_t node,
                                  const float axis[3], float angle, uint32_t spread,
                                  mer_error *err)
{
    return merp_inv_record_bend(m, w->sk, node, axis, angle, spread, err);
}

/* Every node's leaf is the model's (G_l as grown by G_lg): none but this year's. */
static float inverse_leaf(const merp_model *m, const merp_skeleton *sk, uint32_t id)
{
    float leaf = id < m->keys.used && id < sk->n && sk->alive[id] && m->seeded
                     ? m->keys.leaf[id]
                     : 0.0f;
    return leaf > 0.0f ? leaf : -1.0f;
}

static void inverse_free(merp_model *m)
{
    if (m == NULL)
        return;
    merp_free(m->keys.of);
    merp_free(m->keys.leaf);
    merp_free(m->keys.radius);
    merp_free(m->cuts);
    merp_free(m->hit);
    merp_free(m->bends);
    merp_inv_map_free(&m->ids);
    merp_free(m->text);
    merp_free(m);
}

static mer_result inverse_clone(const merp_model *m, merp_model **out, mer_error *err)
{
    merp_model *c = merp_malloc(sizeof *c);
    if (c == NULL)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the inverse model");
    memcpy(c, m, sizeof *c);
    c->keys.of = NULL;
    c->keys.leaf = NULL;
    c->keys.radius = NULL;
    c->cuts = NULL;
    c->hit = NULL;
    c->bends = NULL;
    memset(&c->ids, 0, sizeof c->ids);
    c->text = NULL;
    retext(c);
    size_t cap = m->keys.cap;
    if (cap > 0) {
        c->keys.of = merp_malloc(cap * sizeof *c->keys.of);
        c->keys.leaf = merp_malloc(cap * sizeof *c->keys.leaf);
        c->keys.radius = merp_malloc(cap * sizeof *c->keys.radius);
    }
    if (m->cap_cuts > 0) {
        c->cuts = merp_malloc((size_t)m->cap_cuts * sizeof *c->cuts);
        c->hit = merp_malloc(m->cap_cuts);
    }
    if (m->cap_bends > 0)
        c->bends = merp_malloc((size_t)m->cap_bends * sizeof *c->bends);
    if (c->text == NULL ||
        (cap > 0 && (c->keys.of == NULL || c->keys.leaf == NULL || c->keys.radius == NULL)) ||
        (m->cap_cuts > 0 && (c->cuts == NULL || c->hit == NULL)) ||
        (m->cap_bends > 0 && c->bends == NULL)) {
        inverse_free(c);
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the inverse model");
    }
    if (cap > 0) {
        memcpy(c->keys.of, m->keys.of, cap * sizeof *c->keys.of);
        memcpy(c->keys.leaf, m->keys.leaf, cap * sizeof *c->keys.leaf);
        memcpy(c->keys.radius, m->keys.radius, cap * sizeof *c->keys.radius);
    }
    if (m->keys.ncut > 0)
        memcpy(c->cuts, m->cuts, (size_t)m->keys.ncut * sizeof *c->cuts);
    if (m->nbends > 0)
        memcpy(c->bends, m->bends, (size_t)m->nbends * sizeof *c->bends);
    c->keys.cut = c->cuts;
    *out = c;
    return MER_OK;
}

/* The checkpoint: the definition (its samples are recomputed on loading), the
 * seed, the time shown, the edits the last rebuild dropped, each built node's key,
 * leaf and radius, the cuts and the bends. Host byte order, as every checkpoint. */
static void inverse_save(const merp_model *m, merp_bytes_out *out)
{
    merp_put(out, &m->def, sizeof m->def);
    merp_put_u64(out, m->seed);
    merp_put_u32(out, (uint32_t)m->seeded);
    merp_put(out, &m->t, sizeof m->t);
    merp_put_u32(out, m->dropped);
    merp_put_u32(out, m->keys.used);
    merp_put(out, m->keys.of, (size_t)m->keys.used * sizeof *m->keys.of);
    merp_put(out, m->keys.leaf, (size_t)m->keys.used * sizeof *m->keys.leaf);
    merp_put(out, m->keys.radius, (size_t)m->keys.used * sizeof *m->keys.radius);
    merp_put_u32(out, m->keys.ncut);
    merp_put(out, m->cuts, (size_t)m->keys.ncut * sizeof *m->cuts);
    merp_put_u32(out, m->nbends);
    for (uint32_t k = 0; k < m->nbends; k++) {
        const merp_inv_bend *b = &m->bends[k];
        merp_put_u64(out, b->key);
        merp_put(out, b->axis, sizeof b->axis);
        merp_put(out, &b->angle, sizeof b->angle);
        merp_put_u32(out, b->spread);
    }
}

/* Whether what was read holds together: a valid definition, a time in its
 * range, ids within the skeleton's, cuts sorted. */
static int loaded_ok(merp_model *m, uint32_t nodes)
{
    if (merp_inv_def_check(&m->def, NULL) != MER_OK || m->seeded > 1 ||
        !(m->t >= 0.0 && m->t <= (double)m->def.y_max) || m->keys.used > nodes)
        return 0;
    for (uint32_t i = 1; i < m->keys.ncut; i++)
        if (m->cuts[i - 1] >= m->cuts[i])
            return 0;
    for (uint32_t k = 0; k < m->nbends; k++)
        if (m->bends[k].spread < 1 || m->bends[k].spread > MER_BEND_SPREAD_MAX)
            return 0;
    for (uint32_t i = 0; i < MERP_G_COUNT; i++)
        merp_gfunc_prepare(&m->def.g[i], NULL);
    retext(m);
    return m->text != NULL;
}

static mer_result inverse_load(merp_bytes_in *in, uint32_t nodes, merp_model **out,
                               mer_error *err)
{
    *out = NULL;
    merp_model *m = merp_calloc(1, sizeof *m);
    if (m == NULL)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the inverse model");
    merp_get(in, &m->def, sizeof m->def);
    m->seed = merp_get_u64(in);
    m->seeded = (int)merp_get_u32(in);
    merp_get(in, &m->t, sizeof m->t);
    m->dropped = merp_get_u32(in);
    uint32_t used = merp_get_u32(in);
    (void)(MERP_GET_ARRAY(in, m->keys.of, used) && MERP_GET_ARRAY(in, m->keys.leaf, used) &&
           MERP_GET_ARRAY(in, m->keys.radius, used));
    m->keys.cap = m->keys.used = in->bad ? 0 : used;
    uint32_t ncut = merp_get_u32(in);
    (void)MERP_GET_ARRAY(in, m->cuts, ncut);
    m->cap_cuts = m->keys.ncut = in->bad ? 0 : ncut;
    m->keys.cut = m->cuts;
    m->hit = ncut > 0 && !in->bad ? merp_malloc(ncut) : NULL;
    if (ncut > 0 && !in->bad && m->hit == NULL)
        in->bad = 2;
    uint32_t nb = merp_get_u32(in);
    if (!in->bad && nb > 0 && nb <= in->n - in->at) {
        m->bends = merp_malloc((size_t)nb * sizeof *m->bends);
        if (m->bends == NULL)
            in->bad = 2;
    } else if (nb > 0) {
        in->bad = in->bad ? in->bad : 1;
    }
    for (uint32_t k = 0; k < nb && !in->bad; k++) {
        merp_inv_bend *b = &m->bends[k];
        memset(b, 0, sizeof *b);
        b->key = merp_get_u64(in);
        merp_get(in, b->axis, sizeof b->axis);
        merp_get(in, &b->angle, sizeof b->angle);
        b->spread = merp_get_u32(in);
    }
    m->nbends = m->cap_bends = in->bad ? 0 : nb;
    if (in->bad || !loaded_ok(m, nodes)) {
        int oom = in->bad == 2;
        inverse_free(m);
        return oom ? mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the inverse model")
                   : mer_error_set(err, MER_ERR_FORMAT, "model", "damaged inverse-model state");
    }
    *out = m;
    return MER_OK;
}

/* The first definition before any tree is shown just sets it; a later one
 * regrows the tree shown, at the same time, from the new definition. */
static mer_result inverse_set_definition(merp_model *m, const merp_world *w, const char *text,
                                         size_t len, mer_error *err)
{
    merp_inv_def d = m->def;
    mer_result rc = merp_inv_def_read(&d, text, len, err);
    if (rc != MER_OK)
        return rc;
    if ((double)w->step > (double)d.y_max || m->t > (double)d.y_max)
        return mer_error_set(err, MER_ERR_RANGE, "y_max",
                             "the tree shows year %g; y_max must be at least that",
                             (double)w->step > m->t ? (double)w->step : m->t);
    m->def = d;
    retext(m);
    return m->seeded ? merp_inv_show(m, w, m->t, err) : MER_OK;
}

static const char *inverse_definition(const merp_model *m, size_t *len)
{
    if (len != NULL)
        *len = m->tlen;
    return m->text;
}

static size_t inverse_stats(const merp_model *m, mer_model_stat *out, size_t cap)
{
    size_t k = 0;
    double v[5 + MERP_INV_ORDER_MAX];
    char names[5 + MERP_INV_ORDER_MAX][24];
    snprintf(names[k], sizeof names[k], "year");
    v[k++] = m->t;
    snprintf(names[k], sizeof names[k], "y_max");
    v[k++] = m->def.y_max;
    for (uint32_t o = 1; o <= m->def.order_max && o <= MERP_INV_ORDER_MAX; o++) {
        snprintf(names[k], sizeof names[k], "branches.order%u", o);
        v[k++] = m->branches[o];
    }
    /* The recorded edits made again on every regrowth, and those the last one
     * dropped because its tree lacks their node (regrow.c). */
    snprintf(names[k], sizeof names[k], "edits.prunes");
    v[k++] = m->keys.ncut;
    snprintf(names[k], sizeof names[k], "edits.bends");
    v[k++] = m->nbends;
    snprintf(names[k], sizeof names[k], "edits.dropped");
    v[k++] = m->dropped;
    for (size_t i = 0; i < k && i < cap; i++) {
        memcpy(out[i].name, names[i], sizeof out[i].name);
        out[i].value = v[i];
    }
    return k;
}

const merp_model_ops merp_inverse_ops = {
    .name = "inverse",
    .param_rows = 0,
    .state_version = 2,
    .validate = NULL,
    .create = inverse_create,
    /* No set_params: the world's parameters (leaf diameter, pipe exponent) are
     * read by the scene; the tree's own are its definition's. */
    .step = inverse_step,
    .nodes_changed = inverse_nodes_changed,
    .hash = inverse_hash,
    .clone = inverse_clone,
    .save = inverse_save,
    .load = inverse_load,
    .free = inverse_free,
    .set_definition = inverse_set_definition,
    .definition = inverse_definition,
    .diameters = inverse_diameters,
    .leaf = inverse_leaf,
    .bending = inverse_bending,
    .stats = inverse_stats,
};

mer_result merp_inverse_show(mer_scene *s, double t, mer_error *err)
{
    assert(s != NULL && s->ops == &merp_inverse_ops);
    merp_model *m = s->model;
    if (!(t >= 0.0 && t <= (double)m->def.y_max))
        return mer_error_set(err, MER_ERR_RANGE, "t", "t must be in [0, %u] years",
                             m->def.y_max);
    merp_world w = merp_scene_world(s);
    mer_result rc = merp_inv_show(m, &w, t, err);
    merp_pipe_update(&s->sk, &s->p);
    inverse_diameters(m, &w);
    return rc;
}

mer_result merp_inverse_set_def(mer_scene *s, const merp_inv_def *d, mer_error *err)
{
    assert(s != NULL && s->ops == &merp_inverse_ops && d != NULL);
    mer_result rc = merp_inv_def_check(d, err);
    if (rc != MER_OK)
        return rc;
    merp_model *m = s->model;
    if ((double)s->step > (double)d->y_max || m->t > (double)d->y_max)
        return mer_error_set(err, MER_ERR_RANGE, "y_max",
                             "the tree shows year %g; y_max must be at least that",
                             (double)s->step > m->t ? (double)s->step : m->t);
    m->def = *d;
    retext(m);
    for (uint32_t i = 0; i < MERP_G_COUNT; i++)
        merp_gfunc_prepare(&m->def.g[i], NULL);
    /* The tree shown, shown again under the new functions. */
    return m->seeded ? merp_inverse_show(s, m->t, err) : MER_OK;
}

const merp_inv_def *merp_inverse_def(const mer_scene *s)
{
    assert(s != NULL && s->ops == &merp_inverse_ops);
    return &s->model->def;
}

double merp_inverse_time(const mer_scene *s)
{
    assert(s != NULL && s->ops == &merp_inverse_ops);
    return s->model->t;
}

uint64_t merp_inverse_node_key(const mer_scene *s, uint32_t id)
{
    assert(s != NULL && s->ops == &merp_inverse_ops);
    const merp_model *m = s->model;
    return id < m->keys.used && id < s->sk.n && m->seeded ? m->keys.of[id] : 0;
}

float merp_inverse_leaf_size(const mer_scene *s, uint32_t id)
{
    assert(s != NULL && s->ops == &merp_inverse_ops);
    const merp_model *m = s->model;
    return id < m->keys.used && id < s->sk.n && s->sk.alive[id] && m->seeded ? m->keys.leaf[id]
                                                                             : 0.0f;
}
