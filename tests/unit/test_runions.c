/* The space colonization of Runions, Lane & Prusinkiewicz 2007 as a growth
 * model (lib/models/runions/): hand-placed attraction points — association to
 * the closest node within d_i, the kill distance d_k, the direction of a new
 * node, a node's fourth shoot — then determinism and the preset. */
#include "config.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include <meristem/presets.h>
#include <meristem/scene.h>

#include "scene_helpers.h"
#include "scene_private.h"

/* One seedling at the origin (its tip, the root node, at (0, 1, 0)), no
 * markers: the points are placed by hand. d_k = 1 so that points a few units
 * away survive a step. */
static mer_scene *bare(float d_i, float d_k)
{
    mer_params p = mer_params_default();
    mer_error err;
    assert_int_equal(mer_model_parse("runions", &p.model, &err), MER_OK);
    p.environment = MER_ENV_MARKERS;
    p.marker_count = 0;
    p.d_i = d_i;
    p.d_k = d_k;
    p.D = 1.0f;
    return new_scene(&p, 1);
}

static void add(mer_scene *s, float x, float y, float z)
{
    const float xyz[3] = {x, y, z};
    mer_error err;
    assert_int_equal(mer_scene_add_markers(s, xyz, 1, &err), MER_OK);
}

static mer_node at(const mer_scene *s, uint32_t id)
{
    mer_node n;
    assert_int_equal(mer_scene_node(s, id, &n, NULL), MER_OK);
    return n;
}

/* A new node grows D along the normalized sum of the unit vectors towards the
 * node's points, from the node's end, in its first free slot. */
static void test_direction_is_the_sum_of_unit_vectors(void **state)
{
    (void)state;
    mer_scene *s = bare(6.0f, 1.0f);
    add(s, 3.0f, 1.0f, 0.0f); /* +x, 3 away */
    add(s, 0.0f, 1.0f, 5.0f); /* +z, 5 away: the same weight as the nearer one */
    step(s, 1);
    assert_int_equal(mer_scene_node_bound(s), 2);
    mer_node c = at(s, 1);
    float h = 1.0f / sqrtf(2.0f);
    assert_int_equal(c.parent, 0);
    assert_close(c.base[1], 1.0f);
    assert_close(c.dir[0], h);
    assert_close(c.dir[1], 0.0f);
    assert_close(c.dir[2], h);
    assert_close(c.length, 1.0f);
    assert_int_equal(c.order, 0); /* slot 0: the main continuation */
    assert_int_equal(mer_scene_marker_count(s), 2);
    mer_scene_free(s);
}

/* A point goes to the closest node within d_i, and only that node grows for it;
 * a point beyond d_i of every node attracts nothing. */
static void test_points_go_to_the_closest_node(void **state)
{
    (void)state;
    mer_scene *s = bare(6.0f, 1.0f);
    add(s, 0.0f, 5.0f, 0.0f);
    step(s, 1); /* the root grows up: node 1 ends at (0, 2, 0) */
    assert_int_equal(mer_scene_node_bound(s), 2);
    add(s, 2.0f, 1.0f, 0.0f);   /* 2 from the root's end, 2.24 from node 1's */
    add(s, 0.0f, 1.0f, -9.0f);  /* beyond d_i of both */
    step(s, 1);
    assert_int_equal(mer_scene_node_bound(s), 4);
    mer_node side = at(s, 2), up = at(s, 3); /* nodes grow in id order */
    assert_int_equal(up.parent, 1); /* (0, 5, 0) is closer to node 1 than to the root */
    assert_close(up.dir[1], 1.0f);
    assert_int_equal(side.parent, 0);
    assert_close(side.dir[0], 1.0f);
    assert_int_equal(side.order, 1); /* the root's slot 0 was taken: a lateral */
    mer_scene_free(s);
}

/* Points within d_k of a node are removed (inclusive), before association and
 * after growth; a point just outside grows a node and is then removed by it. */
static void test_kill_distance(void **state)
{
    (void)state;
    mer_scene *s = bare(6.0f, 1.0f);
    add(s, 0.0f, 1.0f, 1.0f); /* exactly d_k from the root's end */
    mer_error err;
    uint32_t done;
    assert_int_equal(mer_scene_step(s, 1, NULL, NULL, NULL, &done, &err), MER_OK);
    assert_int_equal(mer_scene_marker_count(s), 0);
    assert_int_equal(mer_scene_node_bound(s), 1);
    mer_step_report r;
    mer_scene_step_report(s, &r);
    assert_int_equal(r.stall, MER_STALL_NO_MARKERS);
    add(s, 0.0f, 1.0f, 1.5f);
    step(s, 1);
    assert_int_equal(mer_scene_node_bound(s), 2);
    assert_close(at(s, 1).dir[2], 1.0f);
    assert_int_equal(mer_scene_marker_count(s), 0); /* 0.5 from the new end */
    mer_scene_free(s);
}

/* A node whose three slots are taken no longer attracts points: they go to the
 * closest node within d_i that has a free slot. */
static void test_a_full_node_passes_its_points_on(void **state)
{
    (void)state;
    mer_scene *s = bare(6.0f, 1.0f);
    merp_skeleton *sk = &s->sk;
    float start[3];
    merp_skel_node_end(sk, 0, start);
    for (uint32_t k = 0; k < 3; k++) { /* three short shoots pointing down */
        uint32_t c;
        mer_error err;
        assert_int_equal(merp_skel_node_new(sk, 0, &c, &err), MER_OK);
        sk->parent[c] = 0;
        sk->slot[c] = (uint8_t)k;
        sk->child[3 * 0 + k] = c;
        memcpy(sk->pos + 3 * c, start, sizeof start);
        sk->dir[3 * c + 1] = -1.0f;
        sk->len[c] = 0.5f;
        sk->side[3 * c] = 1.0f;
    }
    add(s, 0.0f, 1.0f, 3.0f); /* 3 from the root's end, 3.04 from the shoots' ends */
    step(s, 1);
    assert_int_equal(mer_scene_node_bound(s), 5);
    assert_int_equal(at(s, 4).parent, 1); /* the lowest id of the tied shoots */
    mer_scene_free(s);
}

/* Parameters the model cannot grow with are refused, naming the field. */
static void test_validation(void **state)
{
    (void)state;
    mer_params p = mer_params_default();
    p.model = MER_MODEL_RUNIONS;
    mer_error err;
    assert_int_equal(mer_params_validate(&p, &err), MER_ERR_INVALID);
    assert_string_equal(err.field, "environment");
    p.environment = MER_ENV_MARKERS;
    assert_int_equal(mer_params_validate(&p, &err), MER_OK);
    p.d_k = p.d_i;
    assert_int_equal(mer_params_validate(&p, &err), MER_ERR_RANGE);
    assert_string_equal(err.field, "d_k");
    assert_int_equal(mer_params_set(&p, "D", 0.5, &err), MER_OK);
    assert_close(p.D, 0.5f);
    size_t i = 0;
    while (strcmp(mer_params_field_name(i), "d_i") != 0)
        i++;
    assert_string_equal(mer_params_field_model(i), "runions");
    assert_string_equal(mer_params_field_symbol(i), "d_i");
}

/* The preset grows a tree in its envelope; one seed gives one tree, bit for bit,
 * and a clone grows on as the original does. */
static void test_preset_is_deterministic(void **state)
{
    (void)state;
    mer_params p;
    assert_int_equal(mer_preset_params("runions-2007", &p, NULL), MER_OK);
    mer_scene *a = new_scene(&p, 7), *b = new_scene(&p, 7), *c = new_scene(&p, 8);
    step(a, 12);
    step(b, 12);
    step(c, 12);
    assert_true(mer_scene_hash(a) == mer_scene_hash(b));
    assert_true(mer_scene_hash(a) != mer_scene_hash(c));
    mer_summary sum;
    mer_scene_summary(a, &sum);
    assert_true(sum.internodes > 100);
    assert_true(sum.height > 10.0f && sum.height < 24.0f);
    assert_true(sum.markers < 20000);
    mer_scene *d = NULL;
    mer_error err;
    assert_int_equal(mer_scene_clone(a, &d, &err), MER_OK);
    step(a, 3);
    step(d, 3);
    assert_true(mer_scene_hash(a) == mer_scene_hash(d));
    mer_scene_free(a);
    mer_scene_free(b);
    mer_scene_free(c);
    mer_scene_free(d);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_direction_is_the_sum_of_unit_vectors),
        cmocka_unit_test(test_points_go_to_the_closest_node),
        cmocka_unit_test(test_kill_distance),
        cmocka_unit_test(test_a_full_node_passes_its_points_on),
        cmocka_unit_test(test_validation),
        cmocka_unit_test(test_preset_is_deterministic),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
