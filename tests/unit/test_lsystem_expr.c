/* Unit tests for lib/models/lsystem/expr.c: the arithmetic of parametric
 * L-systems (ABOP §1.10), its precedence, functions, errors and random draws. */
#include "config.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "models/lsystem/lsystem.h"

static const merp_ls_name names[] = {
    {"k", -1, 10.0},
    {"x", 0, 0.0},
    {"y", 1, 0.0},
};
static const double vars[] = {2.0, 3.0};

static double eval(const char *src)
{
    merp_ls_error err;
    merp_expr *e = merp_expr_compile(src, strlen(src), names, 3, 1, 1, &err);
    if (!e)
        fail_msg("'%s' refused: %s at %d", src, err.msg, err.col);
    double v = merp_expr_eval(e, vars, NULL);
    merp_expr_free(e);
    return v;
}

static void test_table(void **state)
{
    (void)state;
    static const struct { const char *src; double want; } table[] = {
        {"1+2*3", 7},          {"(1+2)*3", 9},       {"2^3^2", 512},
        {"-2^2", -4},          {"10/4", 2.5},        {"k-x-y", 5},
        {"x*y+k", 16},         {"x*-y", -6},         {"x<y", 1},
        {"x>=y", 0},           {"x==2", 1},          {"x!=2", 0},
        {"x<=2", 1},           {"x>2", 0},           {"1+2>2", 1},
        {"x<y && y<x", 0},     {"x<y || y<x", 1},    {"!(x<y)", 0},
        {"!0", 1},             {"1 || 0 && 0", 1},   {"sqrt(16)", 4},
        {"sin(30)", 0.5},      {"cos(60)", 0.5},     {"tan(45)", 1},
        {"atan2(1,1)", 45},    {"exp(0)", 1},        {"log(exp(2))", 2},
        {"floor(2.7)", 2},     {"floor(-2.5)", -3},  {" 1.5e1 ", 15},
        {".5*4", 2},           {"abs(-3)", 3},       {"ran(1)*0", 0},
    };
    for (size_t i = 0; i < sizeof table / sizeof table[0]; i++) {
        double v = eval(table[i].src);
        if (fabs(v - table[i].want) > 1e-12)
            fail_msg("%s = %g, want %g", table[i].src, v, table[i].want);
    }
}

static void expect_error(const char *src, int col0, int col)
{
    merp_ls_error err;
    memset(&err, 0, sizeof err);
    merp_expr *e = merp_expr_compile(src, strlen(src), names, 3, 7, col0, &err);
    if (e)
        fail_msg("'%s' accepted", src);
    assert_int_equal(err.line, 7);
    if (err.col != col)
        fail_msg("'%s': column %d (%s), want %d", src, err.col, err.msg, col);
}

static void test_errors_carry_columns(void **state)
{
    (void)state;
    expect_error("1 + * 2", 5, 9);
    expect_error("foo(1)", 1, 1);
    expect_error("x + z", 3, 7);
    expect_error("sqrt(1,2)", 1, 1);
    expect_error("(1+2", 1, 5);
    expect_error("1 2", 1, 3);
    expect_error("", 4, 4);
}

static void test_constant_folding_flag(void **state)
{
    (void)state;
    merp_ls_error err;
    merp_expr *a = merp_expr_compile("k*2", 3, names, 3, 1, 1, &err);
    merp_expr *b = merp_expr_compile("x*2", 3, names, 3, 1, 1, &err);
    merp_expr *c = merp_expr_compile("ran(2)", 6, names, 3, 1, 1, &err);
    assert_non_null(a);
    assert_non_null(b);
    assert_non_null(c);
    assert_true(merp_expr_is_constant(a));
    assert_false(merp_expr_is_constant(b));
    assert_false(merp_expr_is_constant(c));
    merp_expr_free(a);
    merp_expr_free(b);
    merp_expr_free(c);
}

static void test_random_draws_are_keyed(void **state)
{
    (void)state;
    merp_ls_error err;
    merp_expr *r = merp_expr_compile("ran(2)", 6, names, 3, 1, 1, &err);
    merp_expr *g = merp_expr_compile("nran(5, 2)", 10, names, 3, 1, 1, &err);
    assert_non_null(r);
    assert_non_null(g);
    double sum = 0, gsum = 0, gsq = 0;
    const int n = 20000;
    for (int i = 0; i < n; i++) {
        merp_ls_rand a = {merp_ls_key(42, 3, (uint64_t)i), 0};
        merp_ls_rand b = {merp_ls_key(42, 3, (uint64_t)i), 0};
        double v = merp_expr_eval(r, vars, &a);
        assert_true(v >= 0.0 && v < 2.0);
        assert_true(v == merp_expr_eval(r, vars, &b)); /* same key, same draw */
        sum += v;
        double w = merp_expr_eval(g, vars, &a);
        gsum += w;
        gsq += w * w;
    }
    assert_true(fabs(sum / n - 1.0) < 0.02);
    double mean = gsum / n, sd = sqrt(gsq / n - mean * mean);
    assert_true(fabs(mean - 5.0) < 0.05);
    assert_true(fabs(sd - 2.0) < 0.05);
    merp_ls_rand s1 = {merp_ls_key(1, 0, 0), 0}, s2 = {merp_ls_key(2, 0, 0), 0};
    merp_ls_rand t1 = {merp_ls_key(1, 1, 0), 0};
    double u1 = merp_ls_uniform(&s1), u2 = merp_ls_uniform(&s2);
    assert_true(u1 != u2);
    assert_true(u1 != merp_ls_uniform(&t1));
    merp_expr_free(r);
    merp_expr_free(g);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_table),
        cmocka_unit_test(test_errors_carry_columns),
        cmocka_unit_test(test_constant_folding_flag),
        cmocka_unit_test(test_random_draws_are_keyed),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
