/* meristem — sowing a forest: Poisson-disk places the plants, each gets a
 * preset round-robin and its Voronoi cell of markers, and the member scenes
 * are made (forest.h). */
#include "config.h"

#include <assert.h>
#include <stdio.h>
#include <string.h>

#include <meristem/presets.h>
#include <meristem/sow.h>

#include "core/alloc.h"
#include "models/forest/forest.h"
#include "scene_private.h"

/* Whether plants of a preset of this model share one member scene, planted where
 * they were sown: the models that grow from the scene's plants. The others grow
 * one tree at the origin. */
static bool grows_plants(uint32_t model)
{
    return model == MER_MODEL_P09 || model == MER_MODEL_RUNIONS;
}

/* The seed of member k: SplitMix64 of the sow's seed and k, so members differ. */
static uint64_t member_seed(uint64_t seed, uint32_t k)
{
    uint64_t z = seed + 0x9E3779B97F4A7C15ull * (k + 1ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/* Renames the error as the preset's. */
static mer_result of_preset(mer_result rc, const char *name, mer_error *err)
{
    if (rc != MER_OK && err != NULL) {
        char msg[sizeof err->message];
        snprintf(msg, sizeof msg, "%s", err->message);
        mer_error_set(err, rc, "presets", "preset '%s': %s", name, msg);
    }
    return rc;
}

/* Plant i's markers: its preset's volume over it, clipped to its cell. */
static mer_result fill_cell(const merp_model *f, mer_scene *s, const mer_params *q, uint32_t count,
                            uint32_t i, const float offset[3], mer_error *err)
{
    float *xyz = merp_malloc((size_t)count * 3 * sizeof *xyz);
    if (xyz == NULL)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for markers");
    float c[3] = {q->marker_center[0] + f->sites[2 * i], q->marker_center[1],
                  q->marker_center[2] + f->sites[2 * i + 1]};
    merp_volume_points(&s->rng, q->marker_volume, c, q->marker_size, count, xyz);
    size_t kept = mer_voronoi_clip(f->sites, f->nsites, i, xyz, count);
    for (size_t k = 0; k < kept; k++)
        for (int a = 0; a < 3; a++)
            xyz[3 * k + a] -= offset[a];
    mer_result rc = mer_scene_add_markers(s, xyz, kept, err);
    merp_free(xyz);
    return rc;
}

/* The plants of preset `pi` in one member: its sites (every npresets-th from
 * `first`, or only `first` when `one`) planted, defined and given markers. */
static mer_result make_member(merp_model *f, uint32_t pi, uint32_t first, bool one,
                              const mer_params *preset, mer_error *err)
{
    merp_forest_member *m = &f->m[f->nmembers];
    memset(m, 0, sizeof *m);
    m->preset = pi;
    mer_params q = *preset;
    uint32_t markers = q.environment == MER_ENV_MARKERS && q.marker_volume != MER_VOLUME_NONE
                           ? q.marker_count : 0;
    q.marker_count = 0;
    if (one) {
        m->offset[0] = f->sites[2 * first];
        m->offset[2] = f->sites[2 * first + 1];
    } else {
        q.seedlings = 0;
    }
    uint32_t step = one ? f->nsites : f->sow.npresets;
    for (uint32_t i = first; !one && i < f->nsites; i += step)
        for (int a = 0; a < 2; a++)
            if (!(f->sites[2 * i + a] >= q.bounds_min[2 * a] &&
                  f->sites[2 * i + a] <= q.bounds_max[2 * a]))
                return mer_error_set(err, MER_ERR_INVALID, "area",
                                     "the area must lie within the preset's bounds");
    mer_result rc = mer_scene_new(&q, member_seed(f->sow.seed, f->nmembers), &m->scene, err);
    if (rc != MER_OK)
        return rc;
    f->nmembers++;
    const char *def = mer_preset_definition(f->sow.presets[pi]);
    for (uint32_t i = first; rc == MER_OK && !one && i < f->nsites; i += step) {
        float base[3] = {f->sites[2 * i], q.ground_enabled ? q.ground : 0.0f, f->sites[2 * i + 1]};
        rc = mer_scene_add_plant(m->scene, base, NULL, err);
    }
    if (rc == MER_OK && def != NULL)
        rc = mer_scene_set_definition(m->scene, def, strlen(def), err);
    for (uint32_t i = first; rc == MER_OK && markers > 0 && i < f->nsites; i += step)
        rc = fill_cell(f, m->scene, preset, markers, i, m->offset, err);
    return rc;
}

mer_result merp_forest_sow(merp_model *f, mer_error *err)
{
    assert(f != NULL && f->sites == NULL && f->m == NULL);
    const merp_sow *s = &f->sow;
    f->sites = merp_malloc((size_t)s->count * 2 * sizeof *f->sites);
    f->m = merp_calloc(s->count, sizeof *f->m);
    if (f->sites == NULL || f->m == NULL)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for a forest");
    mer_result rc = mer_poisson_disk(s->lo, s->hi, s->r, s->count, s->seed, f->sites,
                                     &f->nsites, err);
    if (rc != MER_OK)
        return rc;
    for (uint32_t pi = 0; rc == MER_OK && pi < s->npresets; pi++) {
        mer_params preset;
        rc = of_preset(mer_preset_params(s->presets[pi], &preset, err), s->presets[pi], err);
        if (rc != MER_OK)
            break;
        bool grouped = grows_plants(preset.model);
        for (uint32_t i = pi; rc == MER_OK && i < f->nsites; i += s->npresets) {
            rc = of_preset(make_member(f, pi, i, !grouped, &preset, err), s->presets[pi], err);
            if (grouped)
                break;
        }
    }
    return rc;
}
