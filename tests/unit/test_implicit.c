/* The fields of the implicit junctions (G04 §3): the tapered capsule's iso
 * surface at the pipe radius, summation, PCM's contact surface and C¹ bulge,
 * F_b's range and flat ends, and eq. (4)'s reductions. */
#include "config.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "mesh/implicit/implicit.h"

#include "fork_fixture.h"

static const merp_seg seg_x = {{0, 0, 0}, {2, 0, 0}, 0.5f, 0.25f};

/* At distance r(t) from the segment, f = c; inside more, outside less. */
static void capsule_iso_at_radius(void **state)
{
    (void)state;
    for (int i = 0; i <= 10; i++) {
        float t = (float)i / 10.0f, r = (1 - t) * 0.5f + t * 0.25f;
        float on[3] = {2 * t, r * 0.6f, r * 0.8f}, in[3] = {2 * t, 0.9f * r, 0}, out[3] = {2 * t, 0, 1.1f * r};
        assert_float_equal(merp_seg_field(&seg_x, on), MERP_ISO, 1e-5);
        assert_true(merp_seg_field(&seg_x, in) > MERP_ISO);
        assert_true(merp_seg_field(&seg_x, out) < MERP_ISO);
    }
    /* The end caps are spheres of the end radii. */
    const float cap_a[3] = {-0.5f, 0, 0}, cap_b[3] = {2.25f, 0, 0};
    assert_float_equal(merp_seg_field(&seg_x, cap_a), MERP_ISO, 1e-5);
    assert_float_equal(merp_seg_field(&seg_x, cap_b), MERP_ISO, 1e-5);
    /* Compact support: 0 at and beyond R = r / x_c. */
    const float far[3] = {0, merp_seg_support(&seg_x) * 1.001f, 0};
    assert_float_equal(merp_seg_field(&seg_x, far), 0.0f, 0);
}

static void sum_blend(void **state)
{
    (void)state;
    const float f[3] = {0.25f, 0.125f, 0.5f};
    assert_float_equal(merp_blend_sum(f, 3), 0.875f, 1e-7);
    assert_float_equal(merp_blend_sum(f, 0), 0.0f, 0);
}

/* Δ is C¹: continuous with slope 1 through 0, flat and 0 at w. */
static void pcm_delta_c1(void **state)
{
    (void)state;
    const float w = 0.3f, e = 1e-3f;
    assert_float_equal(merp_pcm_delta(0, w), 0.0f, 0);
    assert_float_equal((merp_pcm_delta(e, w) - merp_pcm_delta(0, w)) / e, 1.0f, 0.02);
    assert_float_equal((merp_pcm_delta(0, w) - merp_pcm_delta(-e, w)) / e, 1.0f, 1e-3);
    assert_float_equal(merp_pcm_delta(w, w), 0.0f, 1e-7);
    assert_float_equal((merp_pcm_delta(w, w) - merp_pcm_delta(w - e, w)) / e, 0.0f, 0.02);
    assert_float_equal(merp_pcm_delta(w + e, w), 0.0f, 0);
    assert_float_equal(merp_pcm_delta(w / 3, w), 4 * w / 27, 1e-6); /* the bulge's top */
}

/* Two overlapping balls: on their contact surface {f1 = f2} inside both, both
 * deformed fields are exactly c, and the union max(f1', f2') is ≥ c there. */
static void pcm_keeps_contact_surface(void **state)
{
    (void)state;
    const merp_seg s1 = {{-0.5f, 0, 0}, {-0.5f, 0, 0}, 1, 1}, s2 = {{0.5f, 0, 0}, {0.5f, 0, 0}, 1, 1};
    int checked = 0;
    for (int j = -8; j <= 8; j++)
        for (int k = -8; k <= 8; k++) {
            const float p[3] = {0, 0.1f * (float)j, 0.1f * (float)k}; /* the plane x = 0: f1 = f2 */
            float f1 = merp_seg_field(&s1, p), f2 = merp_seg_field(&s2, p), a, b;
            assert_float_equal(f1, f2, 1e-6);
            if (f1 < MERP_ISO)
                continue;
            merp_pcm_pair(f1, f2, 0.2f, &a, &b);
            assert_float_equal(a, MERP_ISO, 1e-6);
            assert_float_equal(b, MERP_ISO, 1e-6);
            assert_true(merp_pcm_union(f1, f2, 0.2f) >= MERP_ISO - 1e-6f);
            checked++;
        }
    assert_true(checked > 20);
    /* Off the plane inside both, each deformed solid keeps only its own side. */
    const float p[3] = {0.2f, 0, 0};
    float a, b;
    merp_pcm_pair(merp_seg_field(&s1, p), merp_seg_field(&s2, p), 0.2f, &a, &b);
    assert_true(a < MERP_ISO && b > MERP_ISO);
    /* Outside the other solid, near it, the bulge adds; far from it, nothing. */
    const float q[3] = {-1.4f, 0, 0}, qfar[3] = {-1.8f, 0, 0};
    merp_pcm_pair(merp_seg_field(&s1, q), merp_seg_field(&s2, q), 0.5f, &a, &b);
    assert_true(a > merp_seg_field(&s1, q));
    merp_pcm_pair(merp_seg_field(&s1, qfar), merp_seg_field(&s2, qfar), 0.5f, &a, &b);
    assert_float_equal(a, merp_seg_field(&s1, qfar), 0);
}

static const merp_bound bound_y = {{0, 0, 0}, {0, 1, 0}, 0.2f, 0.7f};

static float fb_at(float d)
{
    const float p[3] = {d, 0.5f, 0};
    return merp_bound_field(&bound_y, p);
}

/* F_b ∈ [0, 1], 1 inside r_in, 0 beyond r_out, monotone between. */
static void fb_range(void **state)
{
    (void)state;
    float prev = 2;
    for (int i = 0; i <= 100; i++) {
        float v = fb_at(0.01f * (float)i);
        assert_true(v >= 0 && v <= 1 && v <= prev);
        prev = v;
    }
    assert_float_equal(fb_at(0.1f), 1.0f, 0);
    assert_float_equal(fb_at(0.8f), 0.0f, 0);
    assert_true(fb_at(0.45f) > 0 && fb_at(0.45f) < 1);
}

/* ∇F_b = 0 where F_b = 1 and where F_b = 0 (G04 §3.1): the one-sided
 * difference quotient at r_in and r_out vanishes with the step. */
static void fb_gradient_vanishes_at_ends(void **state)
{
    (void)state;
    for (float e = 1e-2f; e > 1e-3f; e *= 0.5f) {
        float g_in = (fb_at(0.2f + e) - fb_at(0.2f)) / e;
        float g_out = (fb_at(0.7f) - fb_at(0.7f - e)) / e;
        assert_true(fabsf(g_in) < 40 * e);      /* O(e): the slope at the end is 0 */
        assert_true(fabsf(g_out) < 1e-3f);      /* (1 − s²)^6: the slope is O(e^5) */
    }
    /* In between the slope is not 0 (the field does fall). */
    assert_true(fabsf((fb_at(0.46f) - fb_at(0.44f)) / 0.02f) > 0.5f);
}

/* Eq. (4): F_g = B1 where F_b = 1, B2 where F_b = 0, a convex mix between. */
static void gbb_reduces(void **state)
{
    (void)state;
    const float f[2] = {0.4f, 0.3f};
    float b1 = merp_pcm_union(f[0], f[1], 0.2f), b2 = merp_blend_sum(f, 2);
    assert_float_equal(merp_gbb(fb_at(0.0f), b1, b2), b1, 0);
    assert_float_equal(merp_gbb(fb_at(0.9f), b1, b2), b2, 0);
    float mid = merp_gbb(fb_at(0.45f), b1, b2);
    assert_true(mid > (b1 < b2 ? b1 : b2) && mid < (b1 > b2 ? b1 : b2));
}

/* A fork: the parent along y through J = 0 (radius 0.5, then 0.45), a
 * lateral of radius 0.3 at 45° towards +x. */
static merp_junction aged_fork(float years)
{
    const float s2 = 0.70710678f, up[3] = {0, 1, 0};
    merp_junction j = {
        .in = {{0, -2.5f, 0}, {0, 0, 0}, 0.5f, 0.5f},
        .out = {{0, 0, 0}, {0, 2.5f, 0}, 0.45f, 0.45f},
        .lateral = {{{0, 0, 0}, {3 * s2, 3 * s2, 0}, 0.3f, 0.3f}},
        .laterals = 1,
        .w = 0.15f,
    };
    merp_junction_age(&j, up, years);
    return j;
}

typedef struct strengths {
    float trunk, crotch, under;
} strengths;

/* The largest scar or ridge strength (merp_junction_strength) on three
 * stretches of bark: the parent's ring at J on the side away from the
 * lateral, the crotch above the lateral, and the lateral's underside where it
 * meets the parent. */
static strengths measure(const merp_junction *j)
{
    const float s2 = 0.70710678f, up[3] = {0, 1, 0};
    merp_junction ref = *j;
    merp_junction_bound(&ref, 0, up, 1.0f);
    const float *C = ref.bound[0].a; /* the crotch */
    strengths m = {0, 0, 0};
    for (int a = 0; a <= 12; a++)
        for (int i = 0; i <= 16; i++) {
            float scar, ridge, u = (float)i / 16.0f;
            /* The far side: angles 120°..240° from +x, |y| ≤ 0.8. */
            float phi = (float)(M_PI * (2.0 / 3.0 + (2.0 / 3.0) * a / 12.0));
            const float pt[3] = {0.5f * cosf(phi), -0.8f + 1.6f * u, 0.5f * sinf(phi)};
            merp_junction_strength(j, pt, &scar, &ridge);
            m.trunk = fmaxf(m.trunk, scar + ridge);
            /* Within 0.15 of the crotch. */
            const float pc[3] = {C[0] + 0.3f * (u - 0.5f), C[1] + 0.3f * ((float)a / 12.0f - 0.5f), C[2]};
            merp_junction_strength(j, pc, &scar, &ridge);
            m.crotch = fmaxf(m.crotch, ridge);
            /* Under the lateral: its lower line, t in 0.3..0.9 along it. */
            float t = 0.3f + 0.6f * u, off = 0.3f + 0.02f * (float)(a - 6);
            const float pl[3] = {t * s2 + off * s2, t * s2 - off * s2, 0};
            merp_junction_strength(j, pl, &scar, &ridge);
            m.under = fmaxf(m.under, ridge);
        }
    return m;
}

/* G04 Fig. 7 as merp_junction_age's law: over years 1, 4, 7, 10 the scar on
 * the parent fades, the lateral's ring leaves its underside, and its crotch
 * keeps a ridge as strong as the scar was. */
static void ageing(void **state)
{
    (void)state;
    const float years[4] = {1, 4, 7, 10};
    strengths s[4];
    for (int y = 0; y < 4; y++) {
        merp_junction j = aged_fork(years[y]);
        s[y] = measure(&j);
        print_message("year %2.0f: trunk %.4f crotch %.4f under the lateral %.4f\n", (double)years[y],
                      (double)s[y].trunk, (double)s[y].crotch, (double)s[y].under);
    }
    assert_true(s[0].trunk > 0.02f && s[0].under > 0.02f);
    for (int y = 1; y < 4; y++) {
        assert_true(s[y].trunk < 0.7f * s[y - 1].trunk);
        assert_true(s[y].under <= s[y - 1].under);
        assert_true(s[y].crotch >= 0.95f * s[y - 1].crotch);
    }
    assert_true(s[3].trunk < 0.1f * s[0].trunk && s[1].under < 0.1f * s[0].under);
    assert_true(s[3].crotch > 0.5f * s[0].trunk);
    /* No scar set: the field is the one merp_junction_bound gives. */
    merp_junction plain = aged_fork(1.0f), aged = plain;
    plain.scar_weight = 0.0f;
    const float p[3] = {-0.5f, 0.2f, 0.0f};
    float scar, ridge;
    merp_junction_strength(&plain, p, &scar, &ridge);
    assert_float_equal(scar, 0.0f, 0.0f);
    merp_junction_strength(&aged, p, &scar, &ridge);
    assert_true(scar > 0.0f);
}

/* merp_junction_gradient: F_g as merp_junction_field gives it, and ∇F_g as
 * central differences see it, over a box about an aged fork (scar, ring and
 * ridge all present), except at the few points a crease or a max's switch
 * lies between the differences' samples. */
static void gradient_matches_differences(void **state)
{
    (void)state;
    const float years[2] = {1, 4}, e = 1e-3f;
    for (int y = 0; y < 2; y++) {
        merp_junction j = aged_fork(years[y]);
        int n = 0, off = 0;
        for (int a = 0; a < 24; a++)
            for (int b = 0; b < 24; b++)
                for (int c = 0; c < 6; c++) {
                    const float p[3] = {-0.8f + 2.4f * (float)a / 23.0f, -1.0f + 2.6f * (float)b / 23.0f,
                                        -0.6f + 1.2f * (float)c / 5.0f};
                    float g[3], f = merp_junction_gradient(&j, p, g), len = 0.0f, err = 0.0f;
                    assert_float_equal(f, merp_junction_field(p, &j), 1e-6f);
                    for (int k = 0; k < 3; k++) {
                        float hi[3] = {p[0], p[1], p[2]}, lo[3] = {p[0], p[1], p[2]};
                        hi[k] += e, lo[k] -= e;
                        float d = (merp_junction_field(hi, &j) - merp_junction_field(lo, &j)) / (2.0f * e);
                        len += d * d, err += (d - g[k]) * (d - g[k]);
                    }
                    n++;
                    off += sqrtf(err) > 0.02f * sqrtf(len) + 0.01f;
                }
        print_message("year %.0f: %d of %d points off\n", (double)years[y], off, n);
        assert_true(off * 50 < n);
    }
}

/* Of the points of a grid of m[0] × m[1] × m[2] over the box lo..hi (*n of
 * them), how many have jp's closed-form gradient off its field's central
 * differences (as gradient_matches_differences counts them); asserts that
 * the gradient's value is the field's. */
static int gradient_off(const merp_jprep *jp, const float lo[3], const float hi[3], const int m[3], int *n)
{
    const float e = 1e-3f;
    int off = 0;
    *n = 0;
    for (int a = 0; a < m[0]; a++)
        for (int b = 0; b < m[1]; b++)
            for (int c = 0; c < m[2]; c++) {
                const int i[3] = {a, b, c};
                float p[3], g[3], len = 0.0f, err = 0.0f;
                for (int k = 0; k < 3; k++)
                    p[k] = lo[k] + (hi[k] - lo[k]) * (float)i[k] / (float)(m[k] - 1);
                float fv = merp_jprep_gradient(jp, p, g);
                assert_float_equal(fv, merp_jprep_field(jp, p), 1e-6f);
                for (int k = 0; k < 3; k++) {
                    float up[3] = {p[0], p[1], p[2]}, dn[3] = {p[0], p[1], p[2]};
                    up[k] += e, dn[k] -= e;
                    float d = (merp_jprep_field(jp, up) - merp_jprep_field(jp, dn)) / (2.0f * e);
                    len += d * d, err += (d - g[k]) * (d - g[k]);
                }
                ++*n;
                off += sqrtf(err) > 0.02f * sqrtf(len) + 0.01f;
            }
    return off;
}

/* Two forks up one axis, as a run: aged_fork's at J0 = 0 with its
 * continuation ending at J1 = (0, 1.2, 0), and there a second lateral of
 * radius 0.28 at 45° towards −x; both forks' bark a year old (scars and
 * rings). */
static void aged_run(merp_junction f[2])
{
    const float s2 = 0.70710678f, up[3] = {0, 1, 0};
    f[0] = aged_fork(1.0f);
    f[0].out = (merp_seg){{0, 0, 0}, {0, 1.2f, 0}, 0.45f, 0.42f};
    f[1] = (merp_junction){
        .in = f[0].out,
        .out = {{0, 1.2f, 0}, {0, 3.5f, 0}, 0.42f, 0.4f},
        .lateral = {{{0, 1.2f, 0}, {-3 * s2, 1.2f + 3 * s2, 0}, 0.28f, 0.28f}},
        .laterals = 1,
        .w = 0.15f,
    };
    merp_junction_age(&f[0], up, 1.0f);
    merp_junction_age(&f[1], up, 1.0f);
}

/* A run's field (merp_jprep_init_run): a run of one fork is that fork's
 * junction to the bit; near each fork of a run of two, beyond the other's
 * primitives, it is that fork's junction field (up to rounding where the
 * other's scar band still reaches, as PCM of the axis with a field of 0
 * gives the axis back); the axis between the forks and both laterals are
 * one solid; and its closed-form gradient matches central differences. */
static void runs_fold_the_axis(void **state)
{
    (void)state;
    merp_junction f[2];
    aged_run(f);
    merp_jprep one, run, second;
    merp_jprep_init_run(&one, f, NULL, 1);
    merp_jprep_init_run(&run, f, NULL, 2);
    merp_jprep_init(&second, &f[1]);
    assert_int_equal(run.rows, 2); /* the axis in 3 lanes and 2 laterals: two rows */
    int near0 = 0, near1 = 0;
    for (int a = 0; a < 9; a++)
        for (int b = 0; b < 9; b++)
            for (int c = 0; c < 9; c++) {
                float u = (float)a / 8.0f - 0.5f, v = (float)b / 8.0f - 0.5f, w = (float)c / 8.0f - 0.5f;
                const float p[3] = {2.0f * u, 0.6f + 3.0f * v, 2.0f * w};
                float g1[3], g2[3];
                assert_true(merp_jprep_field(&one, p) == merp_junction_field(p, &f[0]));
                assert_true(merp_jprep_gradient(&one, p, g1) == merp_junction_gradient(&f[0], p, g2));
                assert_memory_equal(g1, g2, sizeof g1);
                /* within 0.15 of J0, below 0.15; within 0.1 of J1, above 1.15 */
                const float q0[3] = {0.3f * u, 0.3f * v, 0.3f * w}, q1[3] = {0.2f * u, 1.2f + 0.2f * v, 0.2f * w};
                if (q0[1] < 0.15f) {
                    assert_float_equal(merp_jprep_field(&run, q0), merp_junction_field(q0, &f[0]), 1e-6f);
                    near0++;
                }
                if (q1[1] > 1.15f) {
                    assert_float_equal(merp_jprep_field(&run, q1), merp_jprep_field(&second, q1), 1e-6f);
                    near1++;
                }
            }
    assert_true(near0 > 100 && near1 > 100);
    const float s2 = 0.70710678f;
    const float inside[4][3] = {{0, 0.6f, 0}, {0, 1.0f, 0.3f}, {0.5f * s2, 0.5f * s2, 0}, {-0.5f * s2, 1.2f + 0.5f * s2, 0}};
    for (int i = 0; i < 4; i++)
        assert_true(merp_jprep_field(&run, inside[i]) > MERP_ISO);
    const float lo[3] = {-0.9f, -0.8f, -0.6f}, hi[3] = {0.9f, 2.0f, 0.6f};
    int n, off = gradient_off(&run, lo, hi, (const int[3]){20, 30, 6}, &n);
    print_message("a run of two forks: %d of %d points off\n", off, n);
    assert_true(off * 50 < n);
}

/* A run with a fork up a lateral: aged_fork's fork at J0 = 0, whose
 * lateral (45° towards +x) ends at J1 = 2·(cos 45°, sin 45°, 0), where a
 * second fork goes on up it (its continuation along the lateral, a lateral
 * of radius 0.2 going up), both a year old. */
static void lateral_run(merp_junction f[2], merp_link link[2])
{
    const float s2 = 0.70710678f, up[3] = {0, 1, 0}, along[3] = {s2, s2, 0};
    const float J1[3] = {2 * s2, 2 * s2, 0};
    f[0] = aged_fork(1.0f);
    f[0].lateral[0] = (merp_seg){{0, 0, 0}, {J1[0], J1[1], 0}, 0.3f, 0.28f};
    f[1] = (merp_junction){
        .in = f[0].lateral[0],
        .out = {{J1[0], J1[1], 0}, {J1[0] + 2 * s2, J1[1] + 2 * s2, 0}, 0.26f, 0.24f},
        .lateral = {{{J1[0], J1[1], 0}, {J1[0], J1[1] + 2.0f, 0}, 0.2f, 0.2f}},
        .laterals = 1,
        .w = 0.15f,
    };
    merp_junction_age(&f[0], up, 1.0f);
    merp_junction_age(&f[1], along, 1.0f);
    link[0] = (merp_link){0, MERP_LINK_OUT};
    link[1] = (merp_link){0, 0}; /* up fork 0's lateral 0 */
}

/* A run whose second fork goes on up the first's lateral: near the first
 * fork, beyond the second's primitives, it is the first fork's field (up
 * to rounding where the second's scar band reaches); near the second,
 * beyond the first's, it is the second's junction field, whose parent is
 * the lateral; the lateral, its fork's continuation and lateral are one
 * solid with the parent; the gradient matches differences. */
static void runs_go_up_laterals(void **state)
{
    (void)state;
    merp_junction f[2];
    merp_link link[2];
    lateral_run(f, link);
    merp_jprep run, second;
    merp_jprep_init_run(&run, f, link, 2);
    merp_jprep_init(&second, &f[1]);
    assert_int_equal(run.lanes.groups, 2);
    const float s2 = 0.70710678f, J1[3] = {2 * s2, 2 * s2, 0};
    int near0 = 0, near1 = 0;
    for (int a = 0; a < 9; a++)
        for (int b = 0; b < 9; b++)
            for (int c = 0; c < 9; c++) {
                float u = (float)a / 8.0f - 0.5f, v = (float)b / 8.0f - 0.5f, w = (float)c / 8.0f - 0.5f;
                const float q0[3] = {0.4f * u, 0.4f * v, 0.4f * w};
                const float q1[3] = {J1[0] + 0.2f * u, J1[1] + 0.2f * v, 0.2f * w};
                assert_float_equal(merp_jprep_field(&run, q0), merp_junction_field(q0, &f[0]), 1e-6f);
                assert_float_equal(merp_jprep_field(&run, q1), merp_jprep_field(&second, q1), 1e-6f);
                near0++, near1++;
            }
    assert_true(near0 > 500 && near1 > 500);
    const float inside[4][3] = {{0, 0.6f, 0}, {s2, s2, 0}, {J1[0] + 0.5f * s2, J1[1] + 0.5f * s2, 0},
                                {J1[0], J1[1] + 0.5f, 0}};
    for (int i = 0; i < 4; i++)
        assert_true(merp_jprep_field(&run, inside[i]) > MERP_ISO);
    const float lo[3] = {-0.6f, -0.8f, -0.6f}, hi[3] = {2.2f, 2.8f, 0.6f};
    int n, off = gradient_off(&run, lo, hi, (const int[3]){24, 24, 6}, &n);
    print_message("a run up a lateral: %d of %d points off\n", off, n);
    assert_true(off * 50 < n);
}

/* A row's lanes are the scalar fields to the bit (row.c keeps their
 * arithmetic's order): a tapered segment, a ball, a bound of each kind and
 * cleared lanes, at points inside, on and beyond their supports. */
static void row_lanes_match_scalar(void **state)
{
    (void)state;
    const merp_seg ball = {{1, 1, 0}, {1, 1, 0}, 0.3f, 0.3f};
    const merp_bound ring = {{0.5f, 0, 0}, {0.5f, 0, 0.4f}, 0.0f, 0.3f};
    merp_row segs, bounds;
    merp_row_clear(&segs);
    merp_row_clear(&bounds);
    merp_row_set(&segs, 0, seg_x.a, seg_x.b, seg_x.ra, seg_x.rb);
    merp_row_set(&segs, 2, ball.a, ball.b, ball.ra, ball.rb);
    merp_row_set(&bounds, 1, bound_y.a, bound_y.b, bound_y.r_in, bound_y.r_out);
    merp_row_set(&bounds, 3, ring.a, ring.b, ring.r_in, ring.r_out);
    uint32_t x = 12345u;
    for (int i = 0; i < 20000; i++) {
        float p[3];
        for (int k = 0; k < 3; k++) {
            x = x * 1664525u + 1013904223u;
            p[k] = -1.0f + 3.5f * (float)(x >> 8) / 16777216.0f;
        }
        float f[MERP_ROW], F[MERP_ROW];
        merp_row_grad sg, bg;
        merp_row_seg_field(&segs, p, f);
        merp_row_seg_gradient(&segs, p, &sg);
        merp_row_bound_field(&bounds, p, F);
        merp_row_bound_gradient(&bounds, p, &bg);
        const float want_f[MERP_ROW] = {merp_seg_field(&seg_x, p), 0, merp_seg_field(&ball, p), 0};
        const float want_F[MERP_ROW] = {0, merp_bound_field(&bound_y, p), 0, merp_bound_field(&ring, p)};
        for (int l = 0; l < MERP_ROW; l++) {
            assert_true(f[l] == want_f[l] && sg.f[l] == want_f[l]);
            assert_true(F[l] == want_F[l] && bg.f[l] == want_F[l]);
            if (want_f[l] == 0.0f)
                assert_true(sg.g[0][l] == 0 && sg.g[1][l] == 0 && sg.g[2][l] == 0);
            if (want_F[l] == 0.0f || want_F[l] == 1.0f)
                assert_true(bg.g[0][l] == 0 && bg.g[1][l] == 0 && bg.g[2][l] == 0);
        }
    }
}

/* The bounds' reach balls (merp_jprep_near_bounds) hold their supports: at
 * a point outside every ball every bound lane is +0, field and gradient, as
 * the junction's fields take it when they skip the row there. Sampled on
 * thin shells just outside each ball (where a ball drawn too tight would
 * show) and over the fork fixture's box, for the fork as grown and with its
 * bud scale scar of year 1. */
static void reach_balls_hold_the_bounds(void **state)
{
    (void)state;
    static fork_fixture f;
    const float shift[3] = {0, 0, 0};
    fork_fixture_init(&f, 12, 0.1f, shift);
    for (int aged = 0; aged < 2; aged++) {
        merp_junction j = f.j;
        const float up[3] = {0, 1, 0};
        if (aged)
            merp_junction_age(&j, up, 1.0f);
        merp_jprep jp;
        merp_jprep_init(&jp, &j);
        assert_true(jp.reaches >= 1u + (uint32_t)aged);
        uint32_t x = 777u, outside = 0;
        for (int i = 0; i < 200000; i++) {
            float u[4], p[3];
            for (int k = 0; k < 4; k++) {
                x = x * 1664525u + 1013904223u;
                u[k] = (float)(x >> 8) / 16777216.0f;
            }
            if (i % 2 == 0) { /* a shell 0 to 2 % outside ball i/2 mod reaches */
                const float *b = jp.reach[(uint32_t)(i / 2) % jp.reaches];
                float z = 2.0f * u[0] - 1.0f, phi = MERP_TWO_PI * u[1], s = sqrtf(1.0f - z * z);
                float rho = sqrtf(b[3]) * (1.0f + 0.02f * u[2]);
                const float d[3] = {s * cosf(phi), s * sinf(phi), z};
                for (int k = 0; k < 3; k++)
                    p[k] = b[k] + rho * d[k];
            } else { /* the fixture's box */
                p[0] = -0.8f + 2.6f * u[0], p[1] = -1.4f + 3.3f * u[1], p[2] = -0.8f + 1.6f * u[2];
            }
            if (merp_jprep_near_bounds(&jp, p))
                continue;
            outside++;
            float F[MERP_ROW];
            merp_row_grad bg;
            merp_row_bound_field(&jp.bound[0], p, F);
            merp_row_bound_gradient(&jp.bound[0], p, &bg);
            for (int l = 0; l < MERP_ROW; l++) {
                assert_true(F[l] == 0.0f && !signbit(F[l]) && bg.f[l] == 0.0f && !signbit(bg.f[l]));
                assert_true(bg.g[0][l] == 0.0f && bg.g[1][l] == 0.0f && bg.g[2][l] == 0.0f);
            }
        }
        assert_true(outside > 50000);
    }
}

/* merp_jprep_gradient_bounds hands back the bound row's values bit for bit
 * as merp_jprep_bound_field gives them (the bark's b is read from them), and
 * the same F_g and gradient as merp_jprep_gradient: over the fork fixture's
 * box, near and far from the bounds, as grown and with a year-1 scar. */
static void gradient_gives_the_bounds(void **state)
{
    (void)state;
    static fork_fixture f;
    const float shift[3] = {0, 0, 0};
    fork_fixture_init(&f, 12, 0.1f, shift);
    for (int aged = 0; aged < 2; aged++) {
        merp_junction j = f.j;
        const float up[3] = {0, 1, 0};
        if (aged)
            merp_junction_age(&j, up, 1.0f);
        merp_jprep jp;
        merp_jprep_init(&jp, &j);
        uint32_t x = 4242u, near = 0;
        for (int i = 0; i < 20000; i++) {
            float u[3], p[3];
            for (int k = 0; k < 3; k++) {
                x = x * 1664525u + 1013904223u;
                u[k] = (float)(x >> 8) / 16777216.0f;
            }
            p[0] = -0.8f + 2.6f * u[0], p[1] = -1.4f + 3.3f * u[1], p[2] = -0.8f + 1.6f * u[2];
            float F[MERP_ROW], G[MERP_ROW], g[3], h[3];
            merp_jprep_bound_field(&jp, p, F);
            float a = merp_jprep_gradient_bounds(&jp, p, g, G), b = merp_jprep_gradient(&jp, p, h);
            assert_memory_equal(F, G, sizeof F);
            assert_memory_equal(&a, &b, sizeof a);
            assert_memory_equal(g, h, sizeof g);
            near += F[MERP_JBOUND_LATERAL] > 0.0f;
        }
        print_message("points where the lateral's F_b > 0: %u of 20000\n", near);
        assert_true(near > 100);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(capsule_iso_at_radius),
        cmocka_unit_test(sum_blend),
        cmocka_unit_test(pcm_delta_c1),
        cmocka_unit_test(pcm_keeps_contact_surface),
        cmocka_unit_test(fb_range),
        cmocka_unit_test(fb_gradient_vanishes_at_ends),
        cmocka_unit_test(gbb_reduces),
        cmocka_unit_test(ageing),
        cmocka_unit_test(gradient_matches_differences),
        cmocka_unit_test(runs_fold_the_axis),
        cmocka_unit_test(runs_go_up_laterals),
        cmocka_unit_test(row_lanes_match_scalar),
        cmocka_unit_test(reach_balls_hold_the_bounds),
        cmocka_unit_test(gradient_gives_the_bounds),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
