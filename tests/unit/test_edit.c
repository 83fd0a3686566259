/* Unit tests for edits of the skeleton (lib/edit.c, brush.c, symmetry.c,
 * skeleton/pipe.c): prune and the pipe model's memory, brush and symmetry, the
 * growth constraint, bend, and the shadow grid kept in step with the buds. */
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
#include "scene_private.h" /* for the shadow-grid consistency check */

/* Pipe model memory: prune the lateral branch, stop growth, and the base keeps
 * its 0.065975 although its only remaining tip alone would give 0.05. */
static void test_pipe_memory_after_prune_and_stable_ids(void **state)
{
    (void)state;
    mer_scene *s = make(NULL, 0);
    step(s, 1);
    mer_error err;
    assert_int_equal(mer_scene_prune(s, 2, &err), MER_OK);
    assert_int_equal(node(s, 2).alive, 0);
    assert_int_equal(node(s, 0).lateral_child[0], MER_NO_NODE);
    assert_int_equal(node(s, 0).lateral_bud[0], MER_BUD_NONE); /* a cut does not regrow */
    assert_int_equal(mer_scene_prune(s, 2, &err), MER_ERR_GONE);
    assert_string_equal(err.field, "node");
    assert_int_equal(mer_scene_prune(s, 99, &err), MER_ERR_NOT_FOUND);
    assert_string_equal(err.field, "node");
    assert_int_equal(mer_scene_prune(s, 0, &err), MER_ERR_ROOT); /* it would empty the tree */
    assert_string_equal(err.field, "node");
    assert_int_equal(node(s, 0).alive, 1);
    mer_params p = *mer_scene_params(s);
    p.alpha = 1e-6f; /* no more growth */
    assert_int_equal(mer_scene_set_params(s, &p, &err), MER_OK);
    step(s, 1);
    assert_int_equal(mer_scene_node_bound(s), 3);
    assert_close(node(s, 0).diameter, 0.0659754f);
    assert_close(node(s, 1).diameter, 0.05f);
    /* Growth resumes with new ids only. */
    p.alpha = 2.0f;
    assert_int_equal(mer_scene_set_params(s, &p, &err), MER_OK);
    step(s, 3);
    uint32_t bound = mer_scene_node_bound(s);
    assert_true(bound > 3);
    assert_int_equal(node(s, 2).alive, 0);
    for (uint32_t id = 3; id < bound; id++)
        assert_true(node(s, id).parent != 2);
    assert_true(node(s, 0).diameter >= 0.0659754f);
    mer_scene_free(s);
}

/* d^n at the root of plant 0 as live tips alone would give it: every living node
 * without a main child bears the leaves (P09 §4.5). */
static double live_only_dn(const mer_scene *s, float leaf, float n)
{
    double sum = 0.0;
    for (uint32_t id = 0; id < mer_scene_node_bound(s); id++) {
        mer_node nd = node(s, id);
        if (nd.alive && nd.main_child == MER_NO_NODE)
            sum += pow(leaf, n);
    }
    return sum;
}

/* The pipe model's memory (P09 §4.5: "branch width is not decreased when leaves
 * and branches are shed or pruned"): prune the biggest lateral of a young tree,
 * grow 10 more steps, and the root's d^n is the living tips' plus the pruned
 * branch's d^n at its cut, over several seeds. */
static void test_pipe_memory_outlasts_regrowth(void **state)
{
    (void)state;
    mer_params p = mer_params_default();
    for (uint64_t seed = 1; seed <= 4; seed++) {
        mer_scene *s = make(&p, seed);
        step(s, 8);
        uint32_t big = MER_NO_NODE;
        float d_big = 0.0f;
        for (uint32_t id = 0; id < mer_scene_node_bound(s); id++) {
            mer_node nd = node(s, id);
            if (nd.alive && nd.parent != MER_NO_NODE && node(s, nd.parent).main_child != id &&
                nd.diameter > d_big) {
                big = id;
                d_big = nd.diameter;
            }
        }
        assert_true(big != MER_NO_NODE);
        mer_error err;
        assert_int_equal(mer_scene_prune(s, big, &err), MER_OK);
        step(s, 10);
        double n = p.pipe_n;
        double live = live_only_dn(s, p.leaf_diameter, p.pipe_n);
        double root = pow(node(s, 0).diameter, n);
        double kept = pow(d_big, n);
        assert_true(live > kept); /* the survivors have outgrown the cut branch */
        assert_true(fabs(root - (live + kept)) < 1e-3 * root);
        mer_scene_free(s);
    }
}

static void test_brush_pressure_and_symmetry(void **state)
{
    (void)state;
    mer_params p = worked();
    p.environment = MER_ENV_MARKERS;
    p.marker_count = 0;
    mer_scene *s = make(&p, 3);
    mer_error err;
    size_t added;
    /* Full pressure: max_count markers in the full radius. */
    mer_brush heavy = {{0, 20, 0}, 4.0f, 1.0f, 50};
    assert_int_equal(mer_scene_brush(s, &heavy, NULL, &added, &err), MER_OK);
    assert_int_equal(added, 50);
    /* Light pressure 0.2: 1 + round(49·0.04) = 3 markers within 4·(0.1 + 0.18). */
    mer_brush light = {{0, 40, 0}, 4.0f, 0.2f, 50};
    assert_int_equal(mer_scene_brush(s, &light, NULL, &added, &err), MER_OK);
    assert_int_equal(added, 3);
    float xyz[53 * 3];
    assert_int_equal(mer_scene_markers(s, xyz, 53), 53);
    for (int i = 50; i < 53; i++) {
        float d = sqrtf(xyz[3 * i] * xyz[3 * i] + (xyz[3 * i + 1] - 40) * (xyz[3 * i + 1] - 40) +
                        xyz[3 * i + 2] * xyz[3 * i + 2]);
        assert_true(d <= 4.0f * 0.28f + 1e-5f);
    }
    mer_scene_free(s);
    /* Mirror in the plane x = 0: markers come in pairs (x, y, z), (−x, y, z). */
    s = make(&p, 3);
    mer_symmetry sym;
    memset(&sym, 0, sizeof sym);
    sym.mirror = 1;
    sym.mirror_normal[0] = 2.0f; /* need not be unit */
    mer_brush dab = {{5, 20, 1}, 2.0f, 0.5f, 21};
    assert_int_equal(mer_scene_brush(s, &dab, &sym, &added, &err), MER_OK);
    uint32_t n = 1 + (uint32_t)lroundf(20.0f * 0.25f);
    assert_int_equal(added, 2 * n);
    float m[24 * 3];
    assert_int_equal(mer_scene_markers(s, m, 24), 2 * n);
    for (uint32_t i = 0; i < n; i++) {
        assert_close(m[6 * i + 3], -m[6 * i]);
        assert_close(m[6 * i + 4], m[6 * i + 1]);
        assert_close(m[6 * i + 5], m[6 * i + 2]);
    }
    mer_scene_free(s);
    /* Rotational 4 × mirror × tiles 2 × 3 = 48 copies of each marker. */
    s = make(&p, 3);
    sym.rotational = 4;
    sym.tiles[0] = 2;
    sym.tiles[1] = 3;
    sym.tile_step[0][0] = 30.0f;
    sym.tile_step[1][2] = 30.0f;
    assert_int_equal(mer_scene_brush(s, &light, &sym, &added, &err), MER_OK);
    assert_int_equal(added, 3 * 48);
    /* Four-fold about the y axis: the first marker's second copy is (z, y, −x)… as
     * a rotation by 90°: (x, z) → (x cos − ..); check the radius is preserved. */
    float r[3 * 48 * 3];
    mer_scene_markers(s, r, 3 * 48);
    float r0 = hypotf(r[0], r[2]);
    float r1 = hypotf(r[3 * 2 * 6], r[3 * 2 * 6 + 2]); /* rotation 1, mirror 0, tile 0 */
    assert_close(r0, r1);
    light.pressure = 0.0f;
    assert_int_equal(mer_scene_brush(s, &light, NULL, &added, &err), MER_ERR_RANGE);
    assert_string_equal(err.field, "pressure");
    mer_brush huge = {{0, 20, 0}, 4.0f, 1.0f, 100000};
    sym.tiles[0] = 32; /* 100000 · 4 · 2 · 32 · 3 markers */
    assert_int_equal(mer_scene_brush(s, &huge, &sym, &added, &err), MER_ERR_LIMIT);
    assert_string_equal(err.field, "max_count");
    mer_scene_free(s);
}

static void test_constraint_to_a_bud(void **state)
{
    (void)state;
    mer_scene *s = make(NULL, 0);
    mer_error err;
    assert_int_equal(mer_scene_constrain(s, 0, 1, &err), MER_OK);
    step(s, 1);
    mer_node r = node(s, 0);
    assert_int_equal(r.main_child, MER_NO_NODE);     /* the terminal stayed dormant */
    assert_int_equal(r.terminal_bud, MER_BUD_DORMANT);
    assert_int_equal(r.lateral_child[0], 1);
    step(s, 4);
    /* Every node but the seedling descends from node 1. */
    for (uint32_t i = 2; i < mer_scene_node_bound(s); i++) {
        uint32_t a = i;
        while (node(s, a).parent != 0)
            a = node(s, a).parent;
        assert_int_equal(a, 1);
    }
    mer_scene_unconstrain(s);
    step(s, 2);
    assert_true(node(s, 0).main_child != MER_NO_NODE);
    assert_int_equal(mer_scene_constrain(s, 0, 0, &err), MER_OK); /* grown out: allowed */
    assert_int_equal(mer_scene_constrain(s, 0, 2, &err), MER_ERR_RANGE);
    assert_string_equal(err.field, "slot");
    mer_scene_free(s);
}

static void test_bend_rotates_subtree(void **state)
{
    (void)state;
    mer_scene *s = make(NULL, 0);
    step(s, 1);
    mer_error err;
    const float y[3] = {0, 3, 0};
    mer_node before = node(s, 2);
    assert_int_equal(mer_scene_bend(s, 2, y, 90.0f, &err), MER_OK);
    mer_node l = node(s, 2);
    assert_close(l.base[0], 0.0f);
    assert_close(l.base[1], 1.0f);
    /* 90° about y: (x, y, z) → (z, y, −x) */
    assert_close(l.dir[0], before.dir[2]);
    assert_close(l.dir[1], before.dir[1]);
    assert_close(l.dir[2], -before.dir[0]);
    /* a tilt about a horizontal axis through the base, by hand: 90° about the
     * branch's own horizontal normal n = up × d / |up × d| brings d to ... up·. */
    const float x[3] = {1, 0, 0};
    assert_int_equal(mer_scene_bend(s, 2, x, 180.0f, &err), MER_OK);
    l = node(s, 2);
    assert_close(l.dir[1], -before.dir[1]); /* flipped upside down about x */
    assert_close(node(s, 1).dir[1], 1.0f); /* the rest stays */
    const float zero[3] = {0, 0, 0};
    assert_int_equal(mer_scene_bend(s, 2, zero, 90.0f, &err), MER_ERR_RANGE);
    assert_string_equal(err.field, "axis");
    mer_scene_free(s);
}

/* The angle between a node's direction and straight up, in degrees. */
static float tilt(const mer_scene *s, uint32_t id)
{
    return acosf(fminf(1.0f, node(s, id).dir[1])) * 57.29578f;
}

static mer_scene *copy_of(const mer_scene *s)
{
    mer_scene *c = NULL;
    mer_error err;
    assert_int_equal(mer_scene_clone(s, &c, &err), MER_OK);
    return c;
}

/* A spread bend curves the first internodes of the axis, each by a share; spread 1
 * is the elbow of mer_scene_bend, byte for byte. */
static void test_bend_spread_curves_the_axis(void **state)
{
    (void)state;
    mer_scene *s = make(NULL, 0);
    step(s, 6);
    uint32_t trunk[5] = {0};
    for (int k = 1; k < 5; k++) {
        trunk[k] = node(s, trunk[k - 1]).main_child;
        assert_true(trunk[k] != MER_NO_NODE);
    }
    mer_error err;
    const float x[3] = {1, 0, 0};
    mer_scene *elbow = copy_of(s), *one = copy_of(s);
    assert_int_equal(mer_scene_bend(elbow, 0, x, 30.0f, &err), MER_OK);
    assert_int_equal(mer_scene_bend_spread(one, 0, x, 30.0f, 1, &err), MER_OK);
    assert_true(mer_scene_hash(elbow) == mer_scene_hash(one));
    assert_near(tilt(elbow, trunk[0]), 30.0f, 1e-2f);
    assert_near(tilt(elbow, trunk[3]), 30.0f, 1e-2f);

    mer_scene *curve = copy_of(s);
    assert_int_equal(mer_scene_bend_spread(curve, 0, x, 30.0f, 3, &err), MER_OK);
    assert_near(tilt(curve, trunk[0]), 10.0f, 1e-2f);
    assert_near(tilt(curve, trunk[1]), 20.0f, 1e-2f);
    assert_near(tilt(curve, trunk[2]), 30.0f, 1e-2f);
    assert_near(tilt(curve, trunk[4]), 30.0f, 1e-2f); /* above the spread: rigid */
    assert_close(node(curve, 0).base[1], node(s, 0).base[1]); /* the base stays */
    /* The second internode turned about its own base, where the first now ends. */
    mer_node n0 = node(curve, trunk[0]), n1 = node(curve, trunk[1]);
    for (int a = 0; a < 3; a++)
        assert_close(n1.base[a], n0.base[a] + n0.dir[a] * n0.length);
    assert_true(mer_scene_hash(curve) != mer_scene_hash(elbow));

    uint64_t h = mer_scene_hash(s);
    assert_int_equal(mer_scene_bend_spread(s, 0, x, 30.0f, 0, &err), MER_ERR_RANGE);
    assert_string_equal(err.field, "spread");
    assert_int_equal(mer_scene_bend_spread(s, 0, x, 30.0f, MER_BEND_SPREAD_MAX + 1, &err),
                     MER_ERR_RANGE);
    assert_true(mer_scene_hash(s) == h);
    mer_scene_free(curve);
    mer_scene_free(one);
    mer_scene_free(elbow);
    mer_scene_free(s);
}

/* A step that grows nothing says why: the constraint first, then the environment. */
static void test_step_report_says_why_nothing_grew(void **state)
{
    (void)state;
    mer_params p = worked();
    p.environment = MER_ENV_MARKERS;
    p.marker_count = 0;
    mer_scene *s = make(&p, 0);
    mer_step_report r;
    mer_scene_step_report(s, &r);
    assert_int_equal(r.step, 0);
    assert_int_equal(r.stall, MER_STALL_NONE);
    step(s, 1);
    mer_scene_step_report(s, &r);
    assert_int_equal(r.step, 1);
    assert_int_equal(r.grown, 0);
    assert_int_equal(r.stall, MER_STALL_NO_MARKERS);
    assert_int_equal(r.node, MER_NO_NODE);
    assert_string_equal(mer_stall_name(r.stall), "no-markers");

    mer_error err;
    assert_int_equal(mer_scene_constrain(s, 0, 1, &err), MER_OK);
    step(s, 1);
    mer_scene_step_report(s, &r);
    assert_int_equal(r.stall, MER_STALL_CONSTRAINED);
    assert_int_equal(r.node, 0);
    assert_string_equal(mer_stall_name(r.stall), "constrained");
    mer_scene *c = copy_of(s); /* a copy keeps the report */
    mer_step_report rc;
    mer_scene_step_report(c, &rc);
    assert_memory_equal(&rc, &r, sizeof r);
    mer_scene_free(c);
    mer_scene_free(s);

    s = make(NULL, 0);
    step(s, 2);
    mer_scene_step_report(s, &r);
    assert_int_equal(r.step, 2);
    assert_true(r.grown > 0);
    assert_int_equal(r.stall, MER_STALL_NONE);
    assert_null(mer_stall_name(MER_STALL_NONE));
    assert_string_equal(mer_stall_name(MER_STALL_NO_LIGHT), "no-light");
    assert_string_equal(mer_stall_name(MER_STALL_ALL_BUDS_DEAD), "all-buds-dead");
    assert_string_equal(mer_stall_name(MER_STALL_DONE), "done");
    mer_scene_free(s);
}

/* The incrementally kept shadow grid equals one rebuilt from the buds, after
 * growth, shedding, pruning and bending. */
static void test_shadow_grid_stays_consistent(void **state)
{
    (void)state;
    mer_params p;
    assert_int_equal(mer_preset_params("fig14-tall-bole", &p, NULL), MER_OK);
    mer_scene *s = make(&p, 0);
    step(s, 12);
    mer_error err;
    const float ax[3] = {1, 0, 0};
    assert_int_equal(mer_scene_bend(s, 2, ax, 30.0f, &err), MER_OK);
    uint32_t victim = mer_scene_node_bound(s) / 2;
    while (!node(s, victim).alive)
        victim++;
    assert_int_equal(mer_scene_prune(s, victim, &err), MER_OK);
    step(s, 3);
    uint64_t kept = mer_shadow_hash(s->env.shadow);
    merp_scene_rebuild_shadow(s);
    assert_true(kept == mer_shadow_hash(s->env.shadow));
    mer_scene_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pipe_memory_after_prune_and_stable_ids),
        cmocka_unit_test(test_pipe_memory_outlasts_regrowth),
        cmocka_unit_test(test_brush_pressure_and_symmetry),
        cmocka_unit_test(test_constraint_to_a_bud),
        cmocka_unit_test(test_bend_rotates_subtree),
        cmocka_unit_test(test_shadow_grid_stays_consistent),
        cmocka_unit_test(test_bend_spread_curves_the_axis),
        cmocka_unit_test(test_step_report_says_why_nothing_grew),
    };
    return cmocka_run_group_tests_name("edit", tests, NULL, NULL);
}
