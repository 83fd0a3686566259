/* meristem — scenes: creation, parameters, the step loop and the hash (P09 §3,
 * §4.1, §6). A scene owns a skeleton, an environment, a growth model and a random
 * stream; a step is the model's step, then the pipe model's diameters. */
#include "config.h"

#include <assert.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "core/hash.h"
#include "models/inverse/inverse.h"
#include "scene_private.h"

merp_world merp_scene_world(mer_scene *s)
{
    merp_world w = {&s->sk, &s->env, &s->rng, &s->p, s->step, &s->noise};
    return w;
}

/* The initial plants and markers of the parameters. */
static mer_result populate(mer_scene *s, mer_error *err)
{
    const mer_params *p = &s->p;
    mer_result rc = MER_OK;
    for (uint32_t i = 0; i < p->seedlings && rc == MER_OK; i++) {
        float x = ((float)i - 0.5f * (float)(p->seedlings - 1)) * p->seedling_spacing;
        float base[3] = {x, p->ground_enabled ? p->ground : 0.0f, 0.0f};
        rc = mer_scene_add_plant(s, base, NULL, err);
    }
    if (rc == MER_OK && p->environment == MER_ENV_MARKERS && p->marker_count > 0 &&
        p->marker_volume != MER_VOLUME_NONE)
        rc = mer_scene_fill_markers(s, p->marker_volume, p->marker_center, p->marker_size,
                                    p->marker_count, err);
    return rc;
}

mer_result merp_scene_new_with(const merp_model_ops *ops, const mer_params *params,
                               uint64_t seed, mer_scene **out, mer_error *err)
{
    assert(ops != NULL && out != NULL);
    *out = NULL;
    mer_result rc = mer_params_validate(params, err);
    if (rc != MER_OK)
        return rc;
    mer_scene *s = merp_calloc(1, sizeof *s);
    if (s == NULL)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for a scene");
    mer_params_resolve(params, &s->p);
    mer_rng_seed(&s->rng, seed);
    s->seed = seed;
    merp_perlin_init(&s->noise, seed);
    merp_skel_init(&s->sk, &s->p, merp_env_bud_changed, &s->env);
    s->ops = ops;
    rc = merp_env_init(&s->env, &s->p, err);
    if (rc == MER_OK)
        rc = ops->create(&s->p, &s->model, err);
    if (rc == MER_OK)
        rc = populate(s, err);
    if (rc != MER_OK) {
        mer_scene_free(s);
        return rc;
    }
    *out = s;
    return MER_OK;
}

mer_result mer_scene_new(const mer_params *params, uint64_t seed, mer_scene **out,
                         mer_error *err)
{
    assert(out != NULL);
    mer_params p;
    mer_params_resolve(params, &p);
    const merp_model_ops *ops = merp_model_ops_of(p.model);
    if (ops == NULL) {
        *out = NULL;
        return mer_params_validate(&p, err); /* names the unknown model */
    }
    return merp_scene_new_with(ops, params, seed, out, err);
}

void mer_scene_free(mer_scene *s)
{
    if (s == NULL)
        return;
    if (s->model != NULL)
        s->ops->free(s->model);
    merp_skel_free(&s->sk);
    merp_env_free(&s->env);
    merp_free(s);
}

const mer_params *mer_scene_params(const mer_scene *s) { return &s->p; }

uint32_t mer_scene_step_index(const mer_scene *s) { return s->step; }

mer_result mer_scene_set_params(mer_scene *s, const mer_params *params, mer_error *err)
{
    assert(s != NULL);
    mer_result rc = mer_params_validate(params, err);
    if (rc != MER_OK)
        return rc;
    mer_params p;
    mer_params_resolve(params, &p);
    if (p.model != s->p.model)
        return mer_error_set(err, MER_ERR_INVALID, "model",
                             "a scene keeps its model (%s); make a new scene for %s",
                             mer_model_name(s->p.model), mer_model_name(p.model));
    merp_env_change change;
    rc = merp_env_prepare(&s->env, &p, &change, err);
    if (rc != MER_OK)
        return rc;
    /* Nothing can fail from here on. */
    merp_pipe_set_n(&s->sk, p.pipe_n);
    s->p = p;
    merp_skel_init_angles(&s->sk, &p);
    if (merp_env_commit(&s->env, &p, &change))
        merp_scene_rebuild_shadow(s);
    merp_env_drop_covered(&s->env, &change);
    if (s->ops->set_params != NULL)
        s->ops->set_params(s->model, &s->p);
    return MER_OK;
}

mer_result mer_scene_set_schedule(mer_scene *s, const mer_schedule *schedule, mer_error *err)
{
    assert(s != NULL && schedule != NULL);
    mer_params p = s->p;
    p.schedule = *schedule;
    mer_result rc = mer_params_validate(&p, err);
    if (rc != MER_OK)
        return rc;
    s->p.schedule = *schedule; /* no grid depends on the schedule */
    if (s->ops->set_params != NULL)
        s->ops->set_params(s->model, &s->p);
    return MER_OK;
}

/* The pipe model's diameters, then the ones the model sets itself. */
static void diameters(mer_scene *s, const merp_world *w)
{
    merp_pipe_update(&s->sk, &s->p);
    if (s->ops->diameters != NULL)
        s->ops->diameters(s->model, w);
}

static mer_result one_step(mer_scene *s, mer_error *err)
{
    merp_world w = merp_scene_world(s);
    uint32_t before = s->sk.n;
    mer_result rc = s->ops->step(s->model, &w, err);
    diameters(s, &w);
    /* mer_scene_step_index counts completed steps, as *done does: not a step
     * cut short by a failure. A model that rebuilds its skeleton may end with
     * fewer ids than it began with (an L-system after a prune). */
    if (rc == MER_OK) {
        s->step++;
        merp_scene_report_step(s, s->sk.n > before ? s->sk.n - before : 0);
    }
    return rc;
}

mer_result mer_scene_set_definition(mer_scene *s, const char *text, size_t len,
                                    mer_error *err)
{
    assert(s != NULL && (text != NULL || len == 0));
    if (s->ops->set_definition == NULL)
        return mer_error_set(err, MER_ERR_INVALID, "definition",
                             "the model '%s' takes no definition", s->ops->name);
    merp_world w = merp_scene_world(s);
    mer_result rc = s->ops->set_definition(s->model, &w, text != NULL ? text : "", len, err);
    if (rc == MER_OK)
        diameters(s, &w);
    return rc;
}

const char *mer_scene_definition(const mer_scene *s, size_t *len)
{
    assert(s != NULL);
    if (len != NULL)
        *len = 0;
    return s->ops->definition != NULL ? s->ops->definition(s->model, len) : NULL;
}

size_t mer_scene_definition_warnings(const mer_scene *s, mer_warning *out, size_t cap)
{
    assert(s != NULL && (out != NULL || cap == 0));
    return s->ops->warnings != NULL ? s->ops->warnings(s->model, out, cap) : 0;
}

size_t mer_scene_model_stats(const mer_scene *s, mer_model_stat *out, size_t cap)
{
    assert(s != NULL && (out != NULL || cap == 0));
    return s->ops->stats != NULL ? s->ops->stats(s->model, out, cap) : 0;
}

mer_result mer_scene_step(mer_scene *s, uint32_t count, mer_progress_fn progress, void *ctx,
                          const volatile int *cancel, uint32_t *done, mer_error *err)
{
    assert(s != NULL);
    uint32_t k = 0;
    mer_result rc = MER_OK;
    for (; k < count; k++) {
        if (cancel != NULL && *cancel)
            break;
        rc = one_step(s, err);
        if (rc != MER_OK)
            break;
        if (progress != NULL)
            progress(ctx, k + 1, count);
    }
    if (done != NULL)
        *done = k;
    return rc;
}

uint64_t mer_scene_hash(const mer_scene *s)
{
    assert(s != NULL);
    uint64_t h = MERP_FNV_OFFSET;
    h = merp_fnv(h, &s->step, sizeof s->step);
    h = merp_fnv(h, &s->sk.n, sizeof s->sk.n);
    h = merp_fnv(h, s->rng.s, sizeof s->rng.s);
    h = merp_skel_hash(&s->sk, h);
    h = merp_env_hash(&s->env, h);
    return s->ops->hash(s->model, h);
}

void merp_scene_rebuild_shadow(mer_scene *s)
{
    if (s->env.shadow == NULL)
        return;
    mer_shadow_clear(s->env.shadow);
    merp_skel_cast_buds(&s->sk);
    merp_env_cast_obstacles(&s->env);
}

mer_result mer_scene_show_time(mer_scene *s, double t, mer_error *err)
{
    assert(s != NULL);
    if (s->ops != &merp_inverse_ops)
        return mer_error_set(err, MER_ERR_INVALID, "t",
                             "the model '%s' grows in whole steps; t is for the inverse model",
                             s->ops->name);
    merp_world w = merp_scene_world(s);
    mer_result rc = merp_inverse_show(s, t, err);
    if (rc == MER_OK && s->ops->diameters != NULL)
        s->ops->diameters(s->model, &w);
    return rc;
}
