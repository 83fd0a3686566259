/* Unit tests for lib/models/lsystem: parsing cpfg text and deriving strings, with
 * fixtures from ABOP (Prusinkiewicz & Lindenmayer 1990) worked out by hand or
 * from closed forms. */
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

#include "models/lsystem/lsystem.h"

static merp_lsys *parse_ok(const char *text)
{
    merp_ls_error err;
    merp_lsys *ls = merp_lsys_parse(text, &err);
    if (!ls)
        fail_msg("refused at %d:%d: %s", err.line, err.col, err.msg);
    return ls;
}

/* Derives `n` steps of `text` with `seed` into `out` (initialised here). */
static void run(const char *text, int n, uint64_t seed, merp_lstr *out)
{
    merp_lsys *ls = parse_ok(text);
    merp_lstr_init(out);
    assert_int_equal(merp_lsys_run(ls, n, seed, out), 0);
    merp_lsys_free(ls);
}

static void assert_string(const merp_lstr *s, const char *want)
{
    char buf[512];
    merp_lstr_format(s, buf, sizeof buf);
    if (strcmp(buf, want) != 0)
        fail_msg("got %s, want %s", buf, want);
}

/* Modules with symbol `sym` at bracket depth 0, and the sum of their first
 * parameters (the main axis of a bracketed string). */
static size_t main_axis(const merp_lstr *s, merp_sym sym, double *length)
{
    size_t k = 0;
    int depth = 0;
    *length = 0.0;
    for (size_t i = 0; i < s->n; i++) {
        depth += (s->sym[i] == '[') - (s->sym[i] == ']');
        if (depth == 0 && s->sym[i] == sym) {
            k++;
            if (merp_lstr_np(s, i) > 0)
                *length += (double)s->par[s->poff[i]];
        }
    }
    return k;
}

/* ABOP §1.2: the algae DOL system; lengths are the Fibonacci numbers. */
static void test_algae(void **state)
{
    (void)state;
    const char *text = "axiom: A\nA -> AB\nB -> A\n";
    static const size_t lengths[] = {1, 2, 3, 5, 8, 13};
    for (int n = 0; n <= 5; n++) {
        merp_lstr s;
        run(text, n, 1, &s);
        assert_int_equal(s.n, lengths[n]);
        if (n == 5)
            assert_string(&s, "ABAABABAABAAB");
        merp_lstr_free(&s);
    }
}

/* ABOP Fig. 1.24a: F -> F[+F]F[-F]F, n = 5: 5^5 F, 3^5 on the main axis. */
static void test_fig_1_24a(void **state)
{
    (void)state;
    merp_lstr s;
    run("/* Fig. 1.24a */\nlsystem: 1\nderivation length: 5\n"
        "axiom: F\nF -> F[+F]F[-F]F\nendlsystem\n", 5, 1, &s);
    double len;
    assert_int_equal(merp_lstr_count(&s, 'F'), 3125);
    assert_int_equal(main_axis(&s, 'F', &len), 243);
    merp_lstr_free(&s);
}

/* ABOP Fig. 1.24d: X -> F[+X]F[-X]+X, F -> FF, n = 7: f(n+1) = 2f(n) + 2·3^n. */
static void test_fig_1_24d(void **state)
{
    (void)state;
    merp_lstr s;
    run("axiom: X\nX --> F[+X]F[-X]+X\nF --> FF\n", 7, 1, &s);
    assert_int_equal(merp_lstr_count(&s, 'F'), 4118);
    assert_int_equal(merp_lstr_count(&s, 'X'), 2187);
    merp_lstr_free(&s);
}

/* ABOP §1.8, Fig. 1.25 text: in ABC[DE][SG[HI[JK]L]MNO], BC < S > G[H]M applies
 * to S: the left context skips the sibling [DE] and steps into the parent; the
 * right context enters [H and skips the rest of that branch. */
static void test_context_with_brackets(void **state)
{
    (void)state;
    static const struct { const char *prod; const char *want; } cases[] = {
        {"BC < S > G[H]M -> X", "ABC[DE][XG[HI[JK]L]MNO]"},
        {"C < S -> X", "ABC[DE][XG[HI[JK]L]MNO]"},
        {"E < S -> X", "ABC[DE][SG[HI[JK]L]MNO]"},      /* sibling branch */
        {"S > GM -> X", "ABC[DE][XG[HI[JK]L]MNO]"},     /* child skipped */
        {"S > GH -> X", "ABC[DE][SG[HI[JK]L]MNO]"},
        {"G < M -> X", "ABC[DE][SG[HI[JK]L]XNO]"},      /* branch skipped */
        {"L < M -> X", "ABC[DE][SG[HI[JK]L]MNO]"},
        {"H > I[J]L -> X", "ABC[DE][SG[XI[JK]L]MNO]"},
        {"O > N -> X", "ABC[DE][SG[HI[JK]L]MNO]"},      /* end of branch */
        {"A < D -> X", "ABC[DE][SG[HI[JK]L]MNO]"},      /* C is nearer */
        {"B < C > [DE] -> X", "ABX[DE][SG[HI[JK]L]MNO]"},
        {"* < K > * -> X", "ABC[DE][SG[HI[JX]L]MNO]"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char text[128];
        snprintf(text, sizeof text, "axiom: ABC[DE][SG[HI[JK]L]MNO]\n%s\n", cases[i].prod);
        merp_lstr s;
        run(text, 1, 1, &s);
        char buf[128];
        merp_lstr_format(&s, buf, sizeof buf);
        if (strcmp(buf, cases[i].want) != 0)
            fail_msg("%s: got %s, want %s", cases[i].prod, buf, cases[i].want);
        merp_lstr_free(&s);
    }
}

/* ABOP §1.8: an acropetal signal b < a -> b through branches; the ignore list
 * lets it pass the turning symbols. */
static void test_signal_with_ignore(void **state)
{
    (void)state;
    const char *with = "ignore: + -\naxiom: b[+a]a[-a]a\nb < a -> b\nb -> a\n";
    static const char *want[] = {"b[+a]a[-a]a", "a[+b]b[-a]a", "a[+a]a[-b]b",
                                 "a[+a]a[-a]a"};
    for (int n = 0; n <= 3; n++) {
        merp_lstr s;
        run(with, n, 1, &s);
        assert_string(&s, want[n]);
        merp_lstr_free(&s);
    }
    merp_lstr s;
    run("axiom: b[+a]a[-a]a\nb < a -> b\nb -> a\n", 1, 1, &s);
    assert_string(&s, "a[+a]b[-a]a");
    merp_lstr_free(&s);
    run("consider: ab\naxiom: b[+a]a[-a]a\nb < a -> b\nb -> a\n", 1, 1, &s);
    assert_string(&s, "a[+b]b[-a]a");
    merp_lstr_free(&s);
}

/* ABOP §1.10, Fig. 1.33's derivation of a parametric L-system with conditions. */
static void test_parametric_conditions(void **state)
{
    (void)state;
    const char *text = "axiom: B(2)A(4,4)\n"
                       "A(x,y) : y <= 3 -> A(x*2, x+y)\n"
                       "A(x,y) : y > 3 -> B(x)A(x/y, 0)\n"
                       "B(x) : x < 1 -> C\n"
                       "B(x) : x >= 1 -> B(x-1)\n";
    static const char *want[] = {"B(2)A(4,4)", "B(1)B(4)A(1,0)", "B(0)B(3)A(2,1)",
                                 "CB(2)A(4,3)", "CB(1)A(8,7)"};
    for (int n = 0; n <= 4; n++) {
        merp_lstr s;
        run(text, n, 1, &s);
        assert_string(&s, want[n]);
        merp_lstr_free(&s);
    }
}

static const char honda[] =
    "/* ABOP Fig. 2.6a: a monopodial tree after Honda */\n"
    "#define r1 0.9\n#define r2 0.6\n#define a0 45\n#define a2 45\n"
    "#define d 137.5\n#define wr 0.707\n"
    "derivation length: 10\naxiom: A(1,10)\n"
    "A(l,w) : * -> !(w)F(l)[&(a0)B(l*r2,w*wr)]/(d)A(l*r1,w*wr)\n"
    "B(l,w) -> !(w)F(l)[-(a2)$C(l*r2,w*wr)]C(l*r1,w*wr)\n"
    "C(l,w) -> !(w)F(l)[+(a2)$B(l*r2,w*wr)]B(l*r1,w*wr)\n";

/* Honda's tree: 2^10 - 1 internodes, the trunk sum of 0.9^i for i < 10. */
static void test_honda_tree(void **state)
{
    (void)state;
    merp_lsys *ls = parse_ok(honda);
    assert_int_equal(merp_lsys_derivation_length(ls), 10);
    assert_int_equal(merp_lsys_nprod(ls), 3);
    merp_lstr s;
    merp_lstr_init(&s);
    assert_int_equal(merp_lsys_run(ls, 10, 1, &s), 0);
    assert_int_equal(merp_lstr_count(&s, 'F'), 1023);
    double len;
    assert_int_equal(main_axis(&s, 'F', &len), 10);
    assert_true(fabs(len - 6.5132156) < 1e-5);
    merp_lstr_free(&s);
    merp_lsys_free(ls);
}

/* ABOP Fig. 2.8a, the ternary tree: 1 + 2(3^6 - 1) F at n = 6, the first one
 * F(200·1.109^6). */
static void test_ternary_tree(void **state)
{
    (void)state;
    merp_lstr s;
    run("#define d1 94.74\n#define d2 132.63\n#define a 18.95\n"
        "#define lr 1.109\n#define vr 1.732\n"
        "axiom: !(1)F(200)/(45)A\n"
        "A : * -> !(vr)F(50)[&(a)F(50)A]/(d1)[&(a)F(50)A]/(d2)[&(a)F(50)A]\n"
        "F(l) : * -> F(l*lr)\n!(w) : * -> !(w*vr)\n", 6, 1, &s);
    assert_int_equal(merp_lstr_count(&s, 'F'), 1457);
    assert_int_equal(s.sym[1], 'F');
    assert_true(fabs((double)s.par[s.poff[1]] - 200.0 * pow(1.109, 6)) < 1e-3);
    merp_lstr_free(&s);
}

static const char stochastic[] = "axiom: F\n"
                                 "F -> F[+F]F[-F]F : 0.33\n"
                                 "F -> F[+F]F : 0.33\n"
                                 "F -> F[-F]F : 0.34\n";

/* ABOP §1.7 (Fig. 1.27): the same seed gives the same plant, another seed
 * another. */
static void test_stochastic_determinism(void **state)
{
    (void)state;
    merp_lstr a, b, c;
    run(stochastic, 5, 7, &a);
    run(stochastic, 5, 7, &b);
    run(stochastic, 5, 8, &c);
    assert_int_equal(a.n, b.n);
    assert_memory_equal(a.sym, b.sym, a.n * sizeof *a.sym);
    assert_true(a.n != c.n || memcmp(a.sym, c.sym, a.n * sizeof *a.sym) != 0);
    merp_lstr_free(&a);
    merp_lstr_free(&b);
    merp_lstr_free(&c);
}

/* Weights give the proportions, and a module's choice depends on its index only
 * (not on what the other modules are). */
static void test_stochastic_weights(void **state)
{
    (void)state;
    merp_lsys *ls = parse_ok("axiom: A\nA -> B : 1\nA -> C : 3\nA -> D : 0\n");
    merp_lstr in, mixed, out, out2;
    merp_lstr_init(&in);
    merp_lstr_init(&mixed);
    merp_lstr_init(&out);
    merp_lstr_init(&out2);
    const size_t n = 40000;
    for (size_t i = 0; i < n; i++) {
        assert_int_equal(merp_lstr_push(&in, 'A', NULL, 0), 0);
        assert_int_equal(merp_lstr_push(&mixed, i % 2 ? 'E' : 'A', NULL, 0), 0);
    }
    assert_int_equal(merp_lsys_derive(ls, &in, &out, 99, 4), 0);
    size_t nb = merp_lstr_count(&out, 'B'), nc = merp_lstr_count(&out, 'C');
    assert_int_equal(nb + nc, n);
    assert_int_equal(merp_lstr_count(&out, 'D'), 0);
    assert_true(fabs((double)nb / n - 0.25) < 0.01);
    assert_int_equal(merp_lsys_derive(ls, &mixed, &out2, 99, 4), 0);
    for (size_t i = 0; i < n; i += 2)
        assert_int_equal(out.sym[i], out2.sym[i]);
    merp_lstr_free(&in);
    merp_lstr_free(&mixed);
    merp_lstr_free(&out);
    merp_lstr_free(&out2);
    merp_lsys_free(ls);
}

static void expect_error(const char *text, int line, int col)
{
    merp_ls_error err;
    merp_lsys *ls = merp_lsys_parse(text, &err);
    if (ls)
        fail_msg("accepted: %s", text);
    if (err.line != line || err.col != col)
        fail_msg("%d:%d (%s), want %d:%d", err.line, err.col, err.msg, line, col);
}

static void test_parse_errors(void **state)
{
    (void)state;
    expect_error("axiom: A\nA -> B(1+)\n", 2, 10);
    expect_error("axiom: A\n\nA B C\n", 3, 1);
    expect_error("#define x 2\naxiom: F(y)\n", 2, 10);
    expect_error("axiom: A\n/* a comment\n spanning */ A(x) : x < 1 -> B(z)\n", 3, 32);
    expect_error("axiom: A(1\n", 1, 9);
    expect_error("axiom: A\n  AB -> C\n", 2, 3);
    expect_error("axiom: A\nA -> B : -1\n", 2, 9);
    expect_error("derivation length: x\n", 1, 20);
    expect_error("axiom: A\nA(1x) -> B\n", 2, 3);
}

/* Unbalanced brackets are accepted, as cpfg accepts them, each with a warning
 * at its bracket: a '[' never closed, a ']' that closes nothing. A balanced
 * text has none. */
static void test_bracket_warnings(void **state)
{
    (void)state;
    const merp_ls_error *w;
    merp_lsys *ls = parse_ok("axiom: F\nF -> F[+F[-F]\n");
    assert_int_equal(merp_lsys_warnings(ls, &w), 1);
    assert_int_equal(w[0].line, 2);
    assert_int_equal(w[0].col, 7); /* the outer '[', never closed */
    assert_non_null(strstr(w[0].msg, "never closed"));
    merp_lsys_free(ls);

    ls = parse_ok("axiom: F]F\nF -> F[+F]]\n");
    assert_int_equal(merp_lsys_warnings(ls, &w), 2);
    assert_int_equal(w[0].line, 1);
    assert_int_equal(w[0].col, 9);
    assert_int_equal(w[1].line, 2);
    assert_int_equal(w[1].col, 11);
    assert_non_null(strstr(w[1].msg, "closes no"));
    merp_lsys_free(ls);

    ls = parse_ok("axiom: F\nF -> F[+F][-F(2)]F\n");
    assert_int_equal(merp_lsys_warnings(ls, &w), 0);
    merp_lsys_free(ls);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_algae),
        cmocka_unit_test(test_fig_1_24a),
        cmocka_unit_test(test_fig_1_24d),
        cmocka_unit_test(test_context_with_brackets),
        cmocka_unit_test(test_signal_with_ignore),
        cmocka_unit_test(test_parametric_conditions),
        cmocka_unit_test(test_honda_tree),
        cmocka_unit_test(test_ternary_tree),
        cmocka_unit_test(test_stochastic_determinism),
        cmocka_unit_test(test_stochastic_weights),
        cmocka_unit_test(test_parse_errors),
        cmocka_unit_test(test_bracket_warnings),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
