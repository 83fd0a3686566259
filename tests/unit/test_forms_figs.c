/* The paper's other figures of form as measured trends (P09 §4.2–§4.3, Figs. 6, 11,
 * 12, 13), over 8 seeds each, with the measures of forms.h. */
#include "config.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <meristem/presets.h>
#include <meristem/scene.h>

#include "forms.h"
#include "scene_helpers.h"

#define SEEDS 8

typedef struct form {
    float margin_max;  /* the highest leader margin over the seeds */
    float margin_min;  /* the lowest */
    float margin;      /* the mean */
    int lost;          /* seeds whose leader a lateral has overtopped (margin < 0) */
    float slenderness; /* mean height / width */
    float width;       /* mean crown width */
    float height;      /* mean height */
    float internodes;  /* mean internodes */
    float gnarl;       /* mean angle between consecutive internodes of an axis */
    float dir_y;       /* mean vertical direction of the internodes made from `from` */
    float dir_y_max;   /* its highest value over the seeds */
} form;

static form measure(const char *preset, uint32_t steps, uint32_t from)
{
    mer_params p;
    assert_int_equal(mer_preset_params(preset, &p, NULL), MER_OK);
    form f = {-1.0f, 1.0f, 0.0f, 0, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, -1.0f};
    for (uint64_t seed = 1; seed <= SEEDS; seed++) {
        mer_scene *s = new_scene(&p, seed);
        step(s, steps);
        mer_summary m;
        mer_scene_summary(s, &m);
        float margin = form_leader_margin(s), dy = form_new_dir_y(s, from);
        f.margin_max = margin > f.margin_max ? margin : f.margin_max;
        f.margin_min = margin < f.margin_min ? margin : f.margin_min;
        f.margin += margin / SEEDS;
        f.lost += margin < 0.0f;
        f.slenderness += form_slenderness(s) / SEEDS;
        f.width += m.crown_width / SEEDS;
        f.height += m.height / SEEDS;
        f.internodes += (float)m.internodes / SEEDS;
        f.gnarl += form_gnarl(s) / SEEDS;
        f.dir_y += dy / SEEDS;
        f.dir_y_max = dy > f.dir_y_max ? dy : f.dir_y_max;
        mer_scene_free(s);
    }
    print_message("%s after %u steps: %.0f internodes, leader margin %.3f to %.3f (mean %.3f, lost in %d), "
                  "height/width %.2f, height %.1f, width %.1f, gnarl %.1f°, direction y since step %u %.3f (highest %.3f)\n",
                  preset, steps, (double)f.internodes, (double)f.margin_min, (double)f.margin_max,
                  (double)f.margin, f.lost, (double)f.slenderness, (double)f.height, (double)f.width, (double)f.gnarl, from,
                  (double)f.dir_y, (double)f.dir_y_max);
    return f;
}

/* Fig. 6: sylleptic development, and proleptic development with sympodial branching,
 * make decurrent shrubs: after 12 steps every seed has lost its leader (a lateral
 * tip above the trunk's) and the crown is lower for its width than the default
 * tree's (measured 0.70 and 0.71 against 0.82; margins at most -0.75 and -0.84).
 * The code before issue 19's calibration already reproduced this figure, with the
 * same measures to the digit (the calibration did not touch these presets): the
 * test guards the form, it does not mark a fix. */
static void test_fig6_shrubs_are_decurrent(void **state)
{
    (void)state;
    form def = measure("default", 12, 0);
    form syl = measure("fig6-sylleptic", 12, 0);
    form sym = measure("fig6-sympodial", 12, 0);
    assert_true(def.margin_min > 0.0f);
    assert_true(syl.margin_max < -0.3f);
    assert_true(sym.margin_max < -0.3f);
    assert_true(syl.slenderness < def.slenderness - 0.05f);
    assert_true(sym.slenderness < def.slenderness - 0.05f);
}

/* Fig. 11: apical control everywhere until step 25, then removed: the young tree is
 * excurrent (its leader leads in every seed at step 25) and the old one decurrent,
 * lower for its width (measured 1.20 at step 25, 1.00 at step 50). The young tree's
 * claim discriminates: before the Table 1 calibration (shoots of up to 16 metamers a
 * season) it had lost its leader by step 25 in every seed (margin -0.67, height/width
 * 0.76). The old tree is less decurrent than the figure's last frame: at step 50 a
 * lateral has overtopped the leader in 4 seeds of 8 only. */
static void test_fig11_excurrent_young_decurrent_old(void **state)
{
    (void)state;
    form young = measure("fig11-animation", 25, 0);
    form old = measure("fig11-animation", 50, 0);
    assert_true(young.margin_min > 0.0f);
    assert_true(old.margin_min < 0.0f);
    assert_true(old.slenderness < young.slenderness - 0.15f);
}

/* Fig. 12 (P09 §4.3): downward tropism (b) spreads the branches more widely than
 * upward tropism (a); "a strong downward tropism combined with a strong tendency to
 * grow towards light results in decurrent forms with highly gnarled branches (Fig.
 * 12c, d)". The four trees wander alike (lib/presets.c): a and b keep their leader
 * in every seed, while in c and d the upright leader arches over and a lateral
 * overtops it (leader margin below 0 in every seed), the crowns lower
 * for their width. The figure draws the four trees alike in size: d, whose leader
 * arches over soonest, still grows as tall as c and as many internodes as a. Measured
 * after 20 steps (a, b, c, d): height/width 0.86, 0.72, 0.74, 0.60; height 37.0,
 * 36.8, 26.9, 27.4; internodes 8,500, 11,700, 5,300, 8,600; gnarl 3.1°, 4.0°, 9.4°,
 * 9.4°; mean leader margin 0.012, 0.017, -0.107, -0.324. With η = -0.5 d was a low
 * mound (height 15, height/width 0.41, 3,800 internodes): the size test fails there.
 * Before the wandering the leaders of c and d stayed exactly vertical and led
 * in every seed (margins 0.025 and 0.032 at the least): the leader test fails there.
 * The spread of b against a and the gnarl of c and d held already then. */
static void test_fig12_tropism(void **state)
{
    (void)state;
    form a = measure("fig12a", 20, 0);
    form b = measure("fig12b", 20, 0);
    form c = measure("fig12c", 20, 0);
    form d = measure("fig12d", 20, 0);
    assert_true(b.slenderness < a.slenderness - 0.08f);
    assert_true(b.width > a.width + 4.0f);
    assert_true(b.dir_y < a.dir_y - 0.2f);
    float straight = a.gnarl > b.gnarl ? a.gnarl : b.gnarl;
    assert_true(c.gnarl > 2.0f * straight);
    assert_true(d.gnarl > 2.0f * straight);
    assert_true(c.dir_y_max < 0.0f);
    assert_true(d.dir_y_max < 0.0f);
    /* Decurrent c and d, excurrent a and b. */
    assert_true(a.margin_min > 0.0f);
    assert_true(b.margin_min > 0.0f);
    assert_true(c.margin < -0.05f);
    assert_true(d.margin < -0.05f);
    assert_true(c.margin_max < 0.0f);
    assert_true(d.margin_max < 0.0f);
    assert_true(c.slenderness < a.slenderness - 0.08f);
    assert_true(d.slenderness < a.slenderness - 0.2f);
    /* d at the figure's size. */
    assert_true(d.height > 0.65f * a.height);
    assert_true(d.height > 0.9f * c.height);
    assert_true(d.internodes > 0.75f * a.internodes);
}

/* Fig. 13: downward tropism raised near the end of the simulation (η from 0.05 at
 * step 18 to -1 at step 22): what grows from step 22 on droops in every seed
 * (measured -0.69 against 0.6 for the default tree), and the tree stays inside its
 * grid (100 wide). */
static void test_fig13_late_tropism_droops(void **state)
{
    (void)state;
    form def = measure("default", 26, 22);
    form late = measure("fig13-tropism-late", 26, 22);
    assert_true(def.dir_y > 0.4f);
    assert_true(late.dir_y_max < 0.0f);
    assert_true(late.dir_y < -0.4f);
    assert_true(late.width < 80.0f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fig6_shrubs_are_decurrent),
        cmocka_unit_test(test_fig11_excurrent_young_decurrent_old),
        cmocka_unit_test(test_fig12_tropism),
        cmocka_unit_test(test_fig13_late_tropism_droops),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
