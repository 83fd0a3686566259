/* meristem — obstacles: boxes, spheres and closed meshes that growth and markers
 * avoid and that cast shadow (P09 §6). */
#include "config.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <meristem/scene.h>

#include "core/array.h"
#include "core/vec.h"
#include "env/env.h"

int merp_inside_obstacle(const merp_obstacle *o, const float *p)
{
    assert(o != NULL && p != NULL);
    if (o->kind == MERP_OBS_MESH)
        return merp_solid_inside(o->solid, p); /* checks its bounding box first */
    if (o->kind == MERP_OBS_BOX)
        return p[0] >= o->a[0] && p[0] <= o->b[0] && p[1] >= o->a[1] && p[1] <= o->b[1] &&
               p[2] >= o->a[2] && p[2] <= o->b[2];
    float d[3] = {p[0] - o->a[0], p[1] - o->a[1], p[2] - o->a[2]};
    return v3_dot(d, d) <= o->r * o->r;
}

/* An obstacle shades each voxel whose centre it contains fully (C + a, so Q = 0
 * there) and casts a bud's pyramid from each such voxel whose upper neighbour it
 * does not contain (its top surface). */
static void shadow_obstacle(merp_env *e, const merp_obstacle *o, int sign)
{
    if (e->shadow == NULL)
        return;
    const mer_params *p = &e->p;
    int dim[3];
    mer_shadow_dims(e->shadow, dim);
    float lo[3], hi[3];
    if (o->kind == MERP_OBS_BOX || o->kind == MERP_OBS_MESH) {
        memcpy(lo, o->a, sizeof lo);
        memcpy(hi, o->b, sizeof hi);
    } else {
        for (int a = 0; a < 3; a++) {
            lo[a] = o->a[a] - o->r;
            hi[a] = o->a[a] + o->r;
        }
    }
    float vox = p->voxel;
    int i0[3], i1[3];
    for (int a = 0; a < 3; a++) {
        float f0 = (lo[a] - p->bounds_min[a]) / vox - 0.5f;
        float f1 = (hi[a] - p->bounds_min[a]) / vox - 0.5f;
        i0[a] = f0 < 0.0f ? 0 : (int)ceilf(f0);
        i1[a] = f1 >= (float)(dim[a] - 1) ? dim[a] - 1 : (int)floorf(f1);
    }
    float full = p->shadow_c + p->shadow_a;
    for (int j = i0[1]; j <= i1[1]; j++)
        for (int k = i0[2]; k <= i1[2]; k++)
            for (int i = i0[0]; i <= i1[0]; i++) {
                float c[3] = {p->bounds_min[0] + ((float)i + 0.5f) * vox,
                              p->bounds_min[1] + ((float)j + 0.5f) * vox,
                              p->bounds_min[2] + ((float)k + 0.5f) * vox};
                if (!merp_inside_obstacle(o, c))
                    continue;
                int ijk[3] = {i, j, k};
                mer_shadow_add_voxel(e->shadow, ijk, sign > 0 ? full : -full);
                float up[3] = {c[0], c[1] + vox, c[2]};
                if (!merp_inside_obstacle(o, up))
                    mer_shadow_cast(e->shadow, ijk, sign, 1.0f);
            }
}

void merp_env_cast_obstacles(merp_env *e)
{
    for (uint32_t o = 0; o < e->nobs; o++)
        shadow_obstacle(e, &e->obs[o], 1);
}

/* mer_markers_remove_if's test: a marker inside the obstacle `ctx`. */
static int inside_ctx(const float p[3], void *ctx)
{
    return merp_inside_obstacle(ctx, p);
}

static mer_result too_many(mer_error *err)
{
    return mer_error_set(err, MER_ERR_LIMIT, "obstacles", "a scene holds at most %u obstacles",
                         MER_OBSTACLES_MAX);
}

mer_result merp_env_add_obstacle(merp_env *e, const merp_obstacle *o, mer_error *err)
{
    assert(e != NULL && o != NULL);
    if (e->nobs >= MER_OBSTACLES_MAX)
        return too_many(err);
    if (!MERP_RESIZE(e->obs, (size_t)e->nobs + 1))
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for obstacles");
    e->obs[e->nobs++] = *o;
    shadow_obstacle(e, o, 1);
    // The markers in earlier obstacles or below the ground are gone already: only the
    // new obstacle needs asking (O(markers), not O(markers × obstacles)).
    mer_markers_remove_if(e->markers, inside_ctx, &e->obs[e->nobs - 1]);
    return MER_OK;
}

static int finite3(const float v[3])
{
    return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

mer_result merp_env_add_box(merp_env *e, const float min[3], const float max[3], mer_error *err)
{
    // Not finite, a box's voxel range would be cast from ±inf or NaN to int.
    if (!finite3(min))
        return mer_error_set(err, MER_ERR_INVALID, "min", "a box's min must be 3 finite numbers");
    if (!finite3(max))
        return mer_error_set(err, MER_ERR_INVALID, "max", "a box's max must be 3 finite numbers");
    for (int a = 0; a < 3; a++)
        if (!(max[a] > min[a]))
            return mer_error_set(err, MER_ERR_RANGE, "max", "a box's max must exceed its min on every axis");
    merp_obstacle o;
    memset(&o, 0, sizeof o);
    o.kind = MERP_OBS_BOX;
    memcpy(o.a, min, sizeof o.a);
    memcpy(o.b, max, sizeof o.b);
    return merp_env_add_obstacle(e, &o, err);
}

mer_result merp_env_add_sphere(merp_env *e, const float center[3], float radius, mer_error *err)
{
    if (!finite3(center))
        return mer_error_set(err, MER_ERR_INVALID, "center", "a sphere's center must be 3 finite numbers");
    if (!(radius > 0.0f) || !isfinite(radius))
        return mer_error_set(err, MER_ERR_RANGE, "radius", "radius must be finite and > 0, got %g",
                             (double)radius);
    merp_obstacle o;
    memset(&o, 0, sizeof o);
    o.kind = MERP_OBS_SPHERE;
    memcpy(o.a, center, sizeof o.a);
    o.r = radius;
    return merp_env_add_obstacle(e, &o, err);
}

mer_result merp_check_mesh(const float *xyz, size_t triangles, mer_error *err)
{
    if (triangles == 0 || xyz == NULL)
        return mer_error_set(err, MER_ERR_INVALID, "triangles", "a mesh needs at least one triangle");
    if (triangles > MER_MESH_TRIANGLES_MAX)
        return mer_error_set(err, MER_ERR_LIMIT, "triangles",
                             "a mesh holds at most %u triangles, got %zu",
                             (unsigned)MER_MESH_TRIANGLES_MAX, triangles);
    float lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    for (size_t i = 0; i < 9 * triangles; i++) {
        float x = xyz[i];
        if (!isfinite(x))
            return mer_error_set(err, MER_ERR_INVALID, "xyz",
                                 "coordinate %zu of triangle %zu is not a finite number",
                                 i % 9, i / 9);
        if (!(fabsf(x) <= MER_MESH_COORD_MAX))
            return mer_error_set(err, MER_ERR_RANGE, "xyz",
                                 "mesh coordinates must lie in [-%g, %g]; triangle %zu has %g",
                                 (double)MER_MESH_COORD_MAX, (double)MER_MESH_COORD_MAX, i / 9,
                                 (double)x);
        int a = (int)(i % 3);
        if (i < 3 || x < lo[a])
            lo[a] = x;
        if (i < 3 || x > hi[a])
            hi[a] = x;
    }
    for (int a = 0; a < 3; a++)
        if (!(hi[a] > lo[a]))
            return mer_error_set(err, MER_ERR_RANGE, "xyz",
                                 "the mesh is flat along %c: it encloses no volume", "xyz"[a]);
    return MER_OK;
}

mer_result merp_check_mesh_work(const merp_solid *solid, const mer_params *p, size_t markers,
                                const char *field, mer_error *err)
{
    assert(solid != NULL && p != NULL);
    double vox = (double)p->voxel, volume = 1.0;
    for (int a = 0; a < 3; a++)
        volume *= (double)p->bounds_max[a] - (double)p->bounds_min[a];
    double density = (p->environment == MER_ENV_SHADOW ? 2.0 / (vox * vox * vox) : 0.0) +
                     (double)markers / volume;
    double work = merp_solid_work(solid, p->bounds_min, p->bounds_max, density);
    if (!(work <= MERP_SOLID_WORK_MAX))
        return mer_error_set(err, MER_ERR_RANGE, field,
                             "a mesh obstacle is too coarse for this scene: its inside tests "
                             "would cost %.3g triangle tests, more than %.3g (are its "
                             "coordinates in the scene's units? a quantized mesh needs "
                             "dequantizing)",
                             work, (double)MERP_SOLID_WORK_MAX);
    return MER_OK;
}

mer_result merp_env_add_mesh(merp_env *e, const float *xyz, size_t triangles, mer_error *err)
{
    mer_result rc = merp_check_mesh(xyz, triangles, err);
    if (rc != MER_OK)
        return rc;
    if (e->nobs >= MER_OBSTACLES_MAX) /* before the voxelization, which costs */
        return too_many(err);
    merp_obstacle o;
    memset(&o, 0, sizeof o);
    o.kind = MERP_OBS_MESH;
    rc = merp_solid_new(xyz, triangles, &o.solid, err);
    if (rc != MER_OK)
        return rc;
    rc = merp_check_mesh_work(o.solid, &e->p, mer_markers_count(e->markers), "xyz", err);
    if (rc != MER_OK) {
        merp_solid_free(o.solid);
        return rc;
    }
    merp_solid_bounds(o.solid, o.a, o.b);
    rc = merp_env_add_obstacle(e, &o, err);
    if (rc != MER_OK)
        merp_solid_free(o.solid);
    return rc;
}
