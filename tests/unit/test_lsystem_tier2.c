/* Unit tests for tier 2 of cpfg's L-system language in lib/models/lsystem:
 * decomposition and homomorphism with their maximum depth, and the query
 * modules ?P and ?E answered by the turtle and the scene's environment. The
 * expected strings and counts are worked out by hand in the comments. */
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

#include <meristem/params.h>
#include <meristem/scene.h>

#include "core/alloc.h"
#include "models/lsystem/lsystem.h"
#include "scene_helpers.h"

static merp_lsys *parse_ok(const char *text)
{
    merp_ls_error err;
    merp_lsys *ls = merp_lsys_parse(text, &err);
    if (!ls)
        fail_msg("refused at %d:%d: %s", err.line, err.col, err.msg);
    return ls;
}

static void assert_string(const merp_lstr *s, const char *want)
{
    char buf[512];
    merp_lstr_format(s, buf, sizeof buf);
    if (strcmp(buf, want) != 0)
        fail_msg("got %s, want %s", buf, want);
}

/* The string of `text` after `n` steps, as text. */
static void assert_run(const char *text, int n, const char *want)
{
    merp_lsys *ls = parse_ok(text);
    merp_lstr s;
    merp_lstr_init(&s);
    assert_int_equal(merp_lsys_run(ls, n, 7, &s), 0);
    assert_string(&s, want);
    merp_lstr_free(&s);
    merp_lsys_free(ls);
}

/* A module I that decomposes into a bracketed whorl F[+F][-F] each step; the
 * decomposed F are in the string, so the next step rewrites them (F -> G):
 *   n = 1: IA decomposed:             F[+F][-F]A
 *   n = 2: G[+G][-G] IA decomposed:   G[+G][-G]F[+F][-F]A */
static void test_decomposition(void **state)
{
    (void)state;
    static const char text[] = "axiom: A\nA -> IA\nF -> G\n"
                               "decomposition\nI -> F[+F][-F]\nendlsystem\n";
    assert_run(text, 0, "A");
    assert_run(text, 1, "F[+F][-F]A");
    assert_run(text, 2, "G[+G][-G]F[+F][-F]A");
}

/* Recursion to the maximum depth, then truncation (cpfg leaves the module):
 * A -> FA applied to the axiom three times gives FFFA; the default depth is 1.
 * A condition ends a recursion earlier: A(3) -> F A(2) -> ... -> FFFA(0). */
static void test_maximum_depth(void **state)
{
    (void)state;
    assert_run("axiom: A\ndecomposition\nmaximum depth: 3\nA -> FA\n", 0, "FFFA");
    assert_run("axiom: A\ndecomposition\nA -> FA\n", 0, "FA");
    assert_run("axiom: A(3)\ndecomposition\nmaximum depth: 10\nA(n) : n > 0 -> FA(n-1)\n", 0,
               "FFFA(0)");
    /* One step later the decomposition starts again from the derived string. */
    assert_run("axiom: A\nA -> AB\ndecomposition\nmaximum depth: 2\nA -> FA\n", 1, "FFFFAB");
}

/* The homomorphism rewrites only what the turtle reads: the string keeps its
 * I, the view has F[+F]F for each, and the map names the I that gave them;
 * at depth 2, I -> FI gives FFI (truncated). */
static void test_homomorphism(void **state)
{
    (void)state;
    merp_lsys *ls = parse_ok("axiom: IIA\nhomomorphism\nI -> F[+F]F\n");
    merp_lstr s, view;
    merp_lstr_init(&s);
    merp_lstr_init(&view);
    assert_int_equal(merp_lsys_run(ls, 0, 1, &s), 0);
    assert_string(&s, "IIA");
    uint32_t *map = NULL;
    assert_int_equal(merp_lsys_homomorphism(ls, &s, &view, &map, 1, 0), 0);
    assert_string(&view, "F[+F]FF[+F]FA");
    assert_int_equal(map[0], 0 | MERP_LS_PRODUCED);
    assert_int_equal(map[5], 0 | MERP_LS_PRODUCED);
    assert_int_equal(map[6], 1 | MERP_LS_PRODUCED);
    assert_int_equal(map[12], 2); /* A, not rewritten */
    merp_free(map);
    merp_lsys_free(ls);

    ls = parse_ok("axiom: I\nhomomorphism\nmaximum depth: 2\nI -> FI\n");
    assert_int_equal(merp_lsys_run(ls, 0, 1, &s), 0);
    assert_int_equal(merp_lsys_homomorphism(ls, &s, &view, &map, 1, 0), 0);
    assert_string(&view, "FFI");
    merp_free(map);
    merp_lsys_free(ls);
    merp_lstr_free(&s);
    merp_lstr_free(&view);
}

/* ?P: F(1)+F(1) with δ 90 ends at (-1, 1, 0) (+ turns H = +y towards L = -x).
 * The interpretation writes it into ?P; the next step reads it:
 * A > ?P(x,y,z) -> B(x,y,z) gives F(1)+F(1)B(-1,1,0)?P(-1,1,0). */
static void test_query_position(void **state)
{
    (void)state;
    merp_lsys *ls = parse_ok("axiom: F(1)+F(1)A?P(0,0,0)\nA > ?P(x,y,z) -> B(x,y,z)\n");
    assert_true(merp_lsys_has_queries(ls));
    merp_lstr s, next;
    merp_lstr_init(&s);
    merp_lstr_init(&next);
    assert_int_equal(merp_lstr_copy(&s, merp_lsys_axiom(ls)), 0);
    merp_ls_turtle tp = merp_ls_turtle_default();
    merp_ls_segs segs = {0};
    merp_ls_query q = {.par = s.par, .origin = {0, 0, 0}};
    assert_int_equal(merp_ls_interpret_query(&s, &tp, &q, &segs), 0);
    assert_int_equal(segs.n, 2);
    assert_string(&s, "F(1)+F(1)A?P(-1,1,0)");
    assert_int_equal(merp_lsys_derive(ls, &s, &next, 1, 0), 0);
    assert_string(&next, "F(1)+F(1)B(-1,1,0)?P(-1,1,0)");
    /* ?H ?L ?U: the frame (unturned: exact); the origin is added to ?P. */
    merp_lsys_free(ls);
    ls = parse_ok("axiom: F(2)?H(0,0,0)?L(0,0,0)?U(0,0,0)?P(0,0,0)\n");
    assert_int_equal(merp_lstr_copy(&s, merp_lsys_axiom(ls)), 0);
    q = (merp_ls_query){.par = s.par, .origin = {10, 0, 0}};
    assert_int_equal(merp_ls_interpret_query(&s, &tp, &q, &segs), 0);
    assert_string(&s, "F(2)?H(0,1,0)?L(-1,0,0)?U(0,0,1)?P(10,2,0)");
    merp_ls_segs_free(&segs);
    merp_lstr_free(&s);
    merp_lstr_free(&next);
    merp_lsys_free(ls);
}

static void assert_refused(const char *text, int line, int col, const char *what)
{
    merp_ls_error err;
    merp_lsys *ls = merp_lsys_parse(text, &err);
    if (ls) {
        merp_lsys_free(ls);
        fail_msg("accepted: %s", text);
    }
    if (err.line != line || err.col != col || !strstr(err.msg, what))
        fail_msg("%s: got %d:%d %s, want %d:%d %s", text, err.line, err.col, err.msg, line, col,
                 what);
}

static void test_parse_errors(void **state)
{
    (void)state;
    assert_refused("axiom: A\ndecomposition\nB < A -> F\n", 3, 1, "context in a decomposition");
    assert_refused("axiom: A\nhomomorphism\n  A > B -> F\n", 3, 5, "context in a homomorphism");
    assert_refused("axiom: A\nmaximum depth: 3\n", 2, 1, "outside");
    assert_refused("axiom: A\nhomomorphism\nmaximum depth: 0\n", 3, 16, "bad maximum depth");
    assert_refused("axiom: A\nhomomorphism\nmaximum depth: 2.5\n", 3, 16, "bad maximum depth");
    assert_refused("axiom: A\nhomomorphism\ndecomposition\n", 3, 1, "before the homomorphism");
    assert_refused("axiom: A\ndecomposition\ndecomposition\n", 3, 1, "started before");
    assert_refused("axiom: A\ndecomposition now\n", 2, 15, "unexpected text");
    assert_refused("axiom: A\nhomomorphism\nA -> F(\n", 3, 7, "unclosed");
}

/* ---- through the scene: the environment answers, the skeleton is drawn ---- */

static mer_scene *ls_scene(const char *text, int blocking)
{
    mer_params p = mer_params_default();
    p.model = MER_MODEL_LSYSTEM;
    p.ls_blocking = (uint32_t)blocking;
    return new_defined_scene(&p, 1, text);
}

/* The homomorphism draws F[+F]F for every I; the string holds no F. After 5
 * steps of A -> IA: 5 I, 15 segments. */
static void test_scene_homomorphism(void **state)
{
    (void)state;
    mer_scene *s = ls_scene("axiom: A\nA -> IA\nhomomorphism\nI -> F[+F]F\n", 0);
    step(s, 5);
    assert_true(model_stat(s, "modules.I") == 5);
    assert_true(model_stat(s, "modules.F") == -1);
    assert_true(model_stat(s, "string_length") == 6);
    assert_true(model_stat(s, "segments") == 15);
    mer_summary sum;
    mer_scene_summary(s, &sum);
    assert_int_equal(sum.internodes, 15);
    mer_scene_free(s);
}

/* ?P bounds growth: the apex grows F(1) while the ?P after it says y < 3.5;
 * after steps 1..4 it stands at y = 1, 2, 3, 4 and stops: 4 segments. */
static void test_scene_position_bound(void **state)
{
    (void)state;
    mer_scene *s = ls_scene("axiom: A?P(0,0,0)\nA > ?P(x,y,z) : y < 3.5 -> F(1)A\n", 0);
    step(s, 10);
    assert_true(model_stat(s, "segments") == 4);
    mer_scene_free(s);
}

/* ?E(Q, o): a box from y = 3.5 up holds the apex at y = 4, where o turns 1 and
 * the production stops: 4 segments, though 10 steps were asked for. With the
 * box moved aside, the same text grows 10. */
static void test_scene_environment(void **state)
{
    (void)state;
    static const char text[] = "axiom: A?E(0,0)\nA > ?E(q,o) : o == 0 -> F(1)A\n";
    const float lo[3] = {-1, 3.5f, -1}, hi[3] = {1, 10, 1};
    const float lo2[3] = {5, 3.5f, -1}, hi2[3] = {7, 10, 1};
    mer_error err;
    for (int k = 0; k < 2; k++) {
        mer_scene *s = ls_scene(text, 0);
        if (mer_scene_add_box(s, k ? lo2 : lo, k ? hi2 : hi, &err) != MER_OK)
            fail_msg("box: %s", err.message);
        step(s, 10);
        assert_true(model_stat(s, "segments") == (k ? 10 : 4));
        mer_scene_free(s);
    }
}

/* Stochastic decomposition is drawn from the seed: the same seed, the same
 * string, whatever else happened. */
static void test_scene_determinism(void **state)
{
    (void)state;
    static const char text[] = "axiom: A\nA -> IA\ndecomposition\n"
                               "I -> F[+F] : 1\nI -> F[-F]F : 1\n";
    mer_scene *a = ls_scene(text, 0), *b = ls_scene(text, 0);
    step(a, 6);
    step(b, 3);
    mer_scene *c = NULL;
    mer_error err;
    assert_int_equal(mer_scene_clone(b, &c, &err), MER_OK);
    step(b, 3);
    step(c, 3);
    assert_true(mer_scene_hash(a) == mer_scene_hash(b));
    assert_true(mer_scene_hash(a) == mer_scene_hash(c));
    mer_scene_free(a);
    mer_scene_free(b);
    mer_scene_free(c);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_decomposition),
        cmocka_unit_test(test_maximum_depth),
        cmocka_unit_test(test_homomorphism),
        cmocka_unit_test(test_query_position),
        cmocka_unit_test(test_parse_errors),
        cmocka_unit_test(test_scene_homomorphism),
        cmocka_unit_test(test_scene_position_bound),
        cmocka_unit_test(test_scene_environment),
        cmocka_unit_test(test_scene_determinism),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
