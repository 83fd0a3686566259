/* Unit tests for lib/models/lsystem/model.c and draw.c: the L-system as a growth
 * model on the shared skeleton, through the public scene API (ABOP's fixtures,
 * joints, prune and bend that last, determinism, clone and checkpoints). */
#include "config.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include <meristem/edit.h>
#include <meristem/gltf.h>
#include <meristem/mesh.h>
#include <meristem/params.h>
#include <meristem/scene.h>

#include "scene_helpers.h"

static const char ALGAE[] = "axiom: a\na -> ab\nb -> a\n";
static const char FIG_1_24A[] = "derivation length: 5\naxiom: F\nF -> F[+F]F[-F]F\n";
static const char FIG_1_24D[] =
    "derivation length: 7\naxiom: X\nX -> F[+X]F[-X]+X\nF -> FF\n";
static const char HONDA[] =
    "#define r1 0.9\n#define r2 0.6\n#define a0 45\n#define a2 45\n"
    "#define d 137.5\n#define wr 0.707\n"
    "derivation length: 10\naxiom: A(1,10)\n"
    "A(l,w) : * -> !(w)F(l)[&(a0)B(l*r2,w*wr)]/(d)A(l*r1,w*wr)\n"
    "B(l,w) : * -> !(w)F(l)[-(a2)$C(l*r2,w*wr)]C(l*r1,w*wr)\n"
    "C(l,w) : * -> !(w)F(l)[+(a2)$B(l*r2,w*wr)]B(l*r1,w*wr)\n";
static const char TERNARY[] =
    "#define d1 94.74\n#define d2 132.63\n#define a 18.95\n#define lr 1.109\n#define vr 1.732\n"
    "derivation length: 6\naxiom: !(1)F(200)/(45)A\n"
    "A : * -> !(vr)F(50)[&(a)F(50)A]/(d1)[&(a)F(50)A]/(d2)[&(a)F(50)A]\n"
    "F(l) : * -> F(l*lr)\n!(w) : * -> !(w*vr)\n";
static const char STOCHASTIC[] =
    "derivation length: 5\naxiom: F\n"
    "F -> F[+F]F[-F]F : 0.33\nF -> F[+F]F : 0.33\nF -> F[-F]F : 0.34\n";

static mer_scene *ls_scene(const char *text, float delta, uint64_t seed)
{
    mer_params p = mer_params_default();
    p.model = MER_MODEL_LSYSTEM;
    p.ls_delta = delta;
    return new_defined_scene(&p, seed, text);
}

/* Live nodes that are drawn segments (joints have length 0). */
static uint32_t live_segments(const mer_scene *s)
{
    uint32_t k = 0;
    for (uint32_t i = 0; i < mer_scene_node_bound(s); i++) {
        mer_node nd = node(s, i);
        k += nd.alive && nd.length > 0.0f;
    }
    return k;
}

/* ABOP §1.2: the algae's lengths are Fibonacci numbers; it draws nothing. */
static void test_algae(void **state)
{
    (void)state;
    mer_scene *s = ls_scene(ALGAE, 90.0f, 1);
    static const double want[] = {1, 2, 3, 5, 8, 13};
    for (int n = 0; n < 6; n++) {
        assert_true(model_stat(s, "string_length") == want[n]);
        assert_true(model_stat(s, "derivation_step") == n);
        if (n < 5)
            step(s, 1);
    }
    assert_true(model_stat(s, "modules.a") == 8); /* abaababaabaab */
    assert_true(model_stat(s, "modules.b") == 5);
    assert_int_equal(mer_scene_node_bound(s), 0);
    mer_scene_free(s);
}

/* Fig. 1.24a, n = 5: 5^5 segments, a straight main axis of 3^5 unit steps. */
static void test_fig_1_24a(void **state)
{
    (void)state;
    mer_scene *s = ls_scene(FIG_1_24A, 25.7f, 1);
    step(s, 7); /* the text stops at 5 */
    assert_true(model_stat(s, "derivation_step") == 5);
    assert_true(model_stat(s, "segments") == 3125);
    mer_summary sum;
    mer_scene_summary(s, &sum);
    assert_int_equal(sum.internodes, 3125);
    assert_float_equal(sum.height, 243.0f, 1e-3f);
    assert_int_equal(node(s, 0).order, 0);
    mer_scene_free(s);
}

/* Fig. 1.24d, n = 7: 4,118 segments (f' = 2f + 2x, x = 3^n). */
static void test_fig_1_24d(void **state)
{
    (void)state;
    mer_scene *s = ls_scene(FIG_1_24D, 20.0f, 1);
    step(s, 7);
    assert_true(model_stat(s, "segments") == 4118);
    assert_int_equal(live_segments(s), 4118);
    mer_scene_free(s);
}

/* Fig. 2.6 (Honda): 2^10 - 1 segments, a vertical trunk whose tip is at
 * Σ_{i<10} 0.9^i, widths from ! (times ls_width_scale). */
static void test_honda(void **state)
{
    (void)state;
    mer_scene *s = ls_scene(HONDA, 90.0f, 1);
    step(s, 10);
    assert_true(model_stat(s, "segments") == 1023);
    float top = 0.0f;
    for (uint32_t i = 0; i < mer_scene_node_bound(s); i++) {
        mer_node nd = node(s, i);
        if (nd.order == 0) {
            assert_float_equal(nd.dir[1], 1.0f, 1e-5f);
            top = fmaxf(top, nd.base[1] + nd.length);
        }
    }
    assert_float_equal(top, 6.5132156f, 1e-4f);
    assert_float_equal(node(s, 0).diameter, 10.0f, 1e-4f); /* !(10) */
    mer_scene_free(s);
}

/* Fig. 2.8a: 1 + 2(3^6 - 1) segments, the first F(200·1.109^6); each F(50)
 * with three branches hangs the third on a joint. */
static void test_ternary(void **state)
{
    (void)state;
    mer_scene *s = ls_scene(TERNARY, 90.0f, 1);
    step(s, 6);
    assert_true(model_stat(s, "segments") == 1457);
    assert_int_equal(live_segments(s), 1457);
    assert_true(fabs((double)node(s, 0).length - 200.0 * pow(1.109, 6)) < 1e-2);
    mer_scene_free(s);
}

/* More children than slots: a joint of length 0 at the tip carries the rest;
 * meshing and GLB work; pruning the branch on the joint lasts. */
static void test_joints(void **state)
{
    (void)state;
    mer_scene *s = ls_scene("axiom: F[+F][-F][&F][^F]F\n", 30.0f, 1);
    assert_int_equal(mer_scene_node_bound(s), 7);
    mer_node root = node(s, 0);
    assert_int_equal(root.lateral_child[0], 1);
    assert_int_equal(root.lateral_child[1], 2);
    mer_node joint = node(s, root.main_child);
    assert_float_equal(joint.length, 0.0f, 0.0f);
    assert_int_equal(joint.parent, 0);
    mer_node amp = node(s, joint.lateral_child[0]); /* &F */
    assert_true(amp.dir[2] < -0.4f);
    assert_int_equal(node(s, joint.main_child).order, 0);
    mer_mesh *m = NULL;
    mer_error err;
    assert_int_equal(mer_mesh_build(s, NULL, &m, &err), MER_OK);
    uint8_t *glb = NULL;
    size_t size = 0;
    assert_int_equal(mer_gltf_write_tree(m, NULL, NULL, &glb, &size, &err), MER_OK);
    mer_gltf_free(glb);
    mer_mesh_free(m);
    assert_int_equal(mer_scene_prune(s, amp.id, &err), MER_OK);
    step(s, 2);
    assert_true(model_stat(s, "segments") == 5);
    for (uint32_t i = 0; i < mer_scene_node_bound(s); i++)
        assert_false(node(s, i).dir[2] < -0.4f);
    mer_scene_free(s);
}

/* A pruned branch stays pruned: its apices are cut from the string. */
static void test_prune_lasts(void **state)
{
    (void)state;
    mer_scene *s = ls_scene(HONDA, 90.0f, 1);
    step(s, 3);
    mer_node b = node(s, 1); /* the first lateral, B's F */
    assert_int_equal(b.order, 1);
    mer_error err;
    assert_int_equal(mer_scene_prune(s, 1, &err), MER_OK);
    step(s, 2);
    /* 2^5 - 1 segments less the B subtree grown from step 1: 2^4 - 1. */
    assert_true(model_stat(s, "segments") == 31 - 15);
    mer_scene_free(s);
}

/* A bend lasts: the turn goes into the string before the module that drew the
 * node, so what grows later from it is turned too. */
static void test_bend_lasts(void **state)
{
    (void)state;
    mer_scene *s = ls_scene("axiom: A\nA -> FA\n", 90.0f, 1);
    step(s, 2);
    mer_error err;
    const float z[3] = {0, 0, 1};
    assert_int_equal(mer_scene_bend(s, 1, z, 90.0f, &err), MER_OK);
    mer_node bent = node(s, 1);
    assert_float_equal(bent.dir[0], -1.0f, 1e-5f);
    step(s, 1);
    assert_int_equal(mer_scene_node_bound(s), 3);
    for (uint32_t i = 1; i < 3; i++) {
        mer_node nd = node(s, i);
        assert_float_equal(nd.dir[0], -1.0f, 1e-4f);
        assert_float_equal(nd.dir[1], 0.0f, 1e-4f);
    }
    assert_float_equal(node(s, 2).base[0], -1.0f, 1e-4f);
    assert_float_equal(node(s, 2).base[1], 1.0f, 1e-4f);
    assert_float_equal(node(s, 0).dir[1], 1.0f, 0.0f);
    mer_scene_free(s);
}

/* ls_blocking: an obstacle stops a segment whose end it holds and the rest of
 * its branch, and the ground one that points down; off, both are drawn. */
static void test_blocking(void **state)
{
    (void)state;
    for (uint32_t on = 0; on < 2; on++) {
        mer_params p = mer_params_default();
        p.model = MER_MODEL_LSYSTEM;
        p.ls_blocking = on;
        mer_scene *s = NULL;
        mer_error err;
        assert_int_equal(mer_scene_new(&p, 1, &s, &err), MER_OK);
        const float lo[3] = {-1, 2.5f, -1}, hi[3] = {1, 4, 1};
        assert_int_equal(mer_scene_add_box(s, lo, hi, &err), MER_OK);
        static const char text[] = "axiom: [&(150)F]A\nA -> FA\n";
        assert_int_equal(mer_scene_set_definition(s, text, strlen(text), &err), MER_OK);
        step(s, 5);
        assert_true(model_stat(s, "segments") == (on ? 2 : 6));
        mer_scene_free(s);
    }
}

/* Fig. 1.27: the same seed gives the same plant, another seed another. */
static void test_stochastic_seeds(void **state)
{
    (void)state;
    mer_scene *a = ls_scene(STOCHASTIC, 20.0f, 5);
    mer_scene *b = ls_scene(STOCHASTIC, 20.0f, 5);
    mer_scene *c = ls_scene(STOCHASTIC, 20.0f, 6);
    step(a, 5);
    step(b, 5);
    step(c, 5);
    assert_true(mer_scene_hash(a) == mer_scene_hash(b));
    assert_true(mer_scene_hash(a) != mer_scene_hash(c));
    assert_true(model_stat(a, "segments") == model_stat(b, "segments"));
    mer_scene_free(a);
    mer_scene_free(b);
    mer_scene_free(c);
}

/* A refused text names its line and column and changes nothing. */
static void test_parse_error(void **state)
{
    (void)state;
    mer_scene *s = ls_scene(FIG_1_24A, 25.7f, 1);
    step(s, 1);
    uint64_t h = mer_scene_hash(s);
    static const char bad[] = "axiom: F\nF -> F[+F(]F\n";
    mer_error err;
    assert_int_equal(mer_scene_set_definition(s, bad, strlen(bad), &err), MER_ERR_INVALID);
    assert_string_equal(err.field, "definition");
    assert_int_equal(err.line, 2);
    assert_true(err.column > 0);
    assert_true(mer_scene_hash(s) == h);
    size_t len = 0;
    assert_string_equal(mer_scene_definition(s, &len), FIG_1_24A);
    assert_int_equal(len, strlen(FIG_1_24A));
    mer_scene_free(s);
    /* P09 takes no definition. */
    mer_scene *p = NULL;
    assert_int_equal(mer_scene_new(NULL, 1, &p, &err), MER_OK);
    assert_int_equal(mer_scene_set_definition(p, "axiom: F", 8, &err), MER_ERR_INVALID);
    assert_null(mer_scene_definition(p, NULL));
    mer_scene_free(p);
}

/* set_definition later keeps the string and changes the rules. */
static void test_new_rules_keep_string(void **state)
{
    (void)state;
    mer_scene *s = ls_scene("axiom: A\nA -> FA\n", 90.0f, 1);
    step(s, 2);
    static const char next[] = "A -> F[+F]A\n";
    mer_error err;
    assert_int_equal(mer_scene_set_definition(s, next, strlen(next), &err), MER_OK);
    assert_true(model_stat(s, "segments") == 2);
    step(s, 1);
    assert_true(model_stat(s, "segments") == 4);
    mer_scene_free(s);
}

static void assert_same_checkpoint(const mer_scene *a, const mer_scene *b)
{
    uint8_t *x = NULL, *y = NULL;
    size_t nx = 0, ny = 0;
    mer_error err;
    assert_int_equal(mer_scene_save(a, &x, &nx, &err), MER_OK);
    assert_int_equal(mer_scene_save(b, &y, &ny, &err), MER_OK);
    assert_int_equal(nx, ny);
    assert_memory_equal(x, y, nx);
    free(x);
    free(y);
}

/* clone, save and load give byte-identical checkpoints that grow on alike,
 * pending prunes and bends included. */
static void test_round_trips(void **state)
{
    (void)state;
    mer_scene *s = ls_scene(STOCHASTIC, 20.0f, 3);
    step(s, 2);
    mer_error err;
    const float x[3] = {1, 0, 0};
    assert_int_equal(mer_scene_bend(s, 2, x, 20.0f, &err), MER_OK);
    assert_int_equal(mer_scene_prune(s, 3, &err), MER_OK);
    mer_scene *c = NULL, *l = NULL;
    assert_int_equal(mer_scene_clone(s, &c, &err), MER_OK);
    uint8_t *bytes = NULL;
    size_t size = 0;
    assert_int_equal(mer_scene_save(s, &bytes, &size, &err), MER_OK);
    assert_int_equal(mer_scene_load(bytes, size, &l, &err), MER_OK);
    bytes[size - 1] ^= 1;
    mer_scene *bad = NULL;
    assert_int_equal(mer_scene_load(bytes, size, &bad, &err), MER_ERR_FORMAT);
    free(bytes);
    assert_same_checkpoint(s, c);
    assert_same_checkpoint(s, l);
    assert_true(mer_scene_hash(s) == mer_scene_hash(l));
    step(s, 2);
    step(c, 2);
    step(l, 2);
    assert_same_checkpoint(s, c);
    assert_same_checkpoint(s, l);
    assert_string_equal(mer_scene_definition(l, NULL), STOCHASTIC);
    mer_scene_free(s);
    mer_scene_free(c);
    mer_scene_free(l);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_algae),
        cmocka_unit_test(test_fig_1_24a),
        cmocka_unit_test(test_fig_1_24d),
        cmocka_unit_test(test_honda),
        cmocka_unit_test(test_ternary),
        cmocka_unit_test(test_joints),
        cmocka_unit_test(test_prune_lasts),
        cmocka_unit_test(test_bend_lasts),
        cmocka_unit_test(test_blocking),
        cmocka_unit_test(test_stochastic_seeds),
        cmocka_unit_test(test_parse_error),
        cmocka_unit_test(test_new_rules_keep_string),
        cmocka_unit_test(test_round_trips),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
