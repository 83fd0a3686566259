/* Unit tests for the P09 model (lib/models/p09/): a scene step by step,
 * hand-computed where the numbers are small enough; phyllotaxis, fate, schedules,
 * tropism. The worked seedling: shadow propagation with a = 0.2 (set here; the
 * default is 0.1), C = 1; its two buds share voxel (50, 1, 50), so each has
 * s = 0.4 and Q = 1 − 0.4 + 0.2 = 0.8; v_base = α·ΣQ = 2·1.6 = 3.2. */
#include "config.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include <meristem/edit.h>
#include <meristem/presets.h>
#include <meristem/scene.h>

#include "scene_helpers.h"

/* BH: 3.2 splits 1.6 / 1.6 (λ = 0.5, equal Q): one metamer each, l = 1.6. */
static void test_first_step_by_hand(void **state)
{
    (void)state;
    mer_params p = worked();
    p.xi = 0.0f;
    mer_scene *s = make(&p, 0);
    step(s, 1);
    assert_int_equal(mer_scene_node_bound(s), 3);
    mer_node r = node(s, 0), t = node(s, 1), l = node(s, 2);
    assert_int_equal(r.main_child, 1);
    assert_int_equal(r.lateral_child[0], 2);
    assert_int_equal(r.terminal_bud, MER_BUD_NONE);
    assert_int_equal(r.lateral_bud[0], MER_BUD_NONE);
    assert_close(r.q, 1.6f);
    assert_int_equal(t.parent, 0);
    assert_int_equal(t.order, 0);
    assert_close(t.length, 1.6f);
    assert_close(t.base[1], 1.0f);
    assert_close(t.dir[1], 1.0f);   /* unshaded: V points on, up */
    assert_int_equal(t.terminal_bud, MER_BUD_DORMANT);
    assert_int_equal(t.lateral_bud[0], MER_BUD_DORMANT);
    assert_int_equal(l.order, 1);
    assert_close(l.length, 1.6f);
    /* Lateral (ξ = 0 here): bud dir b = cos 45°·up + sin 45°·side, where side is the
     * seedling's (random) horizontal side vector; d = b + 0.05·up
     * = 0.7071·side + 0.7571·up, normalized 0.68257·side + 0.73083·up. */
    float side[2] = {r.bud_dir[0][0] / 0.70710678f, r.bud_dir[0][2] / 0.70710678f};
    assert_close(side[0] * side[0] + side[1] * side[1], 1.0f);
    assert_close(r.bud_dir[0][1], 0.70710678f);
    assert_near(l.dir[0], 0.68257f * side[0], 1e-4f);
    assert_near(l.dir[1], 0.73083f, 1e-4f);
    assert_near(l.dir[2], 0.68257f * side[1], 1e-4f);
    /* Pipe model: tips have d_leaf; below, d = (2·0.05^2.5)^(1/2.5) = 0.065975. */
    assert_close(t.diameter, 0.05f);
    assert_close(l.diameter, 0.05f);
    assert_close(r.diameter, 0.0659754f);
    mer_summary m;
    mer_scene_summary(s, &m);
    assert_int_equal(m.step, 1);
    assert_int_equal(m.internodes, 3);
    assert_int_equal(m.buds, 4);
    assert_close(m.height, 2.6f);
    assert_close(m.crown_base, 1.0f);
    assert_close(m.crown_depth, 1.6f);
    mer_scene_free(s);
}

static float azimuth(const float *v)
{
    return atan2f(v[2], v[0]);
}

static float wrap(float a)
{
    while (a < 0.0f)
        a += 6.2831853f;
    while (a >= 6.2831853f)
        a -= 6.2831853f;
    return a;
}

/* λ = 1 sends everything up the main axis; ξ = η = 0 keeps it straight. */
static void test_phyllotaxis_spiral(void **state)
{
    (void)state;
    mer_params p = worked();
    p.lambda = 1.0f;
    p.xi = 0.0f;
    p.eta = 0.0f;
    mer_scene *s = make(&p, 0);
    step(s, 4);
    uint32_t prev = 0, count = 0;
    for (uint32_t id = node(s, 0).main_child; id != MER_NO_NODE; id = node(s, id).main_child) {
        mer_node a = node(s, prev), b = node(s, id);
        assert_int_equal(b.order, 0);
        assert_close(b.dir[1], 1.0f);
        /* each lateral bud at the branch angle (45°) from its internode */
        assert_close(b.bud_dir[0][0] * b.dir[0] + b.bud_dir[0][1] * b.dir[1] + b.bud_dir[0][2] * b.dir[2],
                     0.70710678f);
        /* consecutive buds turn by the divergence angle, 137.5°, about the axis */
        float turn = wrap(azimuth(b.bud_dir[0]) - azimuth(a.bud_dir[0]));
        float want = wrap(137.5f * 0.017453292f);
        assert_true(fabsf(turn - want) < 1e-3f || fabsf(turn - (6.2831853f - want)) < 1e-3f);
        prev = id;
        count++;
    }
    assert_true(count >= 4);
    mer_scene_free(s);
}

static void test_phyllotaxis_decussate(void **state)
{
    (void)state;
    mer_params p = worked();
    p.lambda = 1.0f;
    p.xi = 0.0f;
    p.eta = 0.0f;
    p.buds_per_node = 2;
    p.divergence = 90.0f;
    mer_scene *s = make(&p, 0);
    mer_node r = node(s, 0);
    assert_int_equal(r.lateral_bud[1], MER_BUD_DORMANT);
    step(s, 3);
    uint32_t prev = 0, count = 0;
    for (uint32_t id = node(s, 0).main_child; id != MER_NO_NODE; id = node(s, id).main_child) {
        mer_node a = node(s, prev), b = node(s, id);
        /* the pair is opposite */
        float opp = wrap(azimuth(b.bud_dir[1]) - azimuth(b.bud_dir[0]));
        assert_near(opp, 3.14159265f, 1e-3f);
        /* successive pairs cross at 90° */
        float turn = wrap(azimuth(b.bud_dir[0]) - azimuth(a.bud_dir[0]));
        assert_true(fabsf(turn - 1.5707963f) < 1e-3f || fabsf(turn - 4.712389f) < 1e-3f);
        prev = id;
        count++;
    }
    assert_true(count >= 3);
    mer_scene_free(s);
}

/* Priority model, seedling: items (lateral bud, terminal bud), both Q = 0.8.
 * With apical control the terminal is first: weights (1, w_min = 0.006), so it gets
 * 3.2·0.8/(0.8 + 0.0048) = 3.1809: n = 3, l = 1.0603; the lateral gets 0.019.
 * Without, the tie goes to the lateral (listed first), which gets the 3.1809. */
static void test_priority_apical_control_schedule(void **state)
{
    (void)state;
    mer_params p = worked();
    p.fate = MER_FATE_PRIORITY;
    mer_scene *s = make(&p, 0);
    step(s, 1);
    assert_int_equal(mer_scene_node_bound(s), 4);
    for (uint32_t id = 1; id < 4; id++) {
        assert_int_equal(node(s, id).order, 0);
        assert_close(node(s, id).length, 1.06030f);
    }
    assert_int_equal(node(s, 0).lateral_bud[0], MER_BUD_DORMANT);
    mer_scene_free(s);

    p.schedule.apical_off[0] = 0; /* removed from the start */
    s = make(&p, 0);
    step(s, 1);
    assert_int_equal(mer_scene_node_bound(s), 4);
    assert_int_equal(node(s, 0).terminal_bud, MER_BUD_DORMANT);
    for (uint32_t id = 1; id < 4; id++)
        assert_int_equal(node(s, id).order, 1);
    mer_scene_free(s);

    /* Removed at step 2: identical to "never" for steps 0 and 1, different after. */
    mer_params never = worked();
    never.fate = MER_FATE_PRIORITY;
    mer_params at2 = never;
    at2.schedule.apical_off[0] = 2;
    mer_scene *a = make(&never, 0), *b = make(&at2, 0);
    step(a, 2);
    step(b, 2);
    assert_true(mer_scene_hash(a) == mer_scene_hash(b));
    step(a, 1);
    step(b, 1);
    assert_true(mer_scene_hash(a) != mer_scene_hash(b));
    mer_scene_free(a);
    mer_scene_free(b);
}

static void test_sympodial_terminals_flower(void **state)
{
    (void)state;
    mer_params p = worked();
    p.sympodial = 1;
    mer_scene *s = make(&p, 0);
    step(s, 1);
    assert_int_equal(node(s, 1).terminal_bud, MER_BUD_FLOWER);
    assert_int_equal(node(s, 2).terminal_bud, MER_BUD_FLOWER);
    mer_summary m;
    mer_scene_summary(s, &m);
    assert_int_equal(m.flowers, 2);
    step(s, 4);
    assert_int_equal(node(s, 1).main_child, MER_NO_NODE); /* the axis never continues */
    assert_true(mer_scene_node_bound(s) > 5);              /* laterals took over */
    mer_scene_free(s);
    p.sympodial_abort = 1;
    s = make(&p, 0);
    step(s, 1);
    assert_int_equal(node(s, 1).terminal_bud, MER_BUD_ABORTED);
    mer_scene_free(s);
}

/* Sylleptic: after the first round (nodes 1, 2), the lateral buds made in this
 * step compete alone: each sits in a voxel with one other bud, Q = 0.8, so 1.6
 * reaches each and grows one metamer in the same step. */
static void test_sylleptic_vs_proleptic(void **state)
{
    (void)state;
    mer_params p = worked();
    p.sylleptic = 1;
    mer_scene *s = make(&p, 0);
    step(s, 1);
    /* precondition of the hand computation: the two shoot ends lie in different voxels */
    mer_node e1 = node(s, 1), e2 = node(s, 2);
    float x1 = e1.base[0] + e1.dir[0] * e1.length, z1 = e1.base[2] + e1.dir[2] * e1.length;
    float x2 = e2.base[0] + e2.dir[0] * e2.length, z2 = e2.base[2] + e2.dir[2] * e2.length;
    assert_true(floorf(x1) != floorf(x2) || floorf(z1) != floorf(z2));
    assert_int_equal(mer_scene_node_bound(s), 5);
    mer_node a = node(s, 3), b = node(s, 4);
    assert_int_equal(a.parent, 1);
    assert_int_equal(a.order, 1);
    assert_int_equal(a.born, 0);
    assert_int_equal(b.parent, 2);
    assert_int_equal(b.order, 2);
    assert_int_equal(node(s, 1).terminal_bud, MER_BUD_DORMANT); /* terminals wait */
    mer_scene_free(s);
    s = make(NULL, 0);
    step(s, 1);
    assert_int_equal(mer_scene_node_bound(s), 3); /* proleptic: the new buds rest */
    mer_scene_free(s);
}

/* η scaled by order: order-1 shoots droop while the trunk rises. */
static void test_tropism_by_order(void **state)
{
    (void)state;
    mer_params p = worked();
    p.xi = 0.0f;
    p.eta = 0.5f;
    p.schedule.eta_order_scale[1] = -2.0f; /* η = -1 on first-order branches */
    mer_scene *s = make(&p, 0);
    step(s, 3);
    int up = 0, down = 0;
    for (uint32_t i = 1; i < mer_scene_node_bound(s); i++) {
        mer_node n = node(s, i);
        if (n.order == 0)
            up += n.dir[1] > 0.99f;
        if (n.order == 1 && n.parent != MER_NO_NODE && node(s, n.parent).order == 1)
            down += n.dir[1] < node(s, n.parent).dir[1]; /* each metamer bends further down */
    }
    assert_true(up > 0);
    assert_true(down > 0);
    for (uint32_t i = 1; i < mer_scene_node_bound(s); i++)
        if (node(s, i).order == 0)
            assert_true(node(s, i).dir[1] > 0.99f);
    mer_scene_free(s);
}

/* Plants share the shadow grid: a close neighbour leaves a plant less light, so
 * it grows less than alone. */
static void test_plants_compete(void **state)
{
    (void)state;
    mer_params p = mer_params_default();
    mer_scene *alone = make(&p, 2);
    p.seedlings = 2;
    p.seedling_spacing = 4.0f;
    mer_scene *pair = make(&p, 2);
    step(alone, 12);
    step(pair, 12);
    uint32_t n_alone = 0, n_pair0 = 0;
    for (uint32_t i = 0; i < mer_scene_node_bound(alone); i++)
        n_alone += node(alone, i).alive;
    for (uint32_t i = 0; i < mer_scene_node_bound(pair); i++)
        n_pair0 += node(pair, i).alive && node(pair, i).plant == 0;
    assert_true(n_pair0 > 10);
    assert_true(n_pair0 < n_alone);
    mer_scene_free(alone);
    mer_scene_free(pair);
}

/* The schedule alone can be replaced between steps; a bad one changes nothing. */
static void test_set_schedule(void **state)
{
    (void)state;
    mer_params p = mer_params_default();
    p.fate = MER_FATE_PRIORITY;
    mer_scene *a = make(&p, 0), *b = make(&p, 0);
    step(a, 2);
    step(b, 2);
    mer_schedule sch = mer_scene_params(b)->schedule;
    sch.apical_off[0] = 2; /* remove apical control on the trunk now */
    mer_error err;
    assert_int_equal(mer_scene_set_schedule(b, &sch, &err), MER_OK);
    assert_int_equal(mer_scene_params(b)->schedule.apical_off[0], 2);
    step(a, 1);
    step(b, 1);
    assert_true(mer_scene_hash(a) != mer_scene_hash(b));
    sch.eta_key_count = 2;
    sch.eta_keys[0] = (mer_keyframe){5.0f, 0.1f};
    sch.eta_keys[1] = (mer_keyframe){5.0f, 0.2f}; /* steps must increase */
    assert_int_equal(mer_scene_set_schedule(b, &sch, &err), MER_ERR_RANGE);
    assert_string_equal(err.field, "schedule.eta_keys");
    assert_int_equal(mer_scene_params(b)->schedule.eta_key_count, 0);
    mer_scene_free(a);
    mer_scene_free(b);
}

/* The gradient variant of V grows a tree too, and differently. */
static void test_gradient_direction_mode(void **state)
{
    (void)state;
    mer_params p = mer_params_default();
    mer_scene *a = make(&p, 0);
    p.shadow_dir = MER_SHADOW_DIR_GRADIENT;
    mer_scene *b = make(&p, 0);
    step(a, 10);
    step(b, 10);
    assert_true(mer_scene_node_bound(b) > 100);
    assert_true(mer_scene_hash(a) != mer_scene_hash(b));
    mer_scene_free(a);
    mer_scene_free(b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_first_step_by_hand),
        cmocka_unit_test(test_phyllotaxis_spiral),
        cmocka_unit_test(test_phyllotaxis_decussate),
        cmocka_unit_test(test_priority_apical_control_schedule),
        cmocka_unit_test(test_sympodial_terminals_flower),
        cmocka_unit_test(test_sylleptic_vs_proleptic),
        cmocka_unit_test(test_tropism_by_order),
        cmocka_unit_test(test_plants_compete),
        cmocka_unit_test(test_set_schedule),
        cmocka_unit_test(test_gradient_direction_mode),
    };
    return cmocka_run_group_tests_name("p09", tests, NULL, NULL);
}
