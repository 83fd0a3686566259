/* Unit tests for lib/models/lsystem/turtle.c: ABOP's turtle (§1.5, §1.6, §2.2),
 * its sign conventions, and the segment counts and heights of ABOP's trees. */
#include "config.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "models/lsystem/lsystem.h"

/* Derives `n` steps of `text` and interprets the string into `out`. */
static void grow(const char *text, int n, const merp_ls_turtle *tp, merp_ls_segs *out)
{
    merp_ls_error err;
    merp_lsys *ls = merp_lsys_parse(text, &err);
    if (!ls)
        fail_msg("refused at %d:%d: %s", err.line, err.col, err.msg);
    merp_lstr s;
    merp_lstr_init(&s);
    assert_int_equal(merp_lsys_run(ls, n, 1, &s), 0);
    memset(out, 0, sizeof *out);
    assert_int_equal(merp_ls_interpret(&s, tp, out), 0);
    merp_lstr_free(&s);
    merp_lsys_free(ls);
}

static void assert_near3(const float v[3], double x, double y, double z)
{
    if (fabs((double)v[0] - x) > 1e-5 || fabs((double)v[1] - y) > 1e-5 ||
        fabs((double)v[2] - z) > 1e-5)
        fail_msg("(%g, %g, %g), want (%g, %g, %g)", (double)v[0], (double)v[1],
                 (double)v[2], x, y, z);
}

/* The tip of the last drawn segment of `axiom` under the default turtle. */
static void tip_of(const char *axiom, const merp_ls_turtle *tp, double x, double y, double z)
{
    char text[128];
    snprintf(text, sizeof text, "axiom: %s\n", axiom);
    merp_ls_segs g;
    grow(text, 0, tp, &g);
    assert_true(g.n > 0);
    assert_near3(g.seg[g.n - 1].tip, x, y, z);
    merp_ls_segs_free(&g);
}

/* ABOP's signs: + left (towards -x), & down (towards -z), \ rolls L to U. */
static void test_sign_conventions(void **state)
{
    (void)state;
    merp_ls_turtle tp = merp_ls_turtle_default();
    tip_of("F", &tp, 0, 1, 0);
    tip_of("+F", &tp, -1, 0, 0);
    tip_of("-F", &tp, 1, 0, 0);
    tip_of("&F", &tp, 0, 0, -1);
    tip_of("^F", &tp, 0, 0, 1);
    tip_of("\\(90)+F", &tp, 0, 0, 1);
    tip_of("/(90)+F", &tp, 0, 0, -1);
    tip_of("|F", &tp, 0, -1, 0);
    tip_of("+(30)F(2)", &tp, -1, sqrt(3.0), 0);
    tip_of("fF", &tp, 0, 2, 0);
    tip_of("F[+F]F", &tp, 0, 2, 0);
}

/* $ rolls L horizontal (ABOP eq. 2.2): a left turn of 90° then stays level. */
static void test_roll_horizontal(void **state)
{
    (void)state;
    merp_ls_turtle tp = merp_ls_turtle_default();
    merp_ls_segs a, b;
    grow("axiom: &(30)\\(40)+F\n", 0, &tp, &a);
    grow("axiom: &(30)\\(40)$+F\n", 0, &tp, &b);
    assert_true(fabs((double)a.seg[0].tip[1]) > 0.1);
    assert_true(fabs((double)b.seg[0].tip[1]) < 1e-6);
    merp_ls_segs_free(&a);
    merp_ls_segs_free(&b);
}

/* Parents, orders, widths, colours from brackets, ! and '; % cuts a branch. */
static void test_branch_structure(void **state)
{
    (void)state;
    merp_ls_turtle tp = merp_ls_turtle_default();
    merp_ls_segs g;
    grow("axiom: !(3)F['(2)+!(1)F[-F]]F%F\n", 0, &tp, &g);
    assert_int_equal(g.n, 4);
    static const uint32_t parent[] = {UINT32_MAX, 0, 1, 0};
    static const uint16_t order[] = {0, 1, 2, 0};
    static const float width[] = {3, 1, 1, 3};
    static const uint16_t color[] = {0, 2, 2, 0};
    for (int i = 0; i < 4; i++) {
        assert_int_equal(g.seg[i].parent, parent[i]);
        assert_int_equal(g.seg[i].order, order[i]);
        assert_true(g.seg[i].width == width[i]);
        assert_int_equal(g.seg[i].color, color[i]);
    }
    assert_int_equal(g.seg[3].module, 12); /* the F after % is cut */
    merp_ls_segs_free(&g);
    grow("axiom: F[F%FF]F\n", 0, &tp, &g);
    assert_int_equal(g.n, 3);
    merp_ls_segs_free(&g);
}

/* ABOP §2.2: after a step H turns towards T by e|H × T| radians. */
static void test_tropism(void **state)
{
    (void)state;
    merp_ls_turtle tp = merp_ls_turtle_default();
    tp.tropism[0] = 1.0, tp.tropism[1] = 0.0, tp.tropism[2] = 0.0;
    tp.elasticity = 0.5;
    merp_ls_segs g;
    grow("axiom: FF\n", 0, &tp, &g);
    assert_near3(g.seg[1].tip, sin(0.5), 1.0 + cos(0.5), 0.0);
    merp_ls_segs_free(&g);
}

/* ABOP Fig. 1.24a (δ 25.7°): 5^5 segments, the main axis 3^5 unit steps high. */
static void test_fig_1_24a(void **state)
{
    (void)state;
    merp_ls_turtle tp = merp_ls_turtle_default();
    tp.delta = 25.7;
    merp_ls_segs g;
    grow("axiom: F\nF -> F[+F]F[-F]F\n", 5, &tp, &g);
    assert_int_equal(g.n, 3125);
    assert_near3(g.seg[g.n - 1].tip, 0, 243, 0);
    float top = 0;
    for (size_t i = 0; i < g.n; i++)
        top = g.seg[i].tip[1] > top ? g.seg[i].tip[1] : top;
    assert_true(top == g.seg[g.n - 1].tip[1]);
    merp_ls_segs_free(&g);
}

static const char honda[] =
    "#define r1 0.9\n#define r2 0.6\n#define a0 45\n#define a2 45\n"
    "#define d 137.5\n#define wr 0.707\n"
    "axiom: A(1,10)\n"
    "A(l,w) -> !(w)F(l)[&(a0)B(l*r2,w*wr)]/(d)A(l*r1,w*wr)\n"
    "B(l,w) -> !(w)F(l)[-(a2)$C(l*r2,w*wr)]C(l*r1,w*wr)\n"
    "C(l,w) -> !(w)F(l)[+(a2)$B(l*r2,w*wr)]B(l*r1,w*wr)\n";

/* ABOP Fig. 2.6a: 2^10 - 1 segments; a vertical trunk of 10 internodes whose tip
 * is at Σ_{i<10} 0.9^i; widths shrink by wr. */
static void test_honda_tree(void **state)
{
    (void)state;
    merp_ls_turtle tp = merp_ls_turtle_default();
    merp_ls_segs g;
    grow(honda, 10, &tp, &g);
    assert_int_equal(g.n, 1023);
    uint32_t trunk = UINT32_MAX;
    int ntrunk = 0;
    for (size_t i = 0; i < g.n; i++)
        if (g.seg[i].order == 0) {
            ntrunk++;
            if (trunk != UINT32_MAX)
                assert_int_equal(g.seg[i].parent, trunk);
            trunk = (uint32_t)i;
        }
    assert_int_equal(ntrunk, 10);
    assert_near3(g.seg[trunk].tip, 0, 6.5132156, 0);
    assert_true(fabs((double)g.seg[trunk].width - 10 * pow(0.707, 9)) < 1e-4);
    int below = 1;
    for (size_t i = 0; i < g.n; i++)
        below &= g.seg[i].tip[1] < 6.52f;
    assert_true(below);
    merp_ls_segs_free(&g);
}

/* ABOP Fig. 2.8a, the ternary tree with tropism T (0,-1,0), e 0.22: 1 + 2(3^6 - 1)
 * segments; the first is vertical, 200·1.109^6 long. */
static void test_ternary_tree(void **state)
{
    (void)state;
    merp_ls_turtle tp = merp_ls_turtle_default();
    tp.elasticity = 0.22;
    merp_ls_segs g;
    grow("#define d1 94.74\n#define d2 132.63\n#define a 18.95\n"
         "#define lr 1.109\n#define vr 1.732\n"
         "axiom: !(1)F(200)/(45)A\n"
         "A -> !(vr)F(50)[&(a)F(50)A]/(d1)[&(a)F(50)A]/(d2)[&(a)F(50)A]\n"
         "F(l) -> F(l*lr)\n!(w) -> !(w*vr)\n", 6, &tp, &g);
    assert_int_equal(g.n, 1457);
    assert_near3(g.seg[0].base, 0, 0, 0);
    assert_true(fabs((double)g.seg[0].tip[1] - 200 * pow(1.109, 6)) < 1e-3);
    assert_true(fabs((double)g.seg[0].width - pow(1.732, 6)) < 1e-3);
    int drooped = 0; /* tropism bends branches downwards */
    for (size_t i = 1; i < g.n; i++)
        drooped |= g.seg[i].tip[1] < g.seg[i].base[1];
    assert_true(drooped);
    merp_ls_segs_free(&g);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sign_conventions),
        cmocka_unit_test(test_roll_horizontal),
        cmocka_unit_test(test_branch_structure),
        cmocka_unit_test(test_tropism),
        cmocka_unit_test(test_fig_1_24a),
        cmocka_unit_test(test_honda_tree),
        cmocka_unit_test(test_ternary_tree),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
