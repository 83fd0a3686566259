/* Unit tests for lib/scene.c, tree.c, grow.c and edit.c: a scene step by step,
 * hand-computed where the numbers are small enough. The worked seedling: shadow
 * propagation with a = 0.2 (set here; the default is 0.1), C = 1; its two buds
 * share voxel (50, 1, 50), so each has s = 0.4 and Q = 1 − 0.4 + 0.2 = 0.8;
 * v_base = α·ΣQ = 2·1.6 = 3.2. */
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

#define assert_near(a, b, eps) assert_true(fabsf((float)(a) - (float)(b)) < (eps))
#define assert_close(a, b) assert_near(a, b, 1e-4f)

static mer_params worked(void)
{
    mer_params p = mer_params_default();
    p.shadow_a = 0.2f;
    return p;
}

/* A scene from `p`, or from worked() when `p` is NULL. */
static mer_scene *make(const mer_params *p, uint64_t seed)
{
    mer_params w = worked();
    return new_scene(p != NULL ? p : &w, seed);
}

static mer_node node(const mer_scene *s, uint32_t id)
{
    mer_node n;
    assert_int_equal(mer_scene_node(s, id, &n, NULL), MER_OK);
    return n;
}

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
        cmocka_unit_test(test_seedling),
        cmocka_unit_test(test_first_step_by_hand),
        cmocka_unit_test(test_phyllotaxis_spiral),
        cmocka_unit_test(test_phyllotaxis_decussate),
        cmocka_unit_test(test_pipe_memory_after_prune_and_stable_ids),
        cmocka_unit_test(test_priority_apical_control_schedule),
        cmocka_unit_test(test_sympodial_terminals_flower),
        cmocka_unit_test(test_sylleptic_vs_proleptic),
        cmocka_unit_test(test_obstacles_block_shoots_and_remove_markers),
        cmocka_unit_test(test_ground_stops_drooping_shoots),
        cmocka_unit_test(test_raised_ground_removes_markers_below),
        cmocka_unit_test(test_determinism),
        cmocka_unit_test(test_progress_and_cancel),
        cmocka_unit_test(test_brush_pressure_and_symmetry),
        cmocka_unit_test(test_constraint_to_a_bud),
        cmocka_unit_test(test_bend_rotates_subtree),
        cmocka_unit_test(test_shadow_grid_stays_consistent),
        cmocka_unit_test(test_several_plants_and_params),
        cmocka_unit_test(test_obstacles_cast_shadow),
        cmocka_unit_test(test_tropism_by_order),
        cmocka_unit_test(test_plants_compete),
        cmocka_unit_test(test_set_params_regrids_markers),
        cmocka_unit_test(test_set_schedule),
        cmocka_unit_test(test_gradient_direction_mode),
    };
    return cmocka_run_group_tests_name("scene", tests, NULL, NULL);
}
