/* meristem — the scene's full struct: a thin owner of the skeleton, the
 * environment, the growth model and the random stream. Not installed. Helpers use
 * the `merp_` prefix: they are not part of the API, and the library's version
 * script (mer_*) keeps them unexported. */
#ifndef MERISTEM_SCENE_PRIVATE_H
#define MERISTEM_SCENE_PRIVATE_H

#include <stddef.h>
#include <stdint.h>

#include <meristem/params.h>
#include <meristem/rng.h>
#include <meristem/scene.h>

#include "core/perlin.h"
#include "env/env.h"
#include "models/model.h"
#include "skeleton/skeleton.h"

struct mer_scene {
    mer_params p;
    mer_rng rng;
    uint64_t seed;      /* the creation seed: the noise permutation's */
    merp_perlin noise;  /* Perlin noise of the seed (env/noise.h) */
    uint32_t step;
    merp_skeleton sk;
    merp_env env;
    const merp_model_ops *ops;
    merp_model *model;
    mer_step_report last; /* the last step's report (step_report.c) */
};

/* A scene running the model `ops` rather than the one p->model names: the seam
 * tests use to plug in a model of their own. As mer_scene_new otherwise. */
mer_result merp_scene_new_with(const merp_model_ops *ops, const mer_params *params,
                               uint64_t seed, mer_scene **out, mer_error *err);
/* The world lent to the model for one call. */
merp_world merp_scene_world(mer_scene *s);
/* Records the report of the step just run, which made `grown` internodes
 * (step_report.c). O(nodes) when it grew nothing, else O(1). */
void merp_scene_report_step(mer_scene *s, uint32_t grown);
/* edit.c: turns the subtrees of the first `spread` internodes of node's axis
 * about `ax` (unit) by equal shares of `angle` degrees (mer_scene_bend_spread,
 * checked, without telling the model): what a model that rebuilds its tree
 * calls to make a recorded bend again. MER_ERR_NOMEM, changing nothing. */
mer_result merp_bend_apply(merp_skeleton *sk, merp_env *env, uint32_t node, const float ax[3],
                           float angle, uint32_t spread, mer_error *err);
/* Recasts the shadow grid from scratch: every dormant bud, then every obstacle.
 * O(nodes + obstacle voxels). */
void merp_scene_rebuild_shadow(mer_scene *s);

#endif
