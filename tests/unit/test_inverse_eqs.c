/* The equations of G04 §4.1–4.3, each a pure function, on hand-built cases:
 * eqs (5)–(7) (lengths and the l_min floor), (8)–(9) (heading), (10), (13), (15)
 * (scale factor), (11) (shedding), (12) (order scaling), (14) (metamers), the
 * 137.5° phyllotaxis with the 40° rule, and the offsets of continuous growth. */
#include "config.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "models/inverse/inverse.h"

/* The straight line from (0, y0) to (1, y1). */
static void line(merp_gfunc *f, const char *name, float y0, float y1)
{
    const float xy[][2] = {{0, y0}, {1, y1}};
    mer_error err;
    if (merp_gfunc_make(f, name, MERP_GF_LINEAR, 2, xy, 2, &err) != MER_OK)
        fail_msg("%s", err.message);
}

/* A definition whose functions are all lines (given by the caller), heap-made. */
static merp_inv_def *def_new(void)
{
    merp_inv_def *d = calloc(1, sizeof *d);
    for (uint32_t i = 0; i < MERP_G_COUNT; i++)
        line(&d->g[i], merp_inv_fn_names[i], 0.0f, 1.0f);
    d->y_max = 10;
    d->h_max = 10.0f;
    d->l_min = 0.1f;
    d->l_max = 8.0f;
    d->ls_max = 1.0f;
    d->m_max = 10;
    d->a_max = 10.0f;
    d->s_min = 0.1f;
    d->theta_max = 90.0f;
    d->beta_short = 80.0f;
    d->beta_long = 35.0f;
    d->leaf_size = 0.1f;
    d->span = 0.5f;
    d->order_max = 3;
    d->r_max = 0.1f;
    return d;
}

/* Eq (6): the silhouettes blend by t_y and scale by the parent's length. */
static void test_eq6_silhouette(void **state)
{
    (void)state;
    merp_gfunc s1, s2;
    line(&s1, "G_s1", 0.2f, 0.2f);
    line(&s2, "G_s2", 0.6f, 0.6f);
    assert_float_equal(merp_inv_silhouette(&s1, &s2, 0.25f, 0.5f, 10.0f), 3.0f, 1e-5f);
    assert_float_equal(merp_inv_silhouette(&s1, &s2, 0.0f, 0.5f, 10.0f), 2.0f, 1e-5f);
    assert_float_equal(merp_inv_silhouette(&s1, &s2, 1.0f, 0.5f, 10.0f), 6.0f, 1e-5f);
    line(&s2, "G_s2", 1.0f, 0.0f); /* x_y matters: a cone */
    assert_float_equal(merp_inv_silhouette(&s1, &s2, 1.0f, 0.75f, 8.0f), 2.0f, 1e-5f);
    assert_float_equal(merp_inv_time(3, 12), 0.25f, 0.0f);
}

/* Eq (7) enforces eq (5): l_y >= l_{y-1} + l_min, even where the silhouette
 * would shrink the branch. */
static void test_eq7_enforces_l_min(void **state)
{
    (void)state;
    assert_float_equal(merp_inv_enforce_min(1.0f, 2.0f, 0.1f), 2.1f, 1e-6f);
    assert_float_equal(merp_inv_enforce_min(3.0f, 2.0f, 0.1f), 3.0f, 0.0f);
    merp_inv_def *d = def_new();
    /* Silhouettes of 0: each year adds exactly l_min. */
    line(&d->g[MERP_G_S1], "G_s1", 0.0f, 0.0f);
    line(&d->g[MERP_G_S2], "G_s2", 0.0f, 0.0f);
    float lp[11], l[11];
    for (int y = 0; y <= 10; y++)
        lp[y] = (float)y + 1.0f;
    merp_inv_branch_lengths(d, lp, 0.5f, 3, 1, 1.0f, l);
    for (int y = 0; y <= 10; y++)
        assert_float_equal(l[y], y < 3 ? 0.0f : 0.1f * (float)(y - 2), 1e-5f);
    /* A silhouette that shrinks with time still gives growing lengths, each
     * year at least l_min longer. */
    line(&d->g[MERP_G_S1], "G_s1", 0.9f, 0.9f);
    line(&d->g[MERP_G_S2], "G_s2", 0.05f, 0.05f);
    merp_inv_branch_lengths(d, lp, 0.5f, 1, 1, 1.0f, l);
    for (int y = 2; y <= 10; y++)
        assert_true(l[y] >= l[y - 1] + 0.1f - 1e-5f);
    assert_float_equal(l[1], lp[1] * (0.9f * 0.9f + 0.1f * 0.05f), 1e-5f);
    /* The trunk: h_max · G_h(t_y), floored the same way. */
    d->l_min = 0.5f;
    line(&d->g[MERP_G_H], "G_h", 0.0f, 1.0f);
    merp_inv_trunk_lengths(d, l);
    assert_float_equal(l[0], 0.5f, 1e-6f); /* l_{-1} = 0, so l_0 = l_min */
    assert_float_equal(l[1], 1.0f, 1e-6f);
    assert_float_equal(l[7], 7.0f, 1e-5f);
    d->l_min = 1.5f;
    merp_inv_trunk_lengths(d, l);
    for (int y = 1; y <= 10; y++)
        assert_float_equal(l[y] - l[y - 1], 1.5f, 1e-5f);
    free(d);
}

/* Eq (12): orders 2 and up divide by 0.5 · order + 1; s_b scales too. */
static void test_eq12_order_scaling(void **state)
{
    (void)state;
    assert_float_equal(merp_inv_order_scale(0), 1.0f, 0.0f);
    assert_float_equal(merp_inv_order_scale(1), 1.0f, 0.0f);
    assert_float_equal(merp_inv_order_scale(2), 0.5f, 0.0f);
    assert_float_equal(merp_inv_order_scale(3), 0.4f, 1e-7f);
    assert_float_equal(merp_inv_order_scale(4), 1.0f / 3.0f, 1e-7f);
    merp_inv_def *d = def_new();
    line(&d->g[MERP_G_S1], "G_s1", 0.3f, 0.3f);
    line(&d->g[MERP_G_S2], "G_s2", 0.3f, 0.3f);
    float lp[11], l1[11], l2[11], l3[11];
    for (int y = 0; y <= 10; y++)
        lp[y] = 2.0f * (float)y;
    merp_inv_branch_lengths(d, lp, 0.5f, 2, 1, 1.0f, l1);
    merp_inv_branch_lengths(d, lp, 0.5f, 2, 2, 1.0f, l2);
    merp_inv_branch_lengths(d, lp, 0.5f, 2, 3, 0.5f, l3);
    for (int y = 2; y <= 10; y++) {
        assert_float_equal(l2[y], 0.5f * l1[y], 1e-5f);
        assert_float_equal(l3[y], 0.5f * 0.4f * l1[y], 1e-5f);
    }
    free(d);
}

/* Eqs (8)–(9): s_θ = l_y / l_max blends G_o1 and G_o2; the heading turns the
 * original heading towards the parent (θ > 0) or away (θ < 0). */
static void test_eq8_9_heading(void **state)
{
    (void)state;
    assert_float_equal(merp_inv_s_theta(4.0f, 8.0f), 0.5f, 0.0f);
    assert_float_equal(merp_inv_s_theta(16.0f, 8.0f), 1.0f, 0.0f);
    assert_float_equal(merp_inv_s_theta(0.0f, 8.0f), 0.0f, 0.0f);
    merp_gfunc o1, o2;
    line(&o1, "G_o1", 0.2f, 0.2f);
    line(&o2, "G_o2", -0.4f, 0.6f); /* S curve: down at the base, up at the tip */
    assert_float_equal(merp_inv_heading(&o1, &o2, 0.5f, 0.0f, 90.0f), -9.0f, 1e-4f);
    assert_float_equal(merp_inv_heading(&o1, &o2, 1.0f, 0.0f, 90.0f), -36.0f, 1e-4f);
    assert_float_equal(merp_inv_heading(&o1, &o2, 1.0f, 1.0f, 90.0f), 54.0f, 1e-4f);
    assert_float_equal(merp_inv_heading(&o1, &o2, 0.0f, 0.7f, 90.0f), 18.0f, 1e-4f);
    merp_inv_def *d = def_new();
    assert_float_equal(merp_inv_branch_angle(d, 0.0f), 80.0f, 0.0f);
    assert_float_equal(merp_inv_branch_angle(d, 1.0f), 35.0f, 0.0f);
    assert_float_equal(merp_inv_branch_angle(d, 0.5f), 57.5f, 1e-5f);
    free(d);
    const float h0[3] = {1, 0, 0}, up[3] = {0, 1, 0};
    float out[3];
    merp_inv_orient(h0, up, 30.0f, out);
    assert_float_equal(out[0], cosf(0.5235988f), 1e-5f);
    assert_float_equal(out[1], 0.5f, 1e-5f);
    merp_inv_orient(h0, up, -30.0f, out);
    assert_float_equal(out[1], -0.5f, 1e-5f);
    merp_inv_orient(h0, up, 120.0f, out); /* never past the parent's direction */
    assert_float_equal(out[1], 1.0f, 1e-5f);
    merp_inv_orient(h0, up, -150.0f, out); /* nor past its opposite */
    assert_float_equal(out[1], -1.0f, 1e-5f);
}

/* Eqs (10), (13), (15): s_b = G_ss(x_s) · s_bp · G_bs(x_max). */
static void test_eq10_13_15_scale(void **state)
{
    (void)state;
    merp_gfunc bs, ss;
    line(&bs, "G_bs", 0.5f, 1.0f);
    line(&ss, "G_ss", 0.0f, 1.0f);
    assert_float_equal(merp_inv_scale(&bs, 0.5f, 1.0f, NULL, 0.0f), 0.75f, 1e-6f);
    assert_float_equal(merp_inv_scale(&bs, 0.5f, 0.4f, NULL, 0.0f), 0.3f, 1e-6f);
    assert_float_equal(merp_inv_scale(&bs, 0.5f, 0.4f, &ss, 0.5f), 0.15f, 1e-6f);
    line(&bs, "G_bs", -1.0f, -1.0f);
    assert_float_equal(merp_inv_scale(&bs, 0.5f, 1.0f, NULL, 0.0f), 0.0f, 0.0f);
}

/* Eq (11): a = G_a(s_b); a branch is shed at that age, so a smaller s_b sheds
 * sooner. */
static void test_eq11_sheds_at_its_age(void **state)
{
    (void)state;
    merp_gfunc ga;
    line(&ga, "G_a", 0.0f, 1.0f);
    float a = merp_inv_lifespan(&ga, 0.3f, 10.0f);
    assert_float_equal(a, 3.0f, 1e-5f);
    assert_true(merp_inv_alive_at(a, 5, 5.0));
    assert_true(merp_inv_alive_at(a, 5, 7.9));
    assert_false(merp_inv_alive_at(a, 5, 8.0));
    assert_false(merp_inv_alive_at(a, 5, 20.0));
    assert_true(merp_inv_lifespan(&ga, 0.2f, 10.0f) < merp_inv_lifespan(&ga, 0.8f, 10.0f));
    assert_float_equal(merp_inv_lifespan(&ga, 3.0f, 10.0f), 10.0f, 1e-5f); /* s_b clamped */
}

/* Eq (14): m = G_m(l_s / l_smax) metamers, at least one; leaves by G_l(x_s). */
static void test_eq14_metamers_and_leaves(void **state)
{
    (void)state;
    merp_gfunc gm, gl;
    line(&gm, "G_m", 0.0f, 1.0f);
    assert_int_equal(merp_inv_metamers(&gm, 0.6f, 1.2f, 10), 5);
    assert_int_equal(merp_inv_metamers(&gm, 0.001f, 1.2f, 10), 1);
    assert_int_equal(merp_inv_metamers(&gm, 5.0f, 1.2f, 10), 10);
    line(&gl, "G_l", 0.5f, 1.0f);
    assert_float_equal(merp_inv_leaf_size(&gl, 1.0f, 0.2f), 0.2f, 1e-6f);
    assert_float_equal(merp_inv_leaf_size(&gl, 0.0f, 0.2f), 0.1f, 1e-6f);
    assert_float_equal(merp_inv_x_s(0, 4), 0.25f, 0.0f);
    assert_float_equal(merp_inv_x_s(3, 4), 1.0f, 0.0f);
}

/* §4.1's radius: r_b = r_max · L / h_max, no more than the parent's radius,
 * shaped along the branch by G_r(x); a .fset without G_r gets a taper. */
static void test_radius_along_the_branch(void **state)
{
    (void)state;
    merp_inv_def *d = def_new();
    d->r_max = 0.3f;
    d->h_max = 20.0f;
    assert_float_equal(merp_inv_base_radius(d, 20.0f, -1.0f), 0.3f, 1e-6f);
    assert_float_equal(merp_inv_base_radius(d, 5.0f, -1.0f), 0.075f, 1e-6f);
    assert_float_equal(merp_inv_base_radius(d, 5.0f, 0.05f), 0.05f, 0.0f);
    assert_float_equal(merp_inv_base_radius(d, 5.0f, 0.5f), 0.075f, 1e-6f);
    merp_gfunc gr;
    line(&gr, "G_r", 1.0f, 0.2f);
    assert_float_equal(merp_inv_radius(&gr, 0.0f, 0.1f), 0.1f, 1e-6f);
    assert_float_equal(merp_inv_radius(&gr, 0.5f, 0.1f), 0.06f, 1e-6f);
    assert_float_equal(merp_inv_radius(&gr, 1.0f, 0.1f), 0.02f, 1e-6f);
    line(&gr, "G_r", 1.0f, -1.0f);
    assert_float_equal(merp_inv_radius(&gr, 1.0f, 0.1f), 0.0f, 0.0f);
    mer_error err;
    assert_int_equal(merp_inv_radius_default(&gr, &err), MER_OK);
    assert_float_equal(merp_gfunc_eval(&gr, 0.0f), 1.0f, 1e-5f);
    assert_true(merp_gfunc_eval(&gr, 1.0f) < merp_gfunc_eval(&gr, 0.5f));
    free(d);
}

/* 137.5° phyllotaxis and the 40° rule: a count is allowed when the last two
 * laterals sit at least 40° from the previous shoot's last; others move to the
 * nearest allowed count. */
static void test_forty_degree_rule(void **state)
{
    (void)state;
    assert_float_equal(merp_inv_angle_apart(10.0f, 350.0f), 20.0f, 1e-5f);
    assert_float_equal(merp_inv_angle_apart(137.5f * 5.0f, 0.0f), 32.5f, 1e-4f);
    for (uint32_t m = 1; m <= 40; m++) {
        float last = merp_inv_angle_apart(MERP_INV_DIVERGENCE * (float)m, 0.0f);
        float second = merp_inv_angle_apart(MERP_INV_DIVERGENCE * (float)(m - 1), 0.0f);
        int want = last >= 40.0f && (m == 1 || second >= 40.0f);
        assert_int_equal(merp_inv_count_ok(m), want);
    }
    assert_true(merp_inv_count_ok(4));
    assert_false(merp_inv_count_ok(5)); /* the last lateral only 32.5° away */
    assert_false(merp_inv_count_ok(6)); /* its second-longest is that one */
    assert_true(merp_inv_count_ok(7));
    assert_false(merp_inv_count_ok(8)); /* 20° */
    assert_int_equal(merp_inv_phyllo_count(4, 16), 4);
    assert_int_equal(merp_inv_phyllo_count(5, 16), 4);
    assert_int_equal(merp_inv_phyllo_count(6, 16), 7);
    assert_int_equal(merp_inv_phyllo_count(9, 16), 10);
    assert_int_equal(merp_inv_phyllo_count(6, 6), 4); /* 7 is past m_max */
    for (uint32_t m = 1; m <= 30; m++)
        assert_true(merp_inv_count_ok(merp_inv_phyllo_count(m, 30)));
}

/* Continuous development: metamers start one after another and grow by the
 * curve over 1 − span of the year; all are whole at the year's end. */
static void test_development_offsets(void **state)
{
    (void)state;
    merp_gfunc g;
    line(&g, "G_e", 0.0f, 1.0f);
    assert_float_equal(merp_inv_metamer_start(0, 4, 0.5f), 0.0f, 0.0f);
    assert_float_equal(merp_inv_metamer_start(2, 4, 0.5f), 0.25f, 0.0f);
    assert_float_equal(merp_inv_growth(&g, 0.5f, 0, 4, 0.5f), 1.0f, 0.0f);
    assert_float_equal(merp_inv_growth(&g, 0.5f, 2, 4, 0.5f), 0.5f, 1e-6f);
    assert_float_equal(merp_inv_growth(&g, 0.5f, 3, 4, 0.5f), 0.25f, 1e-6f);
    assert_float_equal(merp_inv_growth(&g, 0.1f, 3, 4, 0.5f), 0.0f, 0.0f);
    for (uint32_t j = 0; j < 4; j++) {
        assert_float_equal(merp_inv_growth(&g, 1.0f, j, 4, 0.5f), 1.0f, 0.0f);
        assert_float_equal(merp_inv_growth(&g, 0.0f, j, 4, 0.5f), 0.0f, 0.0f);
    }
    /* Each metamer's growth never decreases in time, and a lower one is ahead. */
    for (int i = 1; i <= 100; i++) {
        float f0 = (float)(i - 1) / 100.0f, f1 = (float)i / 100.0f;
        for (uint32_t j = 0; j < 4; j++) {
            assert_true(merp_inv_growth(&g, f1, j, 4, 0.5f) >=
                        merp_inv_growth(&g, f0, j, 4, 0.5f));
            if (j > 0)
                assert_true(merp_inv_growth(&g, f1, j - 1, 4, 0.5f) >=
                            merp_inv_growth(&g, f1, j, 4, 0.5f));
        }
    }
}

/* A definition names its functions after their roles, and its scalars are
 * checked; the Populus definition passes. */
static void test_definition_checks(void **state)
{
    (void)state;
    merp_inv_def *d = def_new();
    mer_error err;
    assert_int_equal(merp_inv_def_check(d, &err), MER_OK);
    d->y_max = 0;
    assert_int_equal(merp_inv_def_check(d, &err), MER_ERR_INVALID);
    assert_string_equal(err.field, "y_max");
    d->y_max = 10;
    d->span = 1.0f;
    assert_int_equal(merp_inv_def_check(d, &err), MER_ERR_INVALID);
    assert_string_equal(err.field, "span");
    d->span = 0.5f;
    strcpy(d->g[MERP_G_S2].name, "G_s3");
    assert_int_equal(merp_inv_def_check(d, &err), MER_ERR_INVALID);
    assert_non_null(strstr(err.message, "G_s2"));
    assert_int_equal(merp_inv_populus(d, &err), MER_OK);
    assert_int_equal(d->y_max, 27);
    /* The preset's own text: every function, by name; a missing one is named. */
    const char *text = merp_inv_populus_fset;
    const char *cut = strstr(text, "fver 1 1\nname: G_bg");
    assert_non_null(cut);
    char *shorter = strdup(text);
    memcpy(strstr(shorter, "items: 14"), "items: 12", 9);
    shorter[cut - text] = '\0';
    assert_int_equal(merp_inv_def_functions(d, shorter, strlen(shorter), &err), MER_ERR_INVALID);
    assert_non_null(strstr(err.message, "G_bg is missing"));
    free(shorter);
    /* A text from before G_r (§4.1's radius) reads, with the default taper. */
    shorter = strdup(text);
    memcpy(strstr(shorter, "items: 14"), "items: 13", 9);
    shorter[strstr(text, "fver 1 1\nname: G_r") - text] = '\0';
    assert_int_equal(merp_inv_def_functions(d, shorter, strlen(shorter), &err), MER_OK);
    merp_gfunc taper;
    assert_int_equal(merp_inv_radius_default(&taper, &err), MER_OK);
    assert_true(merp_gfunc_equal(&d->g[MERP_G_R], &taper));
    free(shorter);
    /* Written out and read back, the preset's functions are the same. */
    assert_int_equal(merp_inv_populus(d, &err), MER_OK);
    size_t need = merp_fset_write(d->g, MERP_G_COUNT, NULL, 0);
    char *text2 = malloc(need + 1);
    merp_fset_write(d->g, MERP_G_COUNT, text2, need + 1);
    merp_inv_def *e = def_new();
    assert_int_equal(merp_inv_def_functions(e, text2, need, &err), MER_OK);
    for (uint32_t i = 0; i < MERP_G_COUNT; i++)
        assert_true(merp_gfunc_equal(&d->g[i], &e->g[i]));
    free(text2);
    free(e);
    free(d);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_eq6_silhouette),
        cmocka_unit_test(test_eq7_enforces_l_min),
        cmocka_unit_test(test_eq12_order_scaling),
        cmocka_unit_test(test_eq8_9_heading),
        cmocka_unit_test(test_eq10_13_15_scale),
        cmocka_unit_test(test_eq11_sheds_at_its_age),
        cmocka_unit_test(test_eq14_metamers_and_leaves),
        cmocka_unit_test(test_radius_along_the_branch),
        cmocka_unit_test(test_forty_degree_rule),
        cmocka_unit_test(test_development_offsets),
        cmocka_unit_test(test_definition_checks),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
