/* Perlin noise (lib/core/perlin.c) and the perturbation every model can use
 * (lib/env/noise.c): 0 at lattice points, continuous, bounded, the same field
 * for the same seed; amplitude 0 changes nothing, and amplitude > 0 bends,
 * stretches and thickens internodes deterministically. */
#include "config.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include <meristem/presets.h>
#include <meristem/rng.h>
#include <meristem/scene.h>

#include "core/perlin.h"
#include "env/noise.h"
#include "scene_helpers.h"

static void test_zero_at_lattice_points(void **state)
{
    (void)state;
    merp_perlin n;
    for (uint64_t seed = 0; seed < 4; seed++) {
        merp_perlin_init(&n, seed);
        for (int x = -4; x <= 4; x++)
            for (int y = -4; y <= 4; y++)
                for (int z = -4; z <= 4; z++) {
                    assert_true(merp_perlin3(&n, (float)x, (float)y, (float)z) == 0.0f);
                    const float p[3] = {(float)x, (float)y, (float)z};
                    assert_true(merp_perlin_fbm(&n, p, 5) == 0.0f);
                }
        /* ...and not 0 in general between them. */
        assert_true(fabsf(merp_perlin3(&n, 0.5f, 0.25f, 0.75f)) > 0.0f ||
                    fabsf(merp_perlin3(&n, 1.3f, 2.7f, 0.6f)) > 0.0f);
    }
}

/* A small step moves the value a little, inside cells and across their faces;
 * every value is in [-1, 1]. */
static void test_continuous_and_bounded(void **state)
{
    (void)state;
    merp_perlin n;
    merp_perlin_init(&n, 42);
    mer_rng rng;
    mer_rng_seed(&rng, 9);
    float nonzero = 0.0f;
    for (int k = 0; k < 2000; k++) {
        float p[3], q[3];
        for (int a = 0; a < 3; a++)
            p[a] = mer_rng_range(&rng, -20.0f, 20.0f);
        if (k % 4 == 0)
            p[0] = floorf(p[0]) - 1e-4f; /* just below a face: the step crosses it */
        for (int a = 0; a < 3; a++)
            q[a] = p[a] + 2e-4f;
        float a = merp_perlin3(&n, p[0], p[1], p[2]), b = merp_perlin3(&n, q[0], q[1], q[2]);
        assert_true(a >= -1.0f && a <= 1.0f);
        assert_true(fabsf(a - b) < 2e-3f);
        float fa = merp_perlin_fbm(&n, p, 4), fb = merp_perlin_fbm(&n, q, 4);
        assert_true(fa >= -1.0f && fa <= 1.0f);
        assert_true(fabsf(fa - fb) < 4e-3f);
        nonzero = fmaxf(nonzero, fabsf(a));
    }
    assert_true(nonzero > 0.3f); /* the field has some swing */
}

/* The field is the seed's: equal for one seed, different for another. */
static void test_seeded(void **state)
{
    (void)state;
    merp_perlin a, b, c;
    merp_perlin_init(&a, 5);
    merp_perlin_init(&b, 5);
    merp_perlin_init(&c, 6);
    assert_memory_equal(a.perm, b.perm, sizeof a.perm);
    int differ = 0;
    for (int k = 0; k < 50; k++) {
        float x = 0.37f * (float)k, y = 1.1f + 0.13f * (float)k, z = -0.71f * (float)k;
        assert_true(merp_perlin3(&a, x, y, z) == merp_perlin3(&b, x, y, z));
        differ |= merp_perlin3(&a, x, y, z) != merp_perlin3(&c, x, y, z);
    }
    assert_true(differ);
    /* A permutation: every value once. */
    int seen[256] = {0};
    for (int i = 0; i < 256; i++)
        seen[a.perm[i]]++;
    for (int i = 0; i < 256; i++)
        assert_int_equal(seen[i], 1);
}

/* The perturbation: off at amplitude 0 or without the target's bit. */
static void test_perturbation(void **state)
{
    (void)state;
    merp_perlin n;
    merp_perlin_init(&n, 3);
    mer_params p = mer_params_default();
    const float base[3] = {1.3f, 2.2f, -0.4f};
    float d[3] = {0.0f, 1.0f, 0.0f}, l = 1.0f;
    merp_noise_internode(&n, &p, base, d, &l);
    assert_true(d[0] == 0.0f && d[1] == 1.0f && d[2] == 0.0f && l == 1.0f);
    assert_true(merp_noise_diameter(&n, &p, base) == 1.0f);
    p.noise_amplitude = 0.5f;
    p.noise_targets = MER_NOISE_LENGTHS;
    merp_noise_internode(&n, &p, base, d, &l);
    assert_true(d[0] == 0.0f && d[1] == 1.0f && d[2] == 0.0f);
    assert_true(l != 1.0f && l >= 0.1f);
    assert_true(merp_noise_diameter(&n, &p, base) == 1.0f);
    p.noise_targets = MER_NOISE_DIRECTIONS | MER_NOISE_RADII;
    merp_noise_internode(&n, &p, base, d, &l);
    assert_true(d[1] != 1.0f);
    assert_near(sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]), 1.0f, 1e-5f);
    assert_true(merp_noise_diameter(&n, &p, base) != 1.0f);
}

static uint64_t grown(const mer_params *p, uint64_t seed, uint32_t steps)
{
    mer_scene *s = new_scene(p, seed);
    step(s, steps);
    uint64_t h = mer_scene_hash(s);
    mer_scene_free(s);
    return h;
}

/* Amplitude 0 is the scene without noise, whatever the other noise fields say;
 * amplitude > 0 changes the tree, the same way every time, for both models,
 * and survives a checkpoint. */
static void test_scenes(void **state)
{
    (void)state;
    const char *presets[] = {"default", "runions-2007"};
    for (int k = 0; k < 2; k++) {
        mer_params p;
        assert_int_equal(mer_preset_params(presets[k], &p, NULL), MER_OK);
        uint64_t plain = grown(&p, 11, 8);
        p.noise_scale = 0.9f;
        p.noise_octaves = 6;
        p.noise_targets = 3;
        assert_true(grown(&p, 11, 8) == plain);
        p.noise_amplitude = 0.6f;
        uint64_t noisy = grown(&p, 11, 8);
        assert_true(noisy != plain);
        assert_true(grown(&p, 11, 8) == noisy);
        mer_scene *s = new_scene(&p, 11);
        step(s, 4);
        uint8_t *bytes = NULL;
        size_t size = 0;
        mer_error err;
        assert_int_equal(mer_scene_save(s, &bytes, &size, &err), MER_OK);
        mer_scene *t = NULL;
        assert_int_equal(mer_scene_load(bytes, size, &t, &err), MER_OK);
        mer_scene_free(s);
        step(t, 4);
        assert_true(mer_scene_hash(t) == noisy);
        mer_scene_free(t);
        free(bytes);
    }
}

/* Radii: the node view's diameter is the pipe model's times the noise factor. */
static void test_radii(void **state)
{
    (void)state;
    mer_params p = mer_params_default();
    mer_scene *a = new_scene(&p, 2);
    p.noise_amplitude = 0.8f;
    p.noise_targets = MER_NOISE_RADII;
    mer_scene *b = new_scene(&p, 2);
    step(a, 6);
    step(b, 6);
    assert_true(mer_scene_hash(a) == mer_scene_hash(b)); /* the skeleton is the same */
    int differ = 0;
    for (uint32_t id = 0; id < mer_scene_node_bound(a); id++) {
        mer_node x, y;
        assert_int_equal(mer_scene_node(a, id, &x, NULL), MER_OK);
        assert_int_equal(mer_scene_node(b, id, &y, NULL), MER_OK);
        assert_true(y.diameter >= 0.1f * x.diameter * 0.999f);
        differ |= x.diameter != y.diameter;
    }
    assert_true(differ);
    mer_scene_free(a);
    mer_scene_free(b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_zero_at_lattice_points),
        cmocka_unit_test(test_continuous_and_bounded),
        cmocka_unit_test(test_seeded),
        cmocka_unit_test(test_perturbation),
        cmocka_unit_test(test_scenes),
        cmocka_unit_test(test_radii),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
