/* A sown forest (lib/models/forest/): plants no closer than min_distance, the
 * count reached or refused naming how many fit, every plant's markers and
 * nodes in its Voronoi cell, mixed models in one scene, prune and bend made on
 * the member, and clone, checkpoint and a second build giving the same
 * hashes. */
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
#include <meristem/sow.h>

#include "models/forest/forest.h"
#include "scene_helpers.h"
#include "scene_private.h"

#define MIXED "area -20 -20 20 20\ncount 9\nmin_distance 9\nseed 5\n" \
              "presets fig4-colonization runions-2007 default abop-1.24b\n"

static mer_scene *forest(const char *text, mer_result want)
{
    mer_params p = mer_params_default();
    p.model = MER_MODEL_FOREST;
    p.seedlings = 0;
    p.environment = MER_ENV_MARKERS;
    p.marker_count = 0;
    mer_scene *s = new_scene(&p, 0);
    mer_error err = {0};
    assert_int_equal(mer_scene_set_definition(s, text, strlen(text), &err), want);
    return s;
}

/* The site plant `plant` of the forest grows from. */
static uint32_t site_of(const mer_scene *s, uint32_t plant)
{
    const float *b = s->sk.pos + 3 * s->sk.roots[plant];
    const float p[2] = {b[0], b[2]};
    return mer_voronoi_cell(s->model->sites, s->model->nsites, p);
}

/* How far (x, z) point p of the plant on site `site` lies beyond the cells of
 * its preset (of `np`, dealt round-robin): past the bisector between the
 * nearest site of its preset and the nearest site of another; 0 inside. */
static float beyond(const merp_model *f, uint32_t np, uint32_t site, const float p[2])
{
    uint32_t c = mer_voronoi_cell(f->sites, f->nsites, p), own = site;
    float best = INFINITY;
    for (uint32_t i = site % np; i < f->nsites; i += np) {
        float dx = p[0] - f->sites[2 * i], dz = p[1] - f->sites[2 * i + 1];
        if (dx * dx + dz * dz < best)
            best = dx * dx + dz * dz, own = i;
    }
    if (c % np == site % np)
        return 0.0f;
    const float *a = f->sites + 2 * own, *b = f->sites + 2 * c;
    float da = (p[0] - a[0]) * (p[0] - a[0]) + (p[1] - a[1]) * (p[1] - a[1]);
    float db = (p[0] - b[0]) * (p[0] - b[0]) + (p[1] - b[1]) * (p[1] - b[1]);
    float ab = sqrtf((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]));
    return (da - db) / (2.0f * ab);
}

static void test_spacing_and_models(void **state)
{
    (void)state;
    mer_scene *s = forest(MIXED, MER_OK);
    const merp_model *f = s->model;
    assert_int_equal(f->nsites, 9);
    assert_int_equal(mer_scene_plant_count(s), 9);
    for (uint32_t i = 0; i < f->nsites; i++)
        for (uint32_t j = 0; j < i; j++) {
            float dx = f->sites[2 * i] - f->sites[2 * j], dz = f->sites[2 * i + 1] - f->sites[2 * j + 1];
            assert_true(dx * dx + dz * dz >= 81.0f);
        }
    /* P09 and Runions plants share a member per preset; an L-system plant is one. */
    assert_int_equal(f->nmembers, 1 + 1 + 1 + 2);
    uint32_t models = 0;
    for (uint32_t k = 0; k < f->nmembers; k++)
        models |= 1u << mer_scene_params(f->m[k].scene)->model;
    assert_int_equal(models, (1u << MER_MODEL_P09) | (1u << MER_MODEL_RUNIONS) |
                                 (1u << MER_MODEL_LSYSTEM));
    /* Every plant stands on its own site. */
    for (uint32_t r = 0; r < mer_scene_plant_count(s); r++) {
        const float *b = s->sk.pos + 3 * s->sk.roots[r];
        const float *site = f->sites + 2 * site_of(s, r);
        assert_float_equal(b[0], site[0], 1e-4);
        assert_float_equal(b[2], site[1], 1e-4);
    }
    step(s, 8);
    assert_true(mer_scene_node_bound(s) > 500);
    mer_scene_free(s);
}

/* Every marker lies in the cell of a plant of its member; the nodes stay in
 * their preset's cells but for one internode's reach. */
static void test_cells(void **state)
{
    (void)state;
    mer_scene *s = forest("area -15 -15 15 15\ncount 6\nmin_distance 8\nseed 2\n"
                          "presets fig4-colonization runions-2007\n", MER_OK);
    const merp_model *f = s->model;
    for (uint32_t k = 0; k < f->nmembers; k++) {
        mer_scene *ms = f->m[k].scene;
        size_t n = mer_scene_marker_count(ms);
        assert_true(n > 100);
        float *xyz = malloc(n * 3 * sizeof *xyz);
        assert_int_equal(mer_scene_markers(ms, xyz, n), n);
        for (size_t i = 0; i < n; i++) {
            const float p[2] = {xyz[3 * i], xyz[3 * i + 2]};
            assert_int_equal(mer_voronoi_cell(f->sites, f->nsites, p) % 2, f->m[k].preset);
        }
        free(xyz);
    }
    step(s, 10);
    float worst = 0.0f;
    for (uint32_t i = 0; i < s->sk.n; i++) {
        if (!s->sk.alive[i])
            continue;
        const float p[2] = {s->sk.pos[3 * i], s->sk.pos[3 * i + 2]};
        float b = beyond(f, 2, site_of(s, s->sk.plant[i]), p);
        worst = b > worst ? b : worst;
    }
    /* A node grows towards its preset's markers, which lie in its preset's
     * cells (neighbours of one preset share theirs): no base lies further into
     * another preset's cell than one internode (length 1) reaches. */
    assert_true(worst < 1.0f);
    mer_scene_free(s);
}

static void test_count_not_reached(void **state)
{
    (void)state;
    mer_params p = mer_params_default();
    p.model = MER_MODEL_FOREST;
    p.seedlings = 0;
    mer_scene *s = new_scene(&p, 0);
    const char *text = "area 0 0 10 10\ncount 50\nmin_distance 5\npresets default\n";
    mer_error err = {0};
    assert_int_equal(mer_scene_set_definition(s, text, strlen(text), &err), MER_ERR_LIMIT);
    assert_non_null(strstr(err.message, "only"));
    assert_int_equal(mer_scene_node_bound(s), 0);
    /* Nothing was sown: a later valid definition is taken. */
    text = "area 0 0 10 10\ncount 2\nmin_distance 5\npresets default\n";
    assert_int_equal(mer_scene_set_definition(s, text, strlen(text), &err), MER_OK);
    assert_int_equal(mer_scene_plant_count(s), 2);
    /* ...once. */
    assert_int_equal(mer_scene_set_definition(s, text, strlen(text), &err), MER_ERR_INVALID);
    mer_scene_free(s);
}

static void test_bad_text(void **state)
{
    (void)state;
    mer_params p = mer_params_default();
    p.model = MER_MODEL_FOREST;
    p.seedlings = 0;
    mer_scene *s = new_scene(&p, 0);
    mer_error err = {0};
    const char *t1 = "area 0 0 10 10\ncount 2\nmin_distance five\npresets default\n";
    assert_int_equal(mer_scene_set_definition(s, t1, strlen(t1), &err), MER_ERR_INVALID);
    assert_int_equal(err.line, 3);
    assert_int_equal(err.column, 14);
    const char *t2 = "area 0 0 10 10\ncount 2\nmin_distance 5\npresets default no-such\n";
    assert_int_equal(mer_scene_set_definition(s, t2, strlen(t2), &err), MER_ERR_INVALID);
    assert_string_equal(err.field, "presets");
    const char *t3 = "area 0 0 10 10\ncount 2\npresets default\n";
    assert_int_equal(mer_scene_set_definition(s, t3, strlen(t3), &err), MER_ERR_INVALID);
    assert_int_equal(mer_scene_node_bound(s), 0);
    mer_scene_free(s);
}

/* A prune or bend of a forest node is its member's, and lasts. */
static void test_edits(void **state)
{
    (void)state;
    mer_scene *s = forest(MIXED, MER_OK);
    step(s, 6);
    const merp_model *f = s->model;
    uint32_t k, i, cut = MER_NO_NODE;
    for (uint32_t o = 0; o < s->sk.n && cut == MER_NO_NODE; o++)
        if (s->sk.alive[o] && s->sk.parent[o] != MER_NO_NODE && s->sk.order[o] == 1 &&
            merp_forest_member_of(f, o, &k, &i) == 0 && f->m[k].preset == 2)
            cut = o;
    assert_int_not_equal(cut, MER_NO_NODE);
    mer_error err = {0};
    assert_int_equal(mer_scene_prune(s, cut, &err), MER_OK);
    assert_int_equal(merp_forest_member_of(f, cut, &k, &i), 0);
    assert_false(f->m[k].scene->sk.alive[i]);
    step(s, 2);
    assert_false(s->sk.alive[cut]);
    uint32_t root = s->sk.roots[0], tip = s->sk.child[3 * root];
    assert_int_not_equal(tip, MER_NO_NODE);
    const float axis[3] = {1, 0, 0};
    assert_int_equal(mer_scene_bend(s, root, axis, 30.0f, &err), MER_OK);
    assert_int_equal(merp_forest_member_of(f, tip, &k, &i), 0);
    const merp_forest_member *m = &f->m[k];
    for (int a = 0; a < 3; a++)
        assert_float_equal(s->sk.pos[3 * tip + a], m->scene->sk.pos[3 * i + a] + m->offset[a], 1e-5);
    assert_true(fabsf(s->sk.dir[3 * root + 1] - cosf(30.0f * 3.14159265f / 180.0f)) < 1e-3f);
    mer_scene_free(s);
}

/* The same text gives the same forest; a clone and a checkpoint grow on as the
 * original does. */
static void test_determinism(void **state)
{
    (void)state;
    mer_scene *a = forest(MIXED, MER_OK), *b = forest(MIXED, MER_OK);
    step(a, 4);
    step(b, 4);
    assert_int_equal(mer_scene_hash(a), mer_scene_hash(b));
    mer_scene *c = NULL, *d = NULL;
    mer_error err = {0};
    assert_int_equal(mer_scene_clone(a, &c, &err), MER_OK);
    uint8_t *bytes = NULL;
    size_t size = 0;
    assert_int_equal(mer_scene_save(a, &bytes, &size, &err), MER_OK);
    assert_int_equal(mer_scene_load(bytes, size, &d, &err), MER_OK);
    free(bytes);
    assert_int_equal(mer_scene_hash(d), mer_scene_hash(a));
    step(a, 2);
    step(c, 2);
    step(d, 2);
    assert_int_equal(mer_scene_hash(c), mer_scene_hash(a));
    assert_int_equal(mer_scene_hash(d), mer_scene_hash(a));
    mer_scene_free(a);
    mer_scene_free(b);
    mer_scene_free(c);
    mer_scene_free(d);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_spacing_and_models),
        cmocka_unit_test(test_cells),
        cmocka_unit_test(test_count_not_reached),
        cmocka_unit_test(test_bad_text),
        cmocka_unit_test(test_edits),
        cmocka_unit_test(test_determinism),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
