/* Guiding-vector trees after Xu & Mould 2015 as a growth model
 * (lib/models/guiding/): the least-cost path on a small graph with costs worked
 * by hand, without guiding vectors and with them (the survey's Fig. 5); the Yao
 * graph's cones; the endpoints; then the model: one iteration a step, orders,
 * determinism, clone and checkpoint, prune, validation. */
#include "config.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include <meristem/edit.h>
#include <meristem/presets.h>
#include <meristem/scene.h>

#include "core/alloc.h"
#include "models/guiding/guiding.h"
#include "scene_helpers.h"
#include "scene_private.h"

/* S at the origin, T two units along +x, A at (1, 1, 0) between them: the
 * straight edge S→T or the arc S→A→T. */
static void small_graph(merp_gv_graph *g)
{
    static const float pos[] = {0, 0, 0, 2, 0, 0, 1, 1, 0};
    static const uint32_t start[] = {0, 2, 2, 3}, to[] = {1, 2, 1};
    g->n = 3;
    g->pos = merp_malloc(sizeof pos);
    g->start = merp_malloc(sizeof start);
    g->to = merp_malloc(sizeof to);
    assert_non_null(g->pos);
    assert_non_null(g->start);
    assert_non_null(g->to);
    memcpy(g->pos, pos, sizeof pos);
    memcpy(g->start, start, sizeof start);
    memcpy(g->to, to, sizeof to);
}

static const float up[3] = {0.0f, 1.0f, 0.0f};
static const uint32_t zero = 0;

/* Fig. 5: on plain lengths the straight edge wins (2 against 2√2). With guiding
 * vectors, ε = 0.05, p = 1, the source's vector up:
 *  - no rotation: S→T costs 2·(0.05 + 1/2) = 1.1, the arc √2·(0.05 + (1 − √½)/2)
 *    + √2·(0.05 + (1 + √½)/2) = √2·1.1 ≈ 1.556: straight;
 *  - 90° a hop: A's vector is up turned about up × (S→A) towards +x, so A→T
 *    leaves at 45° from it: the arc costs 2·√2·(0.05 + (1 − √½)/2) ≈ 0.5556,
 *    below 1.1: the path curves, following the turning field. */
static void test_fig5_path_without_and_with_guiding_vectors(void **state)
{
    (void)state;
    merp_gv_graph g = {0};
    merp_gv_search s = {0};
    mer_error err;
    small_graph(&g);
    double bend = (1.0 - sqrt(0.5)) / 2.0;

    merp_gv_guide plain = {.on = 0};
    assert_int_equal(merp_gv_dijkstra(&s, &g, &plain, &zero, up, &zero, 1, &err), MER_OK);
    assert_int_equal(s.pred[1], 0);
    assert_true(fabs(s.dist[1] - 2.0) < 1e-6);

    merp_gv_guide still = {.on = 1, .rotation = 0.0f, .falloff = 1.0f, .eps = 0.05f, .p = 1.0f};
    assert_int_equal(merp_gv_dijkstra(&s, &g, &still, &zero, up, &zero, 1, &err), MER_OK);
    assert_int_equal(s.pred[1], 0);
    assert_true(fabs(s.dist[1] - 1.1) < 1e-6);
    assert_true(fabs(s.dist[2] - sqrt(2.0) * (0.05 + bend)) < 1e-6);

    merp_gv_guide turning = still;
    turning.rotation = (float)(M_PI / 2.0);
    assert_int_equal(merp_gv_dijkstra(&s, &g, &turning, &zero, up, &zero, 1, &err), MER_OK);
    assert_int_equal(s.pred[1], 2);
    assert_int_equal(s.pred[2], 0);
    assert_true(fabs(s.dist[1] - 2.0 * sqrt(2.0) * (0.05 + bend)) < 1e-5);
    assert_near(s.g[3 * 2 + 0], 1.0f, 1e-5f); /* A's guiding vector: +x */
    assert_near(s.g[3 * 2 + 1], 0.0f, 1e-5f);
    assert_int_equal(s.hop[1], 2);
    merp_gv_search_free(&s);
    merp_gv_graph_free(&g);
}

/* The cost is never zero, even along the guiding vector, and grows with the
 * angle to it; the rotation falls off by hop. */
static void test_cost_and_turn(void **state)
{
    (void)state;
    merp_gv_guide gd = {.on = 1, .rotation = 0.5f, .falloff = 0.5f, .eps = 0.01f, .p = 2.0f};
    const float along[3] = {0, 3, 0}, side[3] = {3, 0, 0}, back[3] = {0, -3, 0};
    assert_true(fabs(merp_gv_cost(&gd, up, along) - 3.0 * 0.01 * 0.01) < 1e-9);
    assert_true(merp_gv_cost(&gd, up, along) > 0.0);
    assert_true(merp_gv_cost(&gd, up, side) < merp_gv_cost(&gd, up, back));
    float g1[3], g3[3];
    merp_gv_turn(&gd, up, side, 1, g1);
    merp_gv_turn(&gd, up, side, 3, g3);
    assert_near(acosf(g1[1]), 0.5f, 1e-5f);
    assert_near(acosf(g3[1]), 0.125f, 1e-5f);
    assert_true(g1[0] > 0.0f); /* towards the edge */
    float same[3];
    merp_gv_turn(&gd, up, along, 1, same); /* an edge along up: no axis, no turn */
    assert_near(same[1], 1.0f, 1e-6f);
}

/* Yao graph: from every node at most one edge per cone, each to the nearest
 * other node within the radius in that cone (checked by brute force). */
static void test_yao_graph_cones(void **state)
{
    (void)state;
    enum { N = 300, K = 14 };
    float *pts = malloc(3 * N * sizeof *pts), axes[3 * K];
    assert_non_null(pts);
    mer_rng rng;
    mer_rng_seed(&rng, 5);
    for (int i = 0; i < 3 * N; i++)
        pts[i] = mer_rng_range(&rng, 0.0f, 6.0f);
    merp_gv_graph g = {0};
    mer_error err;
    float radius = 2.0f;
    assert_int_equal(merp_gv_graph_link(&g, pts, N, K, radius, &err), MER_OK);
    merp_gv_cone_axes(K, axes);
    for (int a = 0; a < K; a++)
        assert_near(sqrtf(axes[3 * a] * axes[3 * a] + axes[3 * a + 1] * axes[3 * a + 1] +
                          axes[3 * a + 2] * axes[3 * a + 2]), 1.0f, 1e-5f);
    uint32_t edges = 0;
    for (uint32_t i = 0; i < N; i++) {
        uint32_t want[K];
        float wd[K];
        for (int c = 0; c < K; c++) {
            want[c] = UINT32_MAX;
            wd[c] = radius * radius;
        }
        for (uint32_t j = 0; j < N; j++) {
            float d[3] = {pts[3 * j] - pts[3 * i], pts[3 * j + 1] - pts[3 * i + 1],
                          pts[3 * j + 2] - pts[3 * i + 2]};
            float dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
            uint32_t c = merp_gv_cone_of(axes, K, d);
            if (j != i && dd <= wd[c] && (dd < wd[c] || j < want[c])) {
                wd[c] = dd;
                want[c] = j;
            }
        }
        uint32_t expected = 0;
        for (int c = 0; c < K; c++)
            expected += want[c] != UINT32_MAX;
        assert_int_equal(g.start[i + 1] - g.start[i], expected);
        uint8_t seen[K] = {0};
        for (uint32_t t = g.start[i]; t < g.start[i + 1]; t++) {
            uint32_t j = g.to[t];
            float d[3] = {pts[3 * j] - pts[3 * i], pts[3 * j + 1] - pts[3 * i + 1],
                          pts[3 * j + 2] - pts[3 * i + 2]};
            uint32_t c = merp_gv_cone_of(axes, K, d);
            assert_int_equal(seen[c], 0);
            seen[c] = 1;
            assert_int_equal(j, want[c]);
        }
        edges += g.start[i + 1] - g.start[i];
    }
    assert_true(edges > 6 * N); /* dense enough to route paths */
    merp_gv_graph_free(&g);
    free(pts);
}

/* The crown and bounding volumes: the marker volumes' shapes. */
static void test_volume_inside(void **state)
{
    (void)state;
    const float c[3] = {0, 10, 0}, s[3] = {4, 5, 4};
    const float in[3] = {0, 12, 1}, out[3] = {4, 14, 4}, apex[3] = {0, 14.9f, 0};
    assert_true(merp_gv_inside(MER_VOLUME_ELLIPSOID, c, s, in));
    assert_false(merp_gv_inside(MER_VOLUME_ELLIPSOID, c, s, out));
    assert_true(merp_gv_inside(MER_VOLUME_BOX, c, s, out));
    assert_true(merp_gv_inside(MER_VOLUME_CONE, c, s, apex));
    const float wide_top[3] = {3, 14, 0};
    assert_false(merp_gv_inside(MER_VOLUME_CONE, c, s, wide_top));
}

static mer_params preset(const char *name)
{
    mer_params p;
    mer_error err;
    assert_int_equal(mer_preset_params(name, &p, &err), MER_OK);
    return p;
}

/* The model's count `name` (mer_scene_model_stats); fails the test when it has none. */
static uint32_t stat_of(const mer_scene *s, const char *name)
{
    double v = model_stat(s, name);
    if (v < 0.0)
        fail_msg("no stat %s", name);
    return (uint32_t)v;
}

/* One step is one iteration; the first (one early endpoint) is a single path,
 * a trunk of order 0; later ones branch (orders above 0); past gv_iterations
 * nothing grows. */
static void test_iterations_and_orders(void **state)
{
    (void)state;
    mer_params p = preset("gv-fig2-small-2");
    mer_scene *s = new_scene(&p, 3);
    step(s, 1);
    assert_int_equal(stat_of(s, "iteration"), 1);
    uint32_t n1 = mer_scene_node_bound(s);
    assert_true(n1 > 8);
    for (uint32_t i = 0; i < n1; i++) {
        mer_node nd = node(s, i);
        assert_int_equal(nd.order, 0);
        assert_true(i == 0 || nd.parent == i - 1); /* one path */
    }
    step(s, 1);
    uint32_t n2 = mer_scene_node_bound(s), laterals = 0;
    assert_true(n2 > n1 + 50);
    for (uint32_t i = n1; i < n2; i++)
        laterals += node(s, i).order > 0;
    assert_true(laterals > 0);
    step(s, 1); /* gv_iterations is 2 */
    assert_int_equal(mer_scene_node_bound(s), n2);
    assert_int_equal(stat_of(s, "iteration"), 2);
    mer_step_report r;
    mer_scene_step_report(s, &r);
    assert_int_equal(r.grown, 0);
    assert_int_equal(r.stall, MER_STALL_DONE);
    assert_string_equal(mer_stall_name(r.stall), "done");
    mer_scene_free(s);
}

/* With gv_endpoints_total the iterations share the total: the first takes its
 * one early endpoint, each later one its share of what is left, and the tree
 * gets exactly the total; more iterations then grow nothing, and say so. */
static void test_endpoint_total(void **state)
{
    (void)state;
    mer_params p = preset("gv-fig2-small-5");
    p.gv_endpoints_total = 157;
    mer_scene *s = new_scene(&p, 5);
    step(s, 1);
    assert_int_equal(stat_of(s, "endpoints"), 1);
    step(s, 1);
    assert_int_equal(stat_of(s, "endpoints"), 1 + 39); /* ⌈156 / 4⌉ */
    step(s, 3);
    assert_int_equal(stat_of(s, "endpoints"), 157);
    uint32_t n = mer_scene_node_bound(s);
    p.gv_iterations = 8; /* more iterations, but the total is reached */
    mer_error err;
    assert_int_equal(mer_scene_set_params(s, &p, &err), MER_OK);
    step(s, 1);
    assert_int_equal(mer_scene_node_bound(s), n);
    mer_step_report r;
    mer_scene_step_report(s, &r);
    assert_int_equal(r.stall, MER_STALL_DONE);
    p.gv_endpoints_total = 200; /* a larger total: the rest over the 3 iterations left */
    assert_int_equal(mer_scene_set_params(s, &p, &err), MER_OK);
    step(s, 3);
    assert_int_equal(stat_of(s, "endpoints"), 200);
    mer_scene_free(s);
}

/* The same seed and parameters give the same tree; another seed another one; a
 * clone and a checkpoint grow on as the original does. */
static void test_determinism_clone_checkpoint(void **state)
{
    (void)state;
    mer_params p = preset("gv-shrub");
    mer_scene *a = new_scene(&p, 11), *b = new_scene(&p, 11), *c = new_scene(&p, 12);
    step(a, 2);
    step(b, 2);
    step(c, 2);
    assert_true(mer_scene_hash(a) == mer_scene_hash(b));
    assert_true(mer_scene_hash(a) != mer_scene_hash(c));
    mer_scene *d = NULL, *e = NULL;
    mer_error err;
    assert_int_equal(mer_scene_clone(a, &d, &err), MER_OK);
    uint8_t *buf = NULL;
    size_t len = 0;
    assert_int_equal(mer_scene_save(a, &buf, &len, &err), MER_OK);
    assert_int_equal(mer_scene_load(buf, len, &e, &err), MER_OK);
    free(buf);
    step(a, 2);
    step(d, 2);
    step(e, 2);
    assert_true(mer_scene_hash(a) == mer_scene_hash(d));
    assert_true(mer_scene_hash(a) == mer_scene_hash(e));
    mer_scene_free(a);
    mer_scene_free(b);
    mer_scene_free(c);
    mer_scene_free(d);
    mer_scene_free(e);
}

/* A pruned branch leaves the tree; a later iteration grows from what is left. */
static void test_prune_then_grow(void **state)
{
    (void)state;
    mer_params p = preset("gv-fig2-small-5");
    mer_scene *s = new_scene(&p, 1);
    step(s, 2);
    uint32_t tree = stat_of(s, "tree_nodes");
    mer_error err;
    assert_int_equal(mer_scene_prune(s, 4, &err), MER_OK);
    assert_true(stat_of(s, "tree_nodes") < tree);
    uint32_t n = mer_scene_node_bound(s);
    step(s, 1);
    assert_true(mer_scene_node_bound(s) > n);
    mer_scene_free(s);
}

/* Bad values are refused with the field named. */
static void test_validation(void **state)
{
    (void)state;
    mer_params p = preset("gv-fig2-small-2");
    mer_error err;
    assert_int_equal(mer_params_set(&p, "gv_epsilon", 0.0, &err), MER_ERR_RANGE);
    assert_string_equal(err.field, "gv_epsilon");
    assert_int_equal(mer_params_set(&p, "gv_cones", 2, &err), MER_ERR_RANGE);
    assert_int_equal(mer_params_set(&p, "gv_t", 1.5, &err), MER_ERR_RANGE);
    p.marker_volume = MER_VOLUME_NONE;
    assert_int_equal(mer_params_validate(&p, &err), MER_ERR_INVALID);
    assert_string_equal(err.field, "marker_volume");
    p = preset("gv-fig2-small-2");
    p.gv_density = 900.0f;
    assert_int_equal(mer_params_validate(&p, &err), MER_ERR_LIMIT);
    assert_string_equal(err.field, "gv_density");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fig5_path_without_and_with_guiding_vectors),
        cmocka_unit_test(test_cost_and_turn),
        cmocka_unit_test(test_yao_graph_cones),
        cmocka_unit_test(test_volume_inside),
        cmocka_unit_test(test_iterations_and_orders),
        cmocka_unit_test(test_endpoint_total),
        cmocka_unit_test(test_determinism_clone_checkpoint),
        cmocka_unit_test(test_prune_then_grow),
        cmocka_unit_test(test_validation),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
