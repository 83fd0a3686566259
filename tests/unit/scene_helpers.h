/* Helpers shared by the scene unit tests (test_scene.c, test_obstacles.c): a new
 * scene and whole steps, failing the test on any error. Include after <cmocka.h>. */
#ifndef MERISTEM_TEST_SCENE_HELPERS_H
#define MERISTEM_TEST_SCENE_HELPERS_H

#include <math.h>

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

/* Float comparisons with a tolerance. */
#define assert_near(a, b, eps) assert_true(fabsf((float)(a) - (float)(b)) < (eps))
#define assert_close(a, b) assert_near(a, b, 1e-4f)

/* The worked seedling's parameters (test_p09.c): the defaults with a = 0.2. */
static inline mer_params worked(void)
{
    mer_params p = mer_params_default();
    p.shadow_a = 0.2f;
    return p;
}

/* A scene from `p`, or from worked() when `p` is NULL. */
static inline mer_scene *make(const mer_params *p, uint64_t seed)
{
    mer_params w = worked();
    return new_scene(p != NULL ? p : &w, seed);
}

static inline mer_node node(const mer_scene *s, uint32_t id)
{
    mer_node n;
    assert_int_equal(mer_scene_node(s, id, &n, NULL), MER_OK);
    return n;
}

#endif
