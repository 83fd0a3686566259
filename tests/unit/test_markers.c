/* Unit tests for lib/env/markers.c: occupancy, cone membership, competition, Q and V;
 * and markers_near.c: the markers near a set of points. */
#include "config.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <meristem/markers.h>

#include "core/alloc.h"
#include "env/markers_near.h"

#define assert_close(a, b) assert_true(fabsf((a) - (b)) < 1e-4f)

static const float BMIN[3] = {-10, -10, -10}, BMAX[3] = {10, 10, 10};

static void test_cone_membership(void **state)
{
    (void)state;
    const float o[3] = {0, 0, 0}, x[3] = {1, 0, 0};
    float c45 = cosf(45.0f * 0.017453292f); /* θ = 90° */
    const float in44[3] = {cosf(0.7679f), sinf(0.7679f), 0};   /* 44° */
    const float out46[3] = {cosf(0.8029f), sinf(0.8029f), 0};  /* 46° */
    assert_true(mer_in_cone(o, x, in44, 2.0f, c45));
    assert_false(mer_in_cone(o, x, out46, 2.0f, c45));
    const float at_r[3] = {2, 0, 0}, past_r[3] = {2.001f, 0, 0}, behind[3] = {-1, 0, 0};
    assert_true(mer_in_cone(o, x, at_r, 2.0f, c45));      /* distance r is inside */
    assert_false(mer_in_cone(o, x, past_r, 2.0f, c45));
    assert_false(mer_in_cone(o, x, behind, 2.0f, c45));
    assert_false(mer_in_cone(o, x, o, 2.0f, c45));        /* the apex is outside */
    /* θ = 270°: a half-angle of 135° takes in 120° but not 150° */
    float c135 = cosf(135.0f * 0.017453292f);
    const float a120[3] = {cosf(2.0944f), sinf(2.0944f), 0}, a150[3] = {cosf(2.618f), sinf(2.618f), 0};
    assert_true(mer_in_cone(o, x, a120, 2.0f, c135));
    assert_false(mer_in_cone(o, x, a150, 2.0f, c135));
    /* θ = 360°: everything within r */
    assert_true(mer_in_cone(o, x, behind, 2.0f, -1.0f));
}

/* Two buds: A at the origin pointing +x, B at (3, 0, 0) pointing +y; ρ = 0.5,
 * r = 4, θ = 90°. Worked by hand in the comments. */
static void test_colonize_hand_placed(void **state)
{
    (void)state;
    mer_markers *m;
    assert_int_equal(mer_markers_new(BMIN, BMAX, 1.0f, &m, NULL), MER_OK);
    const float pts[] = {
        0.3f, 0, 0,   /* m0: 0.3 from A, inside ρ: removed */
        2, 0.5f, 0,   /* m1: A's cone (14°, 2.06); B sees it at 63°: out. Goes to A */
        3, 1, 0,      /* m2: A's cone at 3.16, B's at 1: goes to the closer B */
        2, 3, 0,      /* m3: A at 56°: out; B at 18°, 3.16: B */
        0, 2, 0,      /* m4: A at 90°, B at 56°: nobody's */
        -1, 0, 0,     /* m5: behind A */
        3, 0.2f, 0,   /* m6: 0.2 from B, inside ρ: removed */
    };
    assert_int_equal(mer_markers_add(m, pts, 7, NULL), MER_OK);
    assert_int_equal(mer_markers_count(m), 7);
    const float pos[6] = {0, 0, 0, 3, 0, 0}, dir[6] = {1, 0, 0, 0, 1, 0};
    float q[2], v[6];
    uint32_t cnt[2];
    assert_int_equal(mer_markers_colonize(m, 2, pos, dir, 0.5f, 4.0f, 90.0f, q, v, cnt, NULL, NULL), MER_OK);
    assert_int_equal(mer_markers_count(m), 5);  /* m0 and m6 gone; association keeps markers */
    assert_int_equal(cnt[0], 1);
    assert_int_equal(cnt[1], 2);
    assert_close(q[0], 1.0f);
    assert_close(q[1], 1.0f);
    /* V_A = (2, 0.5, 0)/|.| = (0.9701, 0.2425, 0) */
    assert_close(v[0], 0.970143f);
    assert_close(v[1], 0.242536f);
    assert_close(v[2], 0.0f);
    /* V_B = normalize((0,1,0) + (−1,3,0)/√10) = (−0.16013, 0.98710, 0) */
    assert_close(v[3], -0.160128f);
    assert_close(v[4], 0.987097f);
    float left[15];
    assert_int_equal(mer_markers_positions(m, left, 5), 5);
    assert_close(left[0], 2.0f);  /* m1 first: index order */
    assert_close(left[12], -1.0f); /* m5 last */
    mer_markers_free(m);
}

static void test_empty_set_gives_q0(void **state)
{
    (void)state;
    mer_markers *m;
    assert_int_equal(mer_markers_new(BMIN, BMAX, 2.0f, &m, NULL), MER_OK);
    const float pts[] = {0, 5, 0};
    mer_markers_add(m, pts, 1, NULL);
    const float pos[3] = {0, 0, 0}, dir[3] = {1, 0, 0};
    float q[1], v[3];
    mer_markers_colonize(m, 1, pos, dir, 0.5f, 4.0f, 90.0f, q, v, NULL, NULL, NULL);
    assert_close(q[0], 0.0f);   /* the marker is 90° off and 5 away */
    assert_close(v[0], 0.0f);
    assert_close(v[1], 0.0f);
    mer_markers_free(m);
}

static void test_tie_goes_to_first_bud(void **state)
{
    (void)state;
    mer_markers *m;
    assert_int_equal(mer_markers_new(BMIN, BMAX, 1.0f, &m, NULL), MER_OK);
    const float pts[] = {0, 2, 0};
    mer_markers_add(m, pts, 1, NULL);
    /* Two buds symmetric about the marker, both pointing at it from 2 away. */
    const float pos[6] = {-1, 2 - 1.7320508f, 0, 1, 2 - 1.7320508f, 0};
    const float dir[6] = {0.5f, 0.8660254f, 0, -0.5f, 0.8660254f, 0};
    float q[2], v[6];
    uint32_t cnt[2];
    mer_markers_colonize(m, 2, pos, dir, 0.1f, 4.0f, 90.0f, q, v, cnt, NULL, NULL);
    assert_int_equal(cnt[0], 1);
    assert_int_equal(cnt[1], 0);
    /* Swap the order: the other bud wins. */
    const float pos2[6] = {1, 2 - 1.7320508f, 0, -1, 2 - 1.7320508f, 0};
    const float dir2[6] = {-0.5f, 0.8660254f, 0, 0.5f, 0.8660254f, 0};
    mer_markers_colonize(m, 2, pos2, dir2, 0.1f, 4.0f, 90.0f, q, v, cnt, NULL, NULL);
    assert_int_equal(cnt[0], 1);
    assert_int_equal(cnt[1], 0);
    mer_markers_free(m);
}

/* A bud with no live marker in its perception volume is reported quiet, even
 * with markers around it (behind it, or beyond r): they can never be its; one
 * with a marker in its cone is not. */
static void test_quiet_buds(void **state)
{
    (void)state;
    mer_markers *m;
    assert_int_equal(mer_markers_new(BMIN, BMAX, 2.0f, &m, NULL), MER_OK);
    const float pts[] = {0, 0, 1.0f, 8, 8, 8, 8, 2, 8};
    mer_markers_add(m, pts, 3, NULL);
    /* bud 0 at the origin: its occupancy zone (ρ = 1.5) eats the first marker, the
     * others are far: quiet. bud 1 at (8, 5, 8) pointing up: (8, 8, 8) is in its
     * cone, (8, 2, 8) behind it: not quiet. bud 2 there pointing down sees
     * (8, 2, 8): not quiet either. */
    const float pos[9] = {0, 0, 0, 8, 5, 8, 8, 5, 8}, dir[9] = {1, 0, 0, 0, 1, 0, 0, -1, 0};
    float q[3], v[9];
    uint8_t quiet[3];
    mer_markers_colonize(m, 3, pos, dir, 1.5f, 4.0f, 90.0f, q, v, NULL, quiet, NULL);
    assert_int_equal(quiet[0], 1);
    assert_int_equal(quiet[1], 0);
    assert_int_equal(quiet[2], 0);
    /* the marker above goes (a zone of ρ = 3.5 around (8, 11, 8)): bud 1 has
     * (8, 2, 8) behind it, in its cells, and is quiet now */
    const float above[3] = {8, 11, 8};
    assert_int_equal(mer_markers_remove_sphere(m, above, 3.5f), 1);
    mer_markers_colonize(m, 3, pos, dir, 1.5f, 4.0f, 90.0f, q, v, NULL, quiet, NULL);
    assert_int_equal(quiet[1], 1);
    assert_close(q[1], 0.0f);
    assert_int_equal(quiet[2], 0);
    assert_close(q[2], 1.0f);
    mer_markers_free(m);
}

static int below_zero(const float p[3], void *ctx)
{
    (void)ctx;
    return p[1] < 0.0f;
}

static void test_remove_sphere_and_predicate(void **state)
{
    (void)state;
    mer_markers *m;
    assert_int_equal(mer_markers_new(BMIN, BMAX, 3.0f, &m, NULL), MER_OK);
    /* A line of 21 markers from x = -10 to 10, y = 1, plus 5 below ground, plus one
     * far outside the grid (filed in a border cell). */
    float pts[27 * 3];
    for (int i = 0; i < 21; i++) {
        pts[3 * i] = (float)(i - 10);
        pts[3 * i + 1] = 1.0f;
        pts[3 * i + 2] = 0.0f;
    }
    for (int i = 21; i < 26; i++) {
        pts[3 * i] = (float)(i - 21);
        pts[3 * i + 1] = -1.0f;
        pts[3 * i + 2] = 0.0f;
    }
    pts[78] = 50.0f;
    pts[79] = 1.0f;
    pts[80] = 0.0f;
    mer_markers_add(m, pts, 27, NULL);
    const float c[3] = {0, 1, 0};
    /* radius 2, inclusive: x = -2..2 on the line, and (0, -1, 0) at exactly 2 */
    assert_int_equal(mer_markers_remove_sphere(m, c, 2.0f), 6);
    assert_int_equal(mer_markers_count(m), 21);
    assert_int_equal(mer_markers_remove_if(m, below_zero, NULL), 4);
    assert_int_equal(mer_markers_count(m), 17);
    const float far[3] = {49, 1, 0};
    assert_int_equal(mer_markers_remove_sphere(m, far, 1.5f), 1); /* outside the grid too */
    /* Adding after removals keeps the index order. */
    const float more[3] = {0, 1, 0};
    mer_markers_add(m, more, 1, NULL);
    assert_int_equal(mer_markers_remove_sphere(m, c, 0.5f), 1);
    mer_markers_free(m);
}

static void test_new_rejects_bad_grids(void **state)
{
    (void)state;
    mer_markers *m = (mer_markers *)&m;
    mer_error err;
    assert_int_equal(mer_markers_new(BMIN, BMAX, 0.0f, &m, &err), MER_ERR_RANGE);
    assert_null(m);
    assert_string_equal(err.field, "marker_cell");
    assert_int_equal(mer_markers_new(BMAX, BMIN, 1.0f, &m, &err), MER_ERR_RANGE);
    assert_int_equal(mer_markers_new(BMIN, BMAX, 0.001f, &m, &err), MER_ERR_LIMIT);
}

/* The index of the marker at p among the n at pts, or -1. */
static int index_of(const float *pts, int n, const float *p)
{
    for (int i = 0; i < n; i++)
        if (pts[3 * i] == p[0] && pts[3 * i + 1] == p[1] && pts[3 * i + 2] == p[2])
            return i;
    return -1;
}

static void test_markers_near(void **state)
{
    (void)state;
    mer_markers *m;
    assert_int_equal(mer_markers_new(BMIN, BMAX, 3.0f, &m, NULL), MER_OK);
    /* A lattice of 13³ markers 1.5 apart, added from the far corner back so that
     * index order is not cell order, and one far outside the grid. */
    enum { SIDE = 13, N = SIDE * SIDE * SIDE + 1 };
    static float pts[3 * N];
    for (int i = 0; i < N - 1; i++) {
        pts[3 * i] = 9.0f - 1.5f * (float)(i % SIDE);
        pts[3 * i + 1] = 9.0f - 1.5f * (float)(i / SIDE % SIDE);
        pts[3 * i + 2] = 9.0f - 1.5f * (float)(i / (SIDE * SIDE));
    }
    pts[3 * (N - 1)] = 50.0f;
    pts[3 * (N - 1) + 1] = 1.0f;
    pts[3 * (N - 1) + 2] = 0.0f;
    assert_int_equal(mer_markers_add(m, pts, N, NULL), MER_OK);
    const float gone[3] = {0, 0, 0};
    assert_int_equal(mer_markers_remove_sphere(m, gone, 0.0f), 1);
    const float q[6] = {0.2f, 0.1f, 0.0f, 49.0f, 1.0f, 0.0f};
    float *xyz = NULL;
    size_t cap = 0, count = 0, again = 0;
    for (int round = 0; round < 2; round++) {
        assert_int_equal(merp_markers_near(m, q, 2, 2.5f, &xyz, &cap, &count, NULL), MER_OK);
        assert_true(count > 0 && count < N - 100);
        int last = -1, within = 0;
        for (size_t j = 0; j < count; j++) {
            int i = index_of(pts, N, xyz + 3 * j);
            assert_true(i > last); /* index order, each once */
            last = i;
            assert_false(pts[3 * i] == 0.0f && pts[3 * i + 1] == 0.0f && pts[3 * i + 2] == 0.0f);
        }
        /* every live marker within the radius of a point is listed */
        for (int i = 0; i < N; i++) {
            const float *p = pts + 3 * i;
            for (int k = 0; k < 2; k++) {
                float dx = p[0] - q[3 * k], dy = p[1] - q[3 * k + 1], dz = p[2] - q[3 * k + 2];
                if (dx * dx + dy * dy + dz * dz > 2.5f * 2.5f || (p[0] == 0 && p[1] == 0 && p[2] == 0))
                    continue;
                within++;
                int listed = 0;
                for (size_t j = 0; j < count; j++)
                    listed |= index_of(pts, N, xyz + 3 * j) == i;
                assert_true(listed);
            }
        }
        assert_true(within > 10);
        if (round == 1)
            assert_int_equal(count, again); /* the scratch was left clean */
        again = count;
    }
    /* A query elsewhere lists what it lists on a set never asked before: nothing
     * of the earlier queries is left in the scratch (repeating one query could not
     * tell, it would mark the same markers again). */
    const float q2[3] = {-7.5f, -7.5f, -7.5f};
    assert_int_equal(merp_markers_near(m, q2, 1, 2.5f, &xyz, &cap, &count, NULL), MER_OK);
    mer_markers *fresh;
    assert_int_equal(mer_markers_new(BMIN, BMAX, 3.0f, &fresh, NULL), MER_OK);
    assert_int_equal(mer_markers_add(fresh, pts, N, NULL), MER_OK);
    assert_int_equal(mer_markers_remove_sphere(fresh, gone, 0.0f), 1);
    float *xyz2 = NULL;
    size_t cap2 = 0, count2 = 0;
    assert_int_equal(merp_markers_near(fresh, q2, 1, 2.5f, &xyz2, &cap2, &count2, NULL), MER_OK);
    assert_true(count2 > 0);
    assert_int_equal(count, count2);
    assert_memory_equal(xyz, xyz2, 3 * count * sizeof *xyz);
    merp_free(xyz2);
    mer_markers_free(fresh);
    merp_free(xyz);
    mer_markers_free(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cone_membership),
        cmocka_unit_test(test_colonize_hand_placed),
        cmocka_unit_test(test_empty_set_gives_q0),
        cmocka_unit_test(test_tie_goes_to_first_bud),
        cmocka_unit_test(test_quiet_buds),
        cmocka_unit_test(test_remove_sphere_and_predicate),
        cmocka_unit_test(test_new_rejects_bad_grids),
        cmocka_unit_test(test_markers_near),
    };
    return cmocka_run_group_tests_name("markers", tests, NULL, NULL);
}
