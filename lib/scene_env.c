/* meristem — what a scene's caller puts into the world: plants, obstacles and
 * markers (P09 §3, §6). The work is the skeleton's and the environment's. */
#include "config.h"

#include <assert.h>

#include "scene_private.h"

mer_result mer_scene_add_plant(mer_scene *s, const float base[3], uint32_t *root, mer_error *err)
{
    assert(s != NULL && base != NULL);
    if (s->sk.nplants >= MER_PLANTS_MAX)
        return mer_error_set(err, MER_ERR_LIMIT, "plants", "a scene holds at most %u plants",
                             MER_PLANTS_MAX);
    float up_end[3] = {base[0], base[1] + s->p.internode_length, base[2]};
    if (merp_env_blocked(&s->env, base) || merp_env_blocked(&s->env, up_end))
        return mer_error_set(err, MER_ERR_RANGE, "base",
                             "a plant's base must be above the ground and outside obstacles");
    return merp_skel_add_plant(&s->sk, &s->p, s->step, base, &s->rng, root, err);
}

uint32_t mer_scene_plant_count(const mer_scene *s) { return s->sk.nplants; }

mer_result mer_scene_add_box(mer_scene *s, const float min[3], const float max[3], mer_error *err)
{
    assert(s != NULL && min != NULL && max != NULL);
    return merp_env_add_box(&s->env, min, max, err);
}

mer_result mer_scene_add_sphere(mer_scene *s, const float center[3], float radius, mer_error *err)
{
    assert(s != NULL && center != NULL);
    return merp_env_add_sphere(&s->env, center, radius, err);
}

mer_result mer_scene_add_mesh(mer_scene *s, const float *xyz, size_t triangles, mer_error *err)
{
    assert(s != NULL);
    return merp_env_add_mesh(&s->env, xyz, triangles, err);
}

mer_result mer_scene_fill_mesh_markers(mer_scene *s, const float *xyz, size_t triangles,
                                       uint32_t count, mer_error *err)
{
    assert(s != NULL);
    return merp_env_fill_mesh(&s->env, &s->rng, xyz, triangles, count, err);
}

mer_result mer_scene_add_markers(mer_scene *s, const float *xyz, size_t count, mer_error *err)
{
    assert(s != NULL);
    return merp_env_add_markers(&s->env, xyz, count, err);
}

mer_result mer_scene_fill_markers(mer_scene *s, uint32_t kind, const float center[3],
                                  const float size[3], uint32_t count, mer_error *err)
{
    assert(s != NULL && center != NULL && size != NULL);
    return merp_env_fill_volume(&s->env, &s->rng, kind, center, size, count, err);
}

size_t mer_scene_marker_count(const mer_scene *s) { return mer_markers_count(s->env.markers); }

size_t mer_scene_markers(const mer_scene *s, float *out, size_t cap)
{
    return mer_markers_positions(s->env.markers, out, cap);
}
