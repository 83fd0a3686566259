/* meristem — marker volumes: the initial and added markers of space colonization,
 * drawn uniformly in a box, sphere, ellipsoid, cylinder, cone or closed mesh (P09
 * §6). Every draw comes from the scene's generator, so a seed replays exactly. */
#include "config.h"

#include <assert.h>
#include <stdlib.h>

#include <meristem/scene.h>

#include "core/alloc.h"
#include "core/vec.h"
#include "env/env.h"

void merp_unit_ball(mer_rng *rng, float out[3])
{
    assert(rng != NULL && out != NULL);
    do {
        for (int a = 0; a < 3; a++)
            out[a] = mer_rng_range(rng, -1.0f, 1.0f);
    } while (v3_dot(out, out) > 1.0f);
}

/* A point of the cone of base radius 1 at y = -1 and apex at y = 1, by rejection
 * from the bounding cylinder, before scaling. */
static void unit_cone(mer_rng *rng, float u[3])
{
    for (;;) {
        u[0] = mer_rng_range(rng, -1.0f, 1.0f);
        u[2] = mer_rng_range(rng, -1.0f, 1.0f);
        float t = mer_rng_float(rng); /* 0 at the base, 1 at the apex */
        float rr = 1.0f - t;
        if (u[0] * u[0] + u[2] * u[2] <= rr * rr) {
            u[1] = 2.0f * t - 1.0f;
            return;
        }
    }
}

/* One point of volume `kind` around the origin, scaled by `size`. */
static void volume_point(mer_rng *rng, uint32_t kind, const float size[3], float u[3])
{
    switch (kind) {
    case MER_VOLUME_BOX:
        for (int a = 0; a < 3; a++)
            u[a] = mer_rng_range(rng, -1.0f, 1.0f) * size[a];
        break;
    case MER_VOLUME_SPHERE:
        merp_unit_ball(rng, u);
        for (int a = 0; a < 3; a++)
            u[a] *= size[0];
        break;
    case MER_VOLUME_ELLIPSOID:
        merp_unit_ball(rng, u);
        for (int a = 0; a < 3; a++)
            u[a] *= size[a];
        break;
    case MER_VOLUME_CYLINDER:
        do {
            u[0] = mer_rng_range(rng, -1.0f, 1.0f);
            u[2] = mer_rng_range(rng, -1.0f, 1.0f);
        } while (u[0] * u[0] + u[2] * u[2] > 1.0f);
        u[0] *= size[0];
        u[2] *= size[0];
        u[1] = mer_rng_range(rng, -1.0f, 1.0f) * size[1];
        break;
    default: /* MER_VOLUME_CONE */
        unit_cone(rng, u);
        u[1] *= size[1];
        u[0] *= size[0];
        u[2] *= size[0];
        break;
    }
}

void merp_volume_points(mer_rng *rng, uint32_t kind, const float center[3], const float size[3],
                        uint32_t count, float *xyz)
{
    assert(kind >= MER_VOLUME_BOX && kind <= MER_VOLUME_CONE);
    for (uint32_t i = 0; i < count; i++) {
        float u[3], *p = xyz + 3 * (size_t)i;
        volume_point(rng, kind, size, u);
        for (int a = 0; a < 3; a++)
            p[a] = center[a] + u[a];
    }
}

mer_result merp_env_fill_volume(merp_env *e, mer_rng *rng, uint32_t kind, const float center[3],
                                const float size[3], uint32_t count, mer_error *err)
{
    assert(e != NULL && rng != NULL && center != NULL && size != NULL);
    if (kind < MER_VOLUME_BOX || kind > MER_VOLUME_CONE)
        return mer_error_set(err, MER_ERR_RANGE, "marker_volume",
                             "marker_volume must be from 1 to 5, got %u", (unsigned)kind);
    for (int a = 0; a < 3; a++)
        if (!(size[a] >= 0.0f))
            return mer_error_set(err, MER_ERR_RANGE, "marker_size", "marker_size must be >= 0");
    float *xyz = merp_malloc((count ? count : 1) * 3 * sizeof *xyz);
    if (xyz == NULL)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for markers");
    /* A refused fill draws nothing: the generator goes back to where it was. */
    const mer_rng drawn_from = *rng;
    merp_volume_points(rng, kind, center, size, count, xyz);
    mer_result rc = merp_env_add_markers(e, xyz, count, err);
    merp_free(xyz);
    if (rc != MER_OK)
        *rng = drawn_from;
    return rc;
}

/* Rejection sampling: a cell drawn uniformly among those that may hold inside
 * points (equal volumes), a point uniform in it, kept if inside. Uniform over the
 * inside, and far fewer misses than drawing from the bounding box. On failure the
 * generator is left as it was. */
static mer_result sample_solid(const merp_solid *solid, const uint32_t *cand, size_t ncand,
                               mer_rng *rng, uint32_t count, float *pts, mer_error *err)
{
    mer_rng saved = *rng;
    uint64_t budget = (uint64_t)count * MER_MESH_FILL_TRIES + MER_MESH_FILL_TRIES_MIN;
    uint64_t tries = 0;
    for (uint32_t i = 0; i < count; i++) {
        for (;;) {
            if (ncand == 0 || tries++ >= budget) {
                *rng = saved;
                return mer_error_set(err, MER_ERR_RANGE, "xyz",
                                     "the mesh encloses too little volume: %u of %u markers "
                                     "placed in %llu draws",
                                     (unsigned)i, (unsigned)count, (unsigned long long)budget);
            }
            uint32_t c = cand[mer_rng_below(rng, (uint32_t)ncand)];
            float f[3];
            for (int a = 0; a < 3; a++)
                f[a] = mer_rng_float(rng);
            float *p = pts + 3 * (size_t)i;
            merp_solid_cell_point(solid, c, f, p);
            if (merp_solid_inside(solid, p))
                break;
        }
    }
    return MER_OK;
}

mer_result merp_env_fill_mesh(merp_env *e, mer_rng *rng, const float *xyz, size_t triangles,
                              uint32_t count, mer_error *err)
{
    assert(e != NULL && rng != NULL);
    mer_result rc = merp_check_mesh(xyz, triangles, err);
    if (rc != MER_OK)
        return rc;
    if (count > MER_MESH_FILL_MAX)
        return mer_error_set(err, MER_ERR_LIMIT, "count",
                             "a mesh volume takes at most %u markers, got %u",
                             (unsigned)MER_MESH_FILL_MAX, (unsigned)count);
    if (count == 0)
        return MER_OK;
    merp_solid *solid;
    rc = merp_solid_new(xyz, triangles, &solid, err);
    if (rc != MER_OK)
        return rc;
    size_t ncand = merp_solid_candidates(solid, NULL);
    // Each marker costs a draw or more in a candidate cell: refuse a mesh whose
    // draws would each walk long runs of coarse cells (see MERP_SOLID_WORK_MAX).
    float lo[3], hi[3];
    merp_solid_bounds(solid, lo, hi);
    double work = merp_solid_work(solid, lo, hi,
                                  (double)count / ((double)(ncand ? ncand : 1) *
                                                   merp_solid_cell_volume(solid)));
    if (!(work <= MERP_SOLID_WORK_MAX)) {
        merp_solid_free(solid);
        return mer_error_set(err, MER_ERR_RANGE, "xyz",
                             "the mesh is too coarse for %u markers: drawing them would cost "
                             "%.3g triangle tests, more than %.3g",
                             (unsigned)count, work, (double)MERP_SOLID_WORK_MAX);
    }
    uint32_t *cand = merp_malloc((ncand ? ncand : 1) * sizeof *cand);
    float *pts = merp_malloc((size_t)count * 3 * sizeof *pts);
    if (cand == NULL || pts == NULL) {
        rc = mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for mesh markers");
    } else {
        merp_solid_candidates(solid, cand);
        const mer_rng drawn_from = *rng;
        rc = sample_solid(solid, cand, ncand, rng, count, pts, err);
        if (rc == MER_OK && (rc = merp_env_add_markers(e, pts, count, err)) != MER_OK)
            *rng = drawn_from;
    }
    merp_free(cand);
    merp_free(pts);
    merp_solid_free(solid);
    return rc;
}
