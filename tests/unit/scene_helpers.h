/* Helpers shared by the scene unit tests (test_scene.c, test_obstacles.c, the
 * models' tests): a new scene, one with a definition, whole steps, a model's
 * statistic, failing the test on any error. Include after <cmocka.h>. */
#ifndef MERISTEM_TEST_SCENE_HELPERS_H
#define MERISTEM_TEST_SCENE_HELPERS_H

#include <math.h>
#include <string.h>

#include <meristem/presets.h>
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

/* A scene from `p` and `seed` given the definition `text` (an L-system's cpfg
 * text, mer_scene_set_definition); fails the test, naming the text's line and
 * column, if it is refused. */
static inline mer_scene *new_defined_scene(const mer_params *p, uint64_t seed, const char *text)
{
    mer_scene *s = new_scene(p, seed);
    mer_error err;
    if (mer_scene_set_definition(s, text, strlen(text), &err) != MER_OK)
        fail_msg("definition: %u:%u %s", err.line, err.column, err.message);
    return s;
}

/* A scene of preset `name` from its parameters `p` and `seed`, given the
 * preset's definition where it has one (an L-system's or the inverse
 * model's source; P09's trees need none). */
static inline mer_scene *new_preset_scene(const char *name, const mer_params *p, uint64_t seed)
{
    const char *text = mer_preset_definition(name);
    return text != NULL ? new_defined_scene(p, seed, text) : new_scene(p, seed);
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

/* The model's number `name` (mer_scene_model_stats), -1 when it has none. */
static inline double model_stat(const mer_scene *s, const char *name)
{
    mer_model_stat st[64];
    size_t n = mer_scene_model_stats(s, st, 64);
    for (size_t i = 0; i < n && i < 64; i++)
        if (strcmp(st[i].name, name) == 0)
            return st[i].value;
    return -1.0;
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
