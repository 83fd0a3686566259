/* Unit tests for lib/env/shadow.c: the pyramid, Q, V, incremental = rebuilt. */
#include "config.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <meristem/params.h>
#include <meristem/shadow.h>

#include "env/env.h"

#define assert_close(a, b) assert_true(fabsf((a) - (b)) < 1e-4f)

static const float BMIN[3] = {0, 0, 0}, BMAX[3] = {10, 10, 10};

static float at(const mer_shadow *sh, int i, int j, int k)
{
    int ijk[3] = {i, j, k};
    return mer_shadow_value(sh, ijk);
}

/* a = 1, b = 2, q_max = 2, bud in voxel (5, 5, 5). */
static void test_pyramid_values(void **state)
{
    (void)state;
    mer_shadow *sh;
    assert_int_equal(mer_shadow_new(BMIN, BMAX, 1.0f, 1.0f, 2.0f, 2, &sh, NULL), MER_OK);
    const float p[3] = {5.5f, 5.5f, 5.5f};
    mer_shadow_cast_at(sh, p, 1);
    assert_close(at(sh, 5, 5, 5), 1.0f);           /* q = 0: a */
    assert_close(at(sh, 5, 6, 5), 0.0f);           /* nothing above */
    assert_close(at(sh, 4, 5, 5), 0.0f);           /* nothing beside */
    for (int i = 4; i <= 6; i++)
        for (int k = 4; k <= 6; k++)
            assert_close(at(sh, i, 4, k), 0.5f);   /* q = 1: a/b, 3×3 */
    assert_close(at(sh, 7, 4, 5), 0.0f);
    for (int i = 3; i <= 7; i++)
        for (int k = 3; k <= 7; k++)
            assert_close(at(sh, i, 3, k), 0.25f);  /* q = 2: a/b², 5×5 */
    assert_close(at(sh, 2, 3, 5), 0.0f);
    assert_close(at(sh, 5, 2, 5), 0.0f);           /* q_max = 2 */
    /* Q = max(C − s + a, 0): alone, a bud sees full light C. */
    assert_close(mer_shadow_light(sh, p, 1.0f), 1.0f);
    /* A second bud two voxels higher: s(5,5,5) = 1 + 0.25. */
    const float p2[3] = {5.5f, 7.5f, 5.5f};
    mer_shadow_cast_at(sh, p2, 1);
    assert_close(at(sh, 5, 5, 5), 1.25f);
    assert_close(at(sh, 4, 6, 4), 0.5f);
    assert_close(mer_shadow_light(sh, p, 1.0f), 0.75f);
    assert_close(mer_shadow_light(sh, p2, 1.0f), 1.0f);
    /* Deep shade clamps at 0: C = 0.1 gives 0.1 − 1.25 + 1 < 0. */
    assert_close(mer_shadow_light(sh, p, 0.1f), 0.0f);
    mer_shadow_free(sh);
}

static void test_pyramid_clipped_at_edges(void **state)
{
    (void)state;
    mer_shadow *sh;
    assert_int_equal(mer_shadow_new(BMIN, BMAX, 1.0f, 1.0f, 2.0f, 4, &sh, NULL), MER_OK);
    const float p[3] = {0.5f, 1.5f, 0.5f}; /* voxel (0, 1, 0) */
    mer_shadow_cast_at(sh, p, 1);
    assert_close(at(sh, 0, 1, 0), 1.0f);
    assert_close(at(sh, 0, 0, 0), 0.5f);
    assert_close(at(sh, 1, 0, 1), 0.5f);
    assert_close(at(sh, 2, 0, 0), 0.0f);
    /* A point beyond the grid is filed in the nearest border voxel. */
    const float far[3] = {-3.0f, 1.2f, 0.2f};
    int ijk[3];
    assert_int_equal(mer_shadow_voxel_of(sh, far, ijk), 0);
    assert_int_equal(ijk[0], 0);
    assert_int_equal(ijk[1], 1);
    assert_int_equal(ijk[2], 0);
    assert_close(mer_shadow_light(sh, far, 1.0f), 1.0f); /* same voxel as the bud */
    mer_shadow_free(sh);
}

static void test_incremental_equals_rebuilt(void **state)
{
    (void)state;
    mer_shadow *a, *b;
    assert_int_equal(mer_shadow_new(BMIN, BMAX, 1.0f, 0.3f, 1.7f, 6, &a, NULL), MER_OK);
    assert_int_equal(mer_shadow_new(BMIN, BMAX, 1.0f, 0.3f, 1.7f, 6, &b, NULL), MER_OK);
    const float pts[4][3] = {{5.2f, 8.1f, 4.9f}, {3.3f, 6.6f, 7.7f}, {5.9f, 9.9f, 5.1f}, {1.1f, 2.2f, 3.3f}};
    uint64_t empty = mer_shadow_hash(a);
    for (int i = 0; i < 4; i++)
        mer_shadow_cast_at(a, pts[i], 1);
    mer_shadow_cast_at(a, pts[1], -1);
    mer_shadow_cast_at(a, pts[3], -1);
    mer_shadow_cast_at(b, pts[2], 1);  /* other order, only the survivors */
    mer_shadow_cast_at(b, pts[0], 1);
    assert_true(mer_shadow_hash(a) == mer_shadow_hash(b));
    assert_true(mer_shadow_hash(a) != empty);
    mer_shadow_cast_at(a, pts[0], -1);
    mer_shadow_cast_at(a, pts[2], -1);
    assert_true(mer_shadow_hash(a) == empty); /* exact: fixed point */
    mer_shadow_free(a);
    mer_shadow_free(b);
}

/* Casts held back and cast layer by layer (merp_shadow_cast_layers, the bud
 * batch) give the grid of the same casts made one by one: sparse layers add
 * each square, crowded ones (here a 40 × 40 patch of buds under q_max 6) go
 * through a running sum, and both must agree bit for bit, clipped edges and
 * lifted (negative) counts included. */
static void test_layers_equal_single_casts(void **state)
{
    (void)state;
    static const float lo[3] = {0, 0, 0}, hi[3] = {48, 24, 40};
    mer_shadow *a, *b;
    assert_int_equal(mer_shadow_new(lo, hi, 1.0f, 0.3f, 1.7f, 6, &a, NULL), MER_OK);
    assert_int_equal(mer_shadow_new(lo, hi, 1.0f, 0.3f, 1.7f, 6, &b, NULL), MER_OK);
    merp_shadow_cast c[1700];
    size_t n = 0;
    uint32_t x = 12345;
    for (int j = 0; j < 24; j += 3)
        for (int t = 0; t < 200; t++) {
            x = x * 1103515245u + 12345u;
            int32_t count = (int32_t)(x >> 28) - 7; /* −7 .. 8, a few 0 */
            int ijk[3] = {(int)(x >> 8) % 48, j, (int)(x >> 16) % 40};
            c[n++] = (merp_shadow_cast){ijk[0], ijk[1], ijk[2], count};
            for (int r = 0; r < (count < 0 ? -count : count); r++)
                mer_shadow_cast(b, ijk, count < 0 ? -1 : 1, 1.0f);
        }
    int far[3] = {47, 23, 39}; /* one lone pyramid in a corner */
    c[n++] = (merp_shadow_cast){far[0], far[1], far[2], 1};
    mer_shadow_cast(b, far, 1, 1.0f);
    merp_shadow_cast_layers(a, c, n);
    assert_true(mer_shadow_hash(a) == mer_shadow_hash(b));
    mer_shadow_free(a);
    mer_shadow_free(b);
}

static void test_direction_least_shadowed_neighbour(void **state)
{
    (void)state;
    mer_shadow *sh;
    assert_int_equal(mer_shadow_new(BMIN, BMAX, 1.0f, 1.0f, 2.0f, 2, &sh, NULL), MER_OK);
    const float p[3] = {5.5f, 5.5f, 5.5f}, up[3] = {0, 1, 0};
    float v[3];
    /* Unshaded: keep the bud's own course, even when the cone (θ = 100°) takes in
     * the 45° neighbours, which come first in the scan. */
    mer_shadow_direction(sh, p, up, 90.0f, MER_SHADOW_DIR_NEIGHBOUR, v);
    assert_close(v[0], 0.0f);
    assert_close(v[1], 1.0f);
    mer_shadow_direction(sh, p, up, 100.0f, MER_SHADOW_DIR_NEIGHBOUR, v);
    assert_close(v[0], 0.0f);
    assert_close(v[1], 1.0f);
    assert_close(v[2], 0.0f);
    /* A bud in voxel (6, 7, 5) shades (5..7, 6, 4..6) by 0.5: of the neighbours
     * within 50° of up, only (4, 6, 5) stays at 0. */
    const float q[3] = {6.5f, 7.5f, 5.5f};
    mer_shadow_cast_at(sh, q, 1);
    mer_shadow_cast_at(sh, p, 1);
    mer_shadow_direction(sh, p, up, 100.0f, MER_SHADOW_DIR_NEIGHBOUR, v);
    assert_close(v[0], -0.70710678f);
    assert_close(v[1], 0.70710678f);
    assert_close(v[2], 0.0f);
    /* A narrow cone (θ = 10°) sees only the shaded (5, 6, 5): V is still up. */
    mer_shadow_direction(sh, p, up, 10.0f, MER_SHADOW_DIR_NEIGHBOUR, v);
    assert_close(v[1], 1.0f);
    mer_shadow_free(sh);
}

static void test_direction_gradient(void **state)
{
    (void)state;
    mer_shadow *sh;
    assert_int_equal(mer_shadow_new(BMIN, BMAX, 1.0f, 1.0f, 2.0f, 2, &sh, NULL), MER_OK);
    const float p[3] = {5.5f, 5.5f, 5.5f}, up[3] = {0, 1, 0};
    const float q[3] = {7.5f, 6.5f, 5.5f}; /* voxel (7, 6, 5) */
    mer_shadow_cast_at(sh, p, 1);
    mer_shadow_cast_at(sh, q, 1);
    /* s(6,5,5) = 0.5, s(4,5,5) = 0; s(5,6,5) = 0, s(5,4,5) = 0.5 + 0.25; z symmetric.
     * g = (0.25, −0.375, 0); V = −g/|g| = (−0.5547, 0.8321, 0). */
    float v[3];
    mer_shadow_direction(sh, p, up, 90.0f, MER_SHADOW_DIR_GRADIENT, v);
    assert_close(v[0], -0.554700f);
    assert_close(v[1], 0.832050f);
    assert_close(v[2], 0.0f);
    mer_shadow_free(sh);
}

static void test_new_rejects_bad_parameters(void **state)
{
    (void)state;
    mer_shadow *sh;
    mer_error err;
    assert_int_equal(mer_shadow_new(BMIN, BMAX, 1.0f, 1.0f, 1.0f, 2, &sh, &err), MER_ERR_RANGE);
    assert_string_equal(err.field, "shadow_b");
    assert_int_equal(mer_shadow_new(BMIN, BMAX, 1.0f, 0.0f, 2.0f, 2, &sh, &err), MER_ERR_RANGE);
    assert_string_equal(err.field, "shadow_a");
    assert_int_equal(mer_shadow_new(BMIN, BMAX, 1.0f, 1.0f, 2.0f, 33, &sh, &err), MER_ERR_RANGE);
    assert_string_equal(err.field, "q_max");
    assert_int_equal(mer_shadow_new(BMIN, BMAX, 0.01f, 1.0f, 2.0f, 2, &sh, &err), MER_ERR_LIMIT);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pyramid_values),
        cmocka_unit_test(test_pyramid_clipped_at_edges),
        cmocka_unit_test(test_incremental_equals_rebuilt),
        cmocka_unit_test(test_layers_equal_single_casts),
        cmocka_unit_test(test_direction_least_shadowed_neighbour),
        cmocka_unit_test(test_direction_gradient),
        cmocka_unit_test(test_new_rejects_bad_parameters),
    };
    return cmocka_run_group_tests_name("shadow", tests, NULL, NULL);
}
