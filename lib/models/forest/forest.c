/* meristem — the forest model's ops (forest.h): a step steps every member in
 * turn and mirrors them; a prune or bend of a forest node is made on its
 * member. */
#include "config.h"

#include <assert.h>
#include <string.h>

#include <meristem/edit.h>

#include "core/alloc.h"
#include "core/hash.h"
#include "models/forest/forest.h"
#include "scene_private.h"

mer_result merp_forest_create_empty(merp_model **out, mer_error *err)
{
    *out = merp_calloc(1, sizeof **out);
    return *out != NULL ? MER_OK
                        : mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for a forest");
}

static mer_result forest_create(const mer_params *p, merp_model **out, mer_error *err)
{
    (void)p;
    return merp_forest_create_empty(out, err);
}

void merp_forest_free(merp_model *f)
{
    if (f == NULL)
        return;
    merp_forest_members_free(f);
    merp_free(f->sites);
    merp_free(f->text);
    merp_free(f);
}

/* The forest's plants are sown (its definition), not the parameters' seedlings. */
static mer_result forest_validate(const mer_params *p, mer_error *err)
{
    if (p->seedlings != 0)
        return mer_error_set(err, MER_ERR_RANGE, "seedlings",
                             "a forest's plants are sown: seedlings must be 0");
    return MER_OK;
}

/* Members keep their presets' parameters: the forest's own are the world's. */
static void forest_set_params(merp_model *f, const mer_params *p)
{
    (void)f;
    (void)p;
}

static mer_result forest_define(merp_model *f, const merp_world *w, const char *text, size_t len,
                                mer_error *err)
{
    if (f->text != NULL)
        return mer_error_set(err, MER_ERR_INVALID, "definition",
                             "a forest is sown once, when its scene is made");
    mer_result rc = merp_sow_parse(text, len, &f->sow, err);
    if (rc == MER_OK)
        rc = merp_forest_sow(f, err);
    if (rc == MER_OK && (f->text = merp_malloc(len + 1)) == NULL)
        rc = mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for a forest");
    if (rc == MER_OK)
        rc = merp_forest_mirror(f, w->sk, w->step, err);
    if (rc != MER_OK) {
        merp_forest_members_free(f);
        merp_free(f->sites);
        merp_free(f->text);
        f->sites = NULL;
        f->text = NULL;
        f->nsites = 0;
        return rc;
    }
    memcpy(f->text, text, len);
    f->text[len] = '\0';
    f->len = len;
    return MER_OK;
}

static const char *forest_definition(const merp_model *f, size_t *len)
{
    if (len != NULL)
        *len = f->len;
    return f->text;
}

/* One step of every member, in order (each member's own threads; the order
 * makes the forest as deterministic as its members). */
static mer_result forest_step(merp_model *f, const merp_world *w, mer_error *err)
{
    for (uint32_t k = 0; k < f->nmembers; k++) {
        mer_result rc = mer_scene_step(f->m[k].scene, 1, NULL, NULL, NULL, NULL, err);
        if (rc != MER_OK)
            return rc;
    }
    return merp_forest_mirror(f, w->sk, w->step, err);
}

/* A forest node found dead whose member node lives was pruned in the forest:
 * the prune is made on the member (ids ascend from parents to children within
 * a member, so the first found is the pruned subtree's root). */
static void forest_nodes_changed(merp_model *f, const merp_world *w)
{
    const merp_skeleton *sk = w->sk;
    for (uint32_t o = 0; o < sk->n && o < f->nout; o++) {
        uint32_t k, i;
        if (sk->alive[o] || merp_forest_member_of(f, o, &k, &i) != 0)
            continue;
        mer_scene *ms = f->m[k].scene;
        if (ms->sk.alive[i] && ms->sk.parent[i] != MER_NO_NODE)
            (void)mer_scene_prune(ms, i, NULL);
    }
    /* No member grew: nothing new to map, so the mirror cannot fail. */
    mer_result rc = merp_forest_mirror(f, w->sk, w->step, NULL);
    assert(rc == MER_OK);
    (void)rc;
    merp_forest_diameters(f, w->sk);
}

static mer_result forest_bending(merp_model *f, const merp_world *w, uint32_t node,
                                 const float axis[3], float angle, uint32_t spread, mer_error *err)
{
    (void)w;
    uint32_t k, i;
    if (merp_forest_member_of(f, node, &k, &i) != 0)
        return mer_error_set(err, MER_ERR_NOT_FOUND, "node", "node %u is in no plant",
                             (unsigned)node);
    return mer_scene_bend_spread(f->m[k].scene, i, axis, angle, spread, err);
}

static void forest_diameters(const merp_model *f, const merp_world *w)
{
    merp_forest_diameters(f, w->sk);
}

static float forest_leaf(const merp_model *f, const merp_skeleton *sk, uint32_t id)
{
    (void)sk;
    uint32_t k, i;
    if (merp_forest_member_of(f, id, &k, &i) != 0)
        return 0.0f;
    const mer_scene *ms = f->m[k].scene;
    return ms->ops->leaf != NULL ? ms->ops->leaf(ms->model, &ms->sk, i) : 0.0f;
}

static uint64_t forest_hash(const merp_model *f, uint64_t h)
{
    if (f->text != NULL)
        h = merp_fnv(h, f->text, f->len);
    for (uint32_t k = 0; k < f->nmembers; k++) {
        uint64_t mh = mer_scene_hash(f->m[k].scene);
        h = merp_fnv(h, &mh, sizeof mh);
        h = merp_fnv(h, f->m[k].outer, (size_t)f->m[k].mapped * sizeof *f->m[k].outer);
    }
    return h;
}

static size_t forest_stats(const merp_model *f, mer_model_stat *out, size_t cap)
{
    uint32_t markers = 0;
    for (uint32_t k = 0; k < f->nmembers; k++)
        markers += (uint32_t)mer_scene_marker_count(f->m[k].scene);
    const mer_model_stat all[] = {
        {"plants", f->nsites}, {"members", f->nmembers}, {"markers", markers}};
    size_t n = sizeof all / sizeof all[0];
    for (size_t i = 0; i < n && i < cap; i++)
        out[i] = all[i];
    return n;
}

const merp_model_ops merp_forest_ops = {
    .name = "forest",
    .param_rows = 0,
    .state_version = 1,
    .validate = forest_validate,
    .create = forest_create,
    .set_params = forest_set_params,
    .step = forest_step,
    .nodes_changed = forest_nodes_changed,
    .hash = forest_hash,
    .clone = merp_forest_clone,
    .save = merp_forest_save,
    .load = merp_forest_load,
    .free = merp_forest_free,
    .set_definition = forest_define,
    .definition = forest_definition,
    .diameters = forest_diameters,
    .leaf = forest_leaf,
    .bending = forest_bending,
    .stats = forest_stats,
};
