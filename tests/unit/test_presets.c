/* Unit tests for lib/presets.c and the paper's qualitative claims, on many seeds.
 *
 * Excurrence, the measure used here: the leader's reach, i.e. the height of the
 * highest point of the trunk (the order-0 axis) above the base, divided by the
 * tree's height. 1 means the leader is the top of the tree (excurrent, a
 * conspicuous trunk); small values mean lateral limbs have overtopped it
 * (decurrent). P09 Fig. 7 claims the tree becomes more excurrent as λ rises.
 *
 * Bole: the height of the lowest living lateral branch (mer_summary.crown_base).
 * P09 §4.4 / Fig. 14 claim shedding raises it. */
#include "config.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include <meristem/edit.h>
#include <meristem/presets.h>
#include <meristem/scene.h>

#define SEEDS 8
#define BOLE_STEPS 40 /* the steps of the Fig. 14 bole tree (test_shedding_...) */

static mer_scene *grow(const mer_params *p, uint64_t seed, uint32_t steps)
{
    mer_scene *s = NULL;
    mer_error err;
    if (mer_scene_new(p, seed, &s, &err) != MER_OK)
        fail_msg("new: %s", err.message);
    if (mer_scene_step(s, steps, NULL, NULL, NULL, NULL, &err) != MER_OK)
        fail_msg("step: %s", err.message);
    return s;
}

static double leader_reach(const mer_scene *s)
{
    mer_summary m;
    mer_scene_summary(s, &m);
    double top = 0.0, base = 0.0;
    for (uint32_t i = 0; i < mer_scene_node_bound(s); i++) {
        mer_node n;
        mer_scene_node(s, i, &n, NULL);
        if (i == 0)
            base = n.base[1];
        if (!n.alive || n.order != 0 || n.plant != 0)
            continue;
        double y = (double)n.base[1] + (double)n.dir[1] * (double)n.length;
        if (y > top)
            top = y;
    }
    return m.height > 0.0f ? (top - base) / (double)m.height : 0.0;
}

static void test_every_preset_grows(void **state)
{
    (void)state;
    assert_true(mer_preset_count() >= 20);
    for (size_t i = 0; i < mer_preset_count(); i++) {
        const char *name = mer_preset_name(i);
        assert_non_null(mer_preset_description(i));
        mer_params p;
        assert_int_equal(mer_preset_params(name, &p, NULL), MER_OK);
        assert_int_equal(mer_params_validate(&p, NULL), MER_OK);
        /* the bole tree's crown forms late: give it the steps of the bole test */
        mer_scene *s = grow(&p, 1, strcmp(name, "fig14-tall-bole") == 0 ? BOLE_STEPS : 20);
        if (strcmp(name, "fig15-brushed") == 0) {
            /* the sketched stem, then two heavy dabs for the crown (Fig. 15c, d) */
            mer_brush dab = {{0, 15, 0}, 6.0f, 1.0f, 400};
            assert_int_equal(mer_scene_brush(s, &dab, NULL, NULL, NULL), MER_OK);
            dab.center[1] = 20.0f;
            assert_int_equal(mer_scene_brush(s, &dab, NULL, NULL, NULL), MER_OK);
            assert_int_equal(mer_scene_step(s, 15, NULL, NULL, NULL, NULL, NULL), MER_OK);
        }
        mer_summary m;
        mer_scene_summary(s, &m);
        print_message("# %s: %u internodes, height %.1f, width %.1f\n", name, m.internodes,
                      (double)m.height, (double)m.crown_width);
        if (m.internodes < 60 || m.height < 5.0f || m.crown_width < 2.0f)
            fail_msg("preset %s: %u internodes, height %g, width %g", name, m.internodes,
                     (double)m.height, (double)m.crown_width);
        mer_scene_free(s);
    }
    mer_params p;
    mer_error err;
    assert_int_equal(mer_preset_params("fig99", &p, &err), MER_ERR_INVALID);
    assert_string_equal(err.field, "preset");
    assert_null(mer_preset_name(mer_preset_count()));
}

static void test_fig7_lambda_makes_trees_more_excurrent(void **state)
{
    (void)state;
    static const char *const names[5] = {"fig7-bh-0.46", "fig7-bh-0.48", "fig7-bh-0.50",
                                         "fig7-bh-0.52", "fig7-bh-0.54"};
    double mean[5];
    for (int k = 0; k < 5; k++) {
        mer_params p;
        assert_int_equal(mer_preset_params(names[k], &p, NULL), MER_OK);
        double sum = 0.0;
        for (uint64_t seed = 0; seed < SEEDS; seed++) {
            mer_scene *s = grow(&p, seed, 20);
            sum += leader_reach(s);
            mer_scene_free(s);
        }
        mean[k] = sum / SEEDS;
        print_message("# %s: leader reach %.3f\n", names[k], mean[k]);
    }
    for (int k = 1; k < 5; k++)
        assert_true(mean[k] >= mean[k - 1] - 0.02);
    assert_true(mean[4] - mean[0] > 0.4);
    assert_true(mean[4] > 0.9);
}

/* P09 §4.4, Fig. 14: shedding raises a tall bole under a vigorous crown. Per seed, the
 * tree must be vigorous (a whip of a few hundred internodes fails) and its lowest
 * living lateral branch must stand at 30% of its height or more; and without shedding
 * the same trees keep branches near the ground. */
#define BOLE_MIN_INTERNODES 2000

static void test_shedding_raises_the_lowest_branch(void **state)
{
    (void)state;
    mer_params with;
    assert_int_equal(mer_preset_params("fig14-tall-bole", &with, NULL), MER_OK);
    mer_params without = with;
    without.shed_threshold = 0.0f;
    double sum_with = 0.0, sum_without = 0.0;
    int raised = 0, boles = 0;
    for (uint64_t seed = 0; seed < SEEDS; seed++) {
        mer_scene *a = grow(&with, seed, BOLE_STEPS), *b = grow(&without, seed, BOLE_STEPS);
        mer_summary ma, mb;
        mer_scene_summary(a, &ma);
        mer_scene_summary(b, &mb);
        int bole = ma.internodes >= BOLE_MIN_INTERNODES && ma.crown_base >= 0.3f * ma.height;
        print_message("# seed %u: %u internodes, height %.1f, lowest branch %.1f (%.2f)%s\n",
                      (unsigned)seed, ma.internodes, (double)ma.height, (double)ma.crown_base,
                      (double)(ma.crown_base / ma.height), bole ? "" : "  no bole");
        sum_with += (double)ma.crown_base;
        sum_without += (double)mb.crown_base;
        raised += ma.crown_base > mb.crown_base + 1.0f;
        boles += bole;
        mer_scene_free(a);
        mer_scene_free(b);
    }
    print_message("# lowest branch: %.2f with shedding, %.2f without; raised in %d of %d; "
                  "vigorous with a bole in %d\n",
                  sum_with / SEEDS, sum_without / SEEDS, raised, SEEDS, boles);
    assert_true(sum_with / SEEDS > sum_without / SEEDS + 5.0);
    assert_true(raised >= SEEDS - 2);
    assert_true(boles >= SEEDS - 2);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_preset_grows),
        cmocka_unit_test(test_fig7_lambda_makes_trees_more_excurrent),
        cmocka_unit_test(test_shedding_raises_the_lowest_branch),
    };
    return cmocka_run_group_tests_name("presets", tests, NULL, NULL);
}
