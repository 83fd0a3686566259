/* Unit tests for scenes (lib/scene.c, scene_env.c, scene_read.c): seedlings,
 * obstacles and the ground, determinism, progress, several plants, parameter
 * changes. The P09 model's steps are test_p09.c, edits test_edit.c. */
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

static void test_seedling(void **state)
{
    (void)state;
    mer_scene *s = make(NULL, 0);
    assert_int_equal(mer_scene_node_bound(s), 1);
    mer_node n = node(s, 0);
    assert_int_equal(n.parent, MER_NO_NODE);
    assert_int_equal(n.order, 0);
    assert_int_equal(n.alive, 1);
    assert_close(n.dir[1], 1.0f);
    assert_close(n.length, 1.0f);
    assert_int_equal(n.terminal_bud, MER_BUD_DORMANT);
    assert_int_equal(n.lateral_bud[0], MER_BUD_DORMANT);
    assert_int_equal(n.lateral_bud[1], MER_BUD_NONE);
    mer_summary m;
    mer_scene_summary(s, &m);
    assert_int_equal(m.internodes, 1);
    assert_int_equal(m.buds, 2);
    assert_close(m.height, 1.0f);
    mer_error err;
    assert_int_equal(mer_scene_node(s, 1, &n, &err), MER_ERR_RANGE);
    assert_string_equal(err.field, "node");
    mer_scene_free(s);
}

static void test_obstacles_block_shoots_and_remove_markers(void **state)
{
    (void)state;
    mer_scene *s = make(NULL, 0);
    mer_error err;
    /* A small box (no voxel centre inside, so no shade) where the trunk's next end
     * (0, 2.6, 0) would be. */
    const float lo[3] = {-0.3f, 2.2f, -0.3f}, hi[3] = {0.3f, 2.8f, 0.3f};
    assert_int_equal(mer_scene_add_box(s, lo, hi, &err), MER_OK);
    step(s, 1);
    mer_node r = node(s, 0);
    assert_int_equal(r.main_child, MER_NO_NODE);
    assert_int_equal(r.terminal_bud, MER_BUD_DORMANT);
    assert_int_equal(r.lateral_child[0], 1);
    assert_int_equal(mer_scene_add_box(s, hi, lo, &err), MER_ERR_RANGE);
    /* Markers inside obstacles are dropped or removed. */
    const float c[3] = {0, 10, 0};
    const float pts[] = {0, 10, 0, 0, 10.5f, 0, 5, 10, 0, 0, 2.5f, 0};
    assert_int_equal(mer_scene_add_markers(s, pts, 4, &err), MER_OK);
    assert_int_equal(mer_scene_marker_count(s), 3); /* (0, 2.5, 0) is in the box */
    assert_int_equal(mer_scene_add_sphere(s, c, 1.0f, &err), MER_OK);
    assert_int_equal(mer_scene_marker_count(s), 1);
    assert_int_equal(mer_scene_add_sphere(s, c, 0.0f, &err), MER_ERR_RANGE);
    assert_string_equal(err.field, "radius");
    /* Coordinates that are not finite are refused, and change nothing. */
    const float inf = INFINITY, nan = NAN;
    const float c_nan[3] = {0, nan, 0}, hi_inf[3] = {0.3f, inf, 0.3f};
    const uint64_t before = mer_scene_hash(s);
    assert_int_equal(mer_scene_add_sphere(s, c, inf, &err), MER_ERR_RANGE);
    assert_int_equal(mer_scene_add_sphere(s, c_nan, 1.0f, &err), MER_ERR_INVALID);
    assert_string_equal(err.field, "center");
    assert_int_equal(mer_scene_add_box(s, lo, hi_inf, &err), MER_ERR_INVALID);
    assert_string_equal(err.field, "max");
    assert_int_equal(mer_scene_add_box(s, c_nan, hi, &err), MER_ERR_INVALID);
    assert_string_equal(err.field, "min");
    const float bad_pts[] = {0, 20, 0, 0, inf, 0};
    assert_int_equal(mer_scene_add_markers(s, bad_pts, 2, &err), MER_ERR_INVALID);
    assert_string_equal(err.field, "points");
    assert_int_equal(mer_scene_marker_count(s), 1);
    assert_true(mer_scene_hash(s) == before);
    mer_scene_free(s);
}

static void test_ground_stops_drooping_shoots(void **state)
{
    (void)state;
    mer_params p = worked();
    p.eta = -0.6f; /* strong downward tropism */
    p.xi = 0.0f;
    mer_scene *s = make(&p, 0);
    step(s, 6);
    int below = 0, any_down = 0;
    for (uint32_t i = 0; i < mer_scene_node_bound(s); i++) {
        mer_node n = node(s, i);
        float end = n.base[1] + n.dir[1] * n.length;
        below |= end < 0.0f;
        any_down |= n.dir[1] < 0.0f;
    }
    assert_false(below);
    assert_true(any_down);
    mer_scene_free(s);
}

static void test_raised_ground_removes_markers_below(void **state)
{
    (void)state;
    mer_scene *s = make(NULL, 0);
    mer_error err;
    const float pts[] = {0, 3, 0, 1, 8, 0, 2, 12, 1};
    assert_int_equal(mer_scene_add_markers(s, pts, 3, &err), MER_OK);
    assert_int_equal(mer_scene_marker_count(s), 3);
    mer_params p = *mer_scene_params(s);
    p.ground = 5.0f;
    assert_int_equal(mer_scene_set_params(s, &p, &err), MER_OK);
    assert_int_equal(mer_scene_marker_count(s), 2); /* (0, 3, 0) is under it now */
    p.ground_enabled = 0;
    p.ground = 10.0f;
    assert_int_equal(mer_scene_set_params(s, &p, &err), MER_OK);
    assert_int_equal(mer_scene_marker_count(s), 2); /* no ground: nothing is below it */
    mer_scene_free(s);
}

static void edits(mer_scene *s)
{
    mer_error err;
    mer_brush b = {{2, 8, 1}, 3.0f, 0.7f, 40};
    mer_symmetry sym;
    memset(&sym, 0, sizeof sym);
    sym.rotational = 3;
    assert_int_equal(mer_scene_brush(s, &b, &sym, NULL, &err), MER_OK);
    step(s, 4);
    const float ax[3] = {0, 0, 1};
    assert_int_equal(mer_scene_bend(s, 2, ax, 20.0f, &err), MER_OK);
    step(s, 2);
    assert_int_equal(mer_scene_prune(s, 5, &err), MER_OK);
    step(s, 3);
}

static void test_determinism(void **state)
{
    (void)state;
    mer_params p;
    assert_int_equal(mer_preset_params("fig4-colonization", &p, NULL), MER_OK);
    mer_scene *a = make(&p, 5), *b = make(&p, 5), *c = make(&p, 6);
    assert_true(mer_scene_hash(a) == mer_scene_hash(b));
    assert_true(mer_scene_hash(a) != mer_scene_hash(c)); /* other markers */
    step(a, 6);
    step(b, 6);
    step(c, 6);
    edits(a);
    edits(b);
    edits(c);
    assert_true(mer_scene_hash(a) == mer_scene_hash(b));
    assert_true(mer_scene_hash(a) != mer_scene_hash(c));
    mer_summary ma, mb;
    mer_scene_summary(a, &ma);
    mer_scene_summary(b, &mb);
    assert_memory_equal(&ma, &mb, sizeof ma);
    assert_true(ma.internodes > 50);
    mer_scene_free(a);
    mer_scene_free(b);
    mer_scene_free(c);
    /* Shadow propagation too: no randomness, the same tree every time. */
    a = make(NULL, 1);
    b = make(NULL, 1);
    step(a, 12);
    step(b, 12);
    assert_true(mer_scene_hash(a) == mer_scene_hash(b));
    mer_scene_free(a);
    mer_scene_free(b);
}

typedef struct progress_log {
    uint32_t calls, last_done, total;
    volatile int *cancel;
    uint32_t cancel_after;
} progress_log;

static void on_progress(void *ctx, uint32_t done, uint32_t total)
{
    progress_log *log = ctx;
    log->calls++;
    log->last_done = done;
    log->total = total;
    if (log->cancel != NULL && done == log->cancel_after)
        *log->cancel = 1;
}

static void test_progress_and_cancel(void **state)
{
    (void)state;
    mer_scene *s = make(NULL, 0);
    progress_log log = {0, 0, 0, NULL, 0};
    uint32_t done;
    assert_int_equal(mer_scene_step(s, 3, on_progress, &log, NULL, &done, NULL), MER_OK);
    assert_int_equal(done, 3);
    assert_int_equal(log.calls, 3);
    assert_int_equal(log.last_done, 3);
    assert_int_equal(log.total, 3);
    volatile int cancel = 0;
    progress_log log2 = {0, 0, 0, &cancel, 2};
    assert_int_equal(mer_scene_step(s, 10, on_progress, &log2, &cancel, &done, NULL), MER_OK);
    assert_int_equal(done, 2);
    assert_int_equal(mer_scene_step_index(s), 5);
    cancel = 1;
    assert_int_equal(mer_scene_step(s, 10, NULL, NULL, &cancel, &done, NULL), MER_OK);
    assert_int_equal(done, 0);
    mer_scene_free(s);
}

static void test_several_plants_and_params(void **state)
{
    (void)state;
    mer_params p = worked();
    p.seedlings = 3;
    mer_scene *s = make(&p, 0);
    assert_int_equal(mer_scene_plant_count(s), 3);
    assert_close(node(s, 0).base[0], -10.0f);
    assert_close(node(s, 2).base[0], 10.0f);
    assert_int_equal(node(s, 2).plant, 2);
    mer_error err;
    const float under[3] = {0, -1, 0};
    assert_int_equal(mer_scene_add_plant(s, under, NULL, &err), MER_ERR_RANGE);
    const float there[3] = {0, 0, 20};
    uint32_t root;
    assert_int_equal(mer_scene_add_plant(s, there, &root, &err), MER_OK);
    assert_int_equal(root, 3);
    step(s, 5);
    for (uint32_t i = 4; i < mer_scene_node_bound(s); i++) {
        mer_node n = node(s, i), par = node(s, n.parent);
        assert_int_equal(n.plant, par.plant);
    }
    /* A bad parameter set is refused and changes nothing. */
    mer_params bad = *mer_scene_params(s);
    bad.kappa = 0.0f;
    assert_int_equal(mer_scene_set_params(s, &bad, &err), MER_ERR_RANGE);
    assert_string_equal(err.field, "kappa");
    assert_close(mer_scene_params(s)->kappa, 0.5f);
    /* Switching environments keeps the tree. */
    uint32_t bound = mer_scene_node_bound(s);
    bad = *mer_scene_params(s);
    bad.environment = MER_ENV_MARKERS;
    assert_int_equal(mer_scene_set_params(s, &bad, &err), MER_OK);
    assert_int_equal(mer_scene_node_bound(s), bound);
    mer_scene_free(s);
    assert_int_equal(mer_scene_new(&bad, 0, NULL == NULL ? &s : NULL, &err), MER_OK);
    mer_scene_free(s);
}

/* A box low over the seedling shades it: its top layer (voxels j = 3, centres
 * x, z = -2.5..2.5) casts pyramids; the 25 of them within two voxels of the bud's
 * column add 25·a·b^(-2) = 25·0.05 = 1.25 at j = 1, so Q = 1 − (0.4 + 1.25) + 0.2
 * < 0: no light, no resource, no growth. */
static void test_obstacles_cast_shadow(void **state)
{
    (void)state;
    mer_scene *s = make(NULL, 0);
    const float lo[3] = {-3, 3, -3}, hi[3] = {3, 4, 3};
    assert_int_equal(mer_scene_add_box(s, lo, hi, NULL), MER_OK);
    step(s, 1);
    assert_int_equal(mer_scene_node_bound(s), 1);
    assert_close(node(s, 0).q, 0.0f);
    mer_scene_free(s);
}

/* A new marker grid keeps the markers. */
static void test_set_params_regrids_markers(void **state)
{
    (void)state;
    mer_params p = worked();
    p.environment = MER_ENV_MARKERS;
    p.marker_count = 500;
    mer_scene *s = make(&p, 4);
    size_t before = mer_scene_marker_count(s);
    assert_int_equal(before, 500);
    p.marker_cell = 1.5f;
    p.bounds_max[1] = 60.0f;
    assert_int_equal(mer_scene_set_params(s, &p, NULL), MER_OK);
    assert_int_equal(mer_scene_marker_count(s), before);
    step(s, 5);
    assert_true(mer_scene_node_bound(s) > 3);
    mer_scene_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_seedling),
        cmocka_unit_test(test_obstacles_block_shoots_and_remove_markers),
        cmocka_unit_test(test_ground_stops_drooping_shoots),
        cmocka_unit_test(test_raised_ground_removes_markers_below),
        cmocka_unit_test(test_determinism),
        cmocka_unit_test(test_progress_and_cancel),
        cmocka_unit_test(test_several_plants_and_params),
        cmocka_unit_test(test_obstacles_cast_shadow),
        cmocka_unit_test(test_set_params_regrids_markers),
    };
    return cmocka_run_group_tests_name("scene", tests, NULL, NULL);
}
