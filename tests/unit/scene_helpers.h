/* Helpers shared by the scene unit tests (test_scene.c, test_obstacles.c): a new
 * scene and whole steps, failing the test on any error. Include after <cmocka.h>. */
#ifndef MERISTEM_TEST_SCENE_HELPERS_H
#define MERISTEM_TEST_SCENE_HELPERS_H

#include <meristem/scene.h>

/* A scene from `p` and `seed`; fails the test if it cannot be made. */
static inline mer_scene *new_scene(const mer_params *p, uint64_t seed)
{
    mer_scene *s = NULL;
    mer_error err;
    if (mer_scene_new(p, seed, &s, &err) != MER_OK)
        fail_msg("mer_scene_new: %s", err.message);
    return s;
}

/* Runs `n` whole steps; fails the test on an error or a short run. */
static inline void step(mer_scene *s, uint32_t n)
{
    mer_error err;
    uint32_t done;
    if (mer_scene_step(s, n, NULL, NULL, NULL, &done, &err) != MER_OK)
        fail_msg("step: %s", err.message);
    assert_int_equal(done, n);
}

#endif
