/* Graphically defined functions (G04 §4; lpfg's function editor): the B-spline
 * and linear kinds on hand-made fixtures, their checks, and the .func and .fset
 * text formats — reading, writing, round trips, and errors with line and column. */
#include "config.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "models/inverse/gfunc.h"

static merp_gfunc *make(merp_gf_kind kind, uint32_t samples, const float (*xy)[2], uint32_t n)
{
    merp_gfunc *f = malloc(sizeof *f);
    mer_error err;
    if (merp_gfunc_make(f, "f", kind, samples, xy, n, &err) != MER_OK)
        fail_msg("merp_gfunc_make: %s", err.message);
    return f;
}

/* Control points on y = x give y = x, between samples too. */
static void test_line_gives_line(void **state)
{
    (void)state;
    const float xy[][2] = {{0, 0}, {0.2f, 0.2f}, {0.3f, 0.3f}, {0.7f, 0.7f}, {1, 1}};
    merp_gfunc *f = make(MERP_GF_BSPLINE, 11, xy, 5);
    for (int i = 0; i <= 100; i++) {
        float x = (float)i / 100.0f;
        assert_float_equal(merp_gfunc_eval(f, x), x, 1e-6f);
    }
    f->pts[2].m = 3; /* multiplicities keep the points on the line */
    assert_int_equal(merp_gfunc_prepare(f, NULL), MER_OK);
    for (int i = 0; i <= 100; i++)
        assert_float_equal(merp_gfunc_eval(f, (float)i / 100.0f), (float)i / 100.0f, 1e-6f);
    free(f);
}

/* (0,0), (0.25,1), (0.75,1), (1,0): one cubic Bézier segment, y(0.5) = 0.75; the
 * curve passes through its end points and stays below the polygon. */
static void test_arch(void **state)
{
    (void)state;
    const float xy[][2] = {{0, 0}, {0.25f, 1}, {0.75f, 1}, {1, 0}};
    merp_gfunc *f = make(MERP_GF_BSPLINE, 101, xy, 4);
    assert_float_equal(merp_gfunc_eval(f, 0.5f), 0.75f, 1e-6f);
    assert_float_equal(merp_gfunc_eval(f, 0.0f), 0.0f, 1e-7f);
    assert_float_equal(merp_gfunc_eval(f, 1.0f), 0.0f, 1e-7f);
    assert_float_equal(merp_gfunc_eval(f, 0.25f), merp_gfunc_eval(f, 0.75f), 1e-6f);
    float x, y;
    merp_gfunc_curve(f, 0.5f, &x, &y);
    assert_float_equal(x, 0.5f, 1e-6f);
    assert_float_equal(y, 0.75f, 1e-6f);
    /* Out of the domain: clamped. */
    assert_float_equal(merp_gfunc_eval(f, -3.0f), 0.0f, 1e-7f);
    assert_float_equal(merp_gfunc_eval(f, 7.0f), 0.0f, 1e-7f);
    /* Few samples: linear between them; 0.5 is still a sample of 3. */
    f->samples = 3;
    assert_int_equal(merp_gfunc_prepare(f, NULL), MER_OK);
    assert_float_equal(merp_gfunc_eval(f, 0.5f), 0.75f, 1e-6f);
    assert_float_equal(merp_gfunc_eval(f, 0.25f), 0.375f, 1e-6f);
    free(f);
}

/* A point of multiplicity 3 pulls the curve through it. */
static void test_multiplicity_interpolates(void **state)
{
    (void)state;
    const float xy[][2] = {{0, 0}, {0.5f, 1}, {1, 0}};
    merp_gfunc *f = make(MERP_GF_LINEAR, 2, xy, 3);
    f->kind = MERP_GF_BSPLINE;
    f->samples = 201;
    f->pts[1].m = 3;
    assert_int_equal(merp_gfunc_prepare(f, NULL), MER_OK);
    assert_float_equal(merp_gfunc_eval(f, 0.5f), 1.0f, 1e-5f);
    free(f);
}

/* The linear kind is the polygon, with vertical steps taken at once. */
static void test_linear(void **state)
{
    (void)state;
    const float xy[][2] = {{0, 0}, {0.5f, 1}, {0.5f, 2}, {1, 0}};
    merp_gfunc *f = make(MERP_GF_LINEAR, 2, xy, 4);
    assert_float_equal(merp_gfunc_eval(f, 0.25f), 0.5f, 1e-7f);
    assert_float_equal(merp_gfunc_eval(f, 0.75f), 1.0f, 1e-7f);
    assert_float_equal(merp_gfunc_eval(f, 0.5f), 2.0f, 1e-7f);
    free(f);
}

/* What prepare refuses, and why. */
static void test_checks(void **state)
{
    (void)state;
    merp_gfunc f;
    mer_error err;
    const float bad_x[][2] = {{0, 0}, {0.6f, 1}, {0.4f, 1}, {1, 0}};
    assert_int_equal(merp_gfunc_make(&f, "g", MERP_GF_BSPLINE, 10, bad_x, 4, &err),
                     MER_ERR_INVALID);
    assert_non_null(strstr(err.message, "point 3: x decreases"));
    const float not_to_one[][2] = {{0, 0}, {0.3f, 1}, {0.6f, 1}, {0.9f, 0}};
    assert_int_equal(merp_gfunc_make(&f, "g", MERP_GF_BSPLINE, 10, not_to_one, 4, &err),
                     MER_ERR_INVALID);
    assert_non_null(strstr(err.message, "x = 1"));
    const float three[][2] = {{0, 0}, {0.5f, 1}, {1, 0}};
    assert_int_equal(merp_gfunc_make(&f, "g", MERP_GF_BSPLINE, 10, three, 3, &err),
                     MER_ERR_INVALID);
    assert_non_null(strstr(err.message, "4 points"));
    assert_int_equal(merp_gfunc_make(&f, "g", MERP_GF_LINEAR, 10, three, 3, &err), MER_OK);
    assert_int_equal(merp_gfunc_make(&f, "g", MERP_GF_LINEAR, 1, three, 3, &err),
                     MER_ERR_INVALID);
    assert_string_equal(err.field, "samples");
    assert_int_equal(merp_gfunc_make(&f, "", MERP_GF_LINEAR, 10, three, 3, &err),
                     MER_ERR_INVALID);
    assert_string_equal(err.field, "name");
}

static const char arch_text[] = "fver 1 1\n"
                                "name: arch\n"
                                "samples: 101\n"
                                "flip: off\n"
                                "points: 4\n"
                                "0 0\n"
                                "0.25 1\n"
                                "0.75 1 2\n"
                                "1 0\n";

/* Reading a .func, writing it back byte for byte. */
static void test_func_round_trip(void **state)
{
    (void)state;
    merp_gfunc f, g;
    mer_error err;
    assert_int_equal(merp_func_read(arch_text, strlen(arch_text), &f, &err), MER_OK);
    assert_string_equal(f.name, "arch");
    assert_int_equal(f.samples, 101);
    assert_int_equal(f.npts, 4);
    assert_int_equal(f.pts[2].m, 2);
    assert_int_equal(f.kind, MERP_GF_BSPLINE);
    size_t need = merp_func_write(&f, NULL, 0);
    char *buf = malloc(need + 1);
    assert_int_equal(merp_func_write(&f, buf, need + 1), need);
    assert_string_equal(buf, arch_text);
    /* A short buffer is cut and terminated, and the length still told. */
    char small[10];
    assert_int_equal(merp_func_write(&f, small, sizeof small), need);
    assert_int_equal(strlen(small), 9);
    free(buf);

    /* Awkward floats, a flipped and a linear function survive the trip. */
    const float xy[][2] = {{0, 0.1f}, {1.0f / 3.0f, 0.7f}, {0.9999f, 1e-7f}, {1, -2.5f}};
    assert_int_equal(merp_gfunc_make(&f, "G_s2", MERP_GF_LINEAR, 7, xy, 4, &err), MER_OK);
    f.flip = 1;
    need = merp_func_write(&f, NULL, 0);
    buf = malloc(need + 1);
    merp_func_write(&f, buf, need + 1);
    assert_non_null(strstr(buf, "flip: on\nkind: linear\npoints: 4\n0.100000001 0\n"));
    assert_int_equal(merp_func_read(buf, need, &g, &err), MER_OK);
    assert_true(merp_gfunc_equal(&f, &g));
    free(buf);
}

/* A gallery of three functions round-trips; blank lines and spaces are fine. */
static void test_fset_round_trip(void **state)
{
    (void)state;
    const char text[] = "funcgalleryver 1 1\n"
                        "items: 2\n"
                        "\n"
                        "fver 1 1\n"
                        "name:   one\n"
                        "samples: 5\n"
                        "flip: off\n"
                        "points: 4\n"
                        "  0 0 \n"
                        "0.3 0.3\n"
                        "0.6 0.6\n"
                        "1 1\n"
                        "fver 1 1\n"
                        "name: two\n"
                        "samples: 20\n"
                        "flip: on\n"
                        "points: 4\n"
                        "1 0\n"
                        "0 0.5\n"
                        "0 0.6\n"
                        "1 1\n";
    merp_gfunc fs[4], back[4];
    uint32_t n = 0, m = 0;
    mer_error err;
    assert_int_equal(merp_fset_read(text, strlen(text), fs, 4, &n, &err), MER_OK);
    assert_int_equal(n, 2);
    assert_string_equal(fs[1].name, "two");
    assert_true(fs[1].flip);
    assert_float_equal(fs[1].pts[1].x, 0.5f, 0.0f); /* flipped: "y x" */
    assert_float_equal(fs[1].pts[0].y, 1.0f, 0.0f);
    assert_float_equal(merp_gfunc_eval(&fs[0], 0.4f), 0.4f, 1e-6f);
    size_t need = merp_fset_write(fs, n, NULL, 0);
    char *buf = malloc(need + 1);
    merp_fset_write(fs, n, buf, need + 1);
    assert_int_equal(merp_fset_read(buf, need, back, 4, &m, &err), MER_OK);
    assert_int_equal(m, 2);
    for (uint32_t i = 0; i < n; i++)
        assert_true(merp_gfunc_equal(&fs[i], &back[i]));
    /* More items than room. */
    assert_int_equal(merp_fset_read(buf, need, back, 1, &m, &err), MER_ERR_LIMIT);
    free(buf);
}

static void expect_error(const char *text, mer_result code, const char *where, const char *what)
{
    merp_gfunc f;
    mer_error err;
    mer_result rc = merp_func_read(text, strlen(text), &f, &err);
    if (rc != code)
        fail_msg("for %s: got %d (%s), want %d", text, rc, err.message, code);
    if (strncmp(err.message, where, strlen(where)) != 0 || strstr(err.message, what) == NULL)
        fail_msg("for %s: got \"%s\", want \"%s...%s\"", text, err.message, where, what);
}

/* Errors say where: line and column. */
static void test_errors_name_line_and_column(void **state)
{
    (void)state;
    expect_error("", MER_ERR_FORMAT, "line 1, column 1:", "expected \"fver\"");
    expect_error("fver 2 1\n", MER_ERR_FORMAT, "line 1, column 6:", "whole number");
    expect_error("fver 1 1\nname: a\nsamples: x\n", MER_ERR_FORMAT, "line 3, column 10:",
                 "whole number");
    expect_error("fver 1 1\nname: a\nsamples: 9\nflip: maybe\n", MER_ERR_FORMAT,
                 "line 4, column 7:", "on or off");
    expect_error("fver 1 1\nname: a\nsamples: 9\nflip: off\npoints: 4\n0 0\n0.5 zz\n",
                 MER_ERR_FORMAT, "line 7, column 5:", "a number");
    expect_error("fver 1 1\nname: a\nsamples: 9\nflip: off\npoints: 4\n0 0\n0.5 1\n",
                 MER_ERR_FORMAT, "line 7,", "found the end after 2");
    expect_error("fver 1 1\nname: a\nsamples: 9\nflip: off\npoints: 2\n0 0 1 7\n",
                 MER_ERR_FORMAT, "line 6, column 7:", "unexpected text");
    /* Parsed, but not a function: reported at the points line. */
    expect_error("fver 1 1\nname: a\nsamples: 9\nflip: off\npoints: 4\n0 0\n0.7 1\n0.5 1\n1 0\n",
                 MER_ERR_INVALID, "line 5, column 1:", "x decreases");
    expect_error("fver 1 1\nname: a\nsamples: 9\nflip: off\nkind: cubic\n", MER_ERR_FORMAT,
                 "line 5, column 7:", "linear or bspline");
    expect_error("fver 1 1\nname: a\nsamples: 9\nflip: off\nkind: linear\npoints: 2\n0 0\n1 1\n"
                 "more\n",
                 MER_ERR_FORMAT, "line 9, column 1:", "after the last point");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_line_gives_line),
        cmocka_unit_test(test_arch),
        cmocka_unit_test(test_multiplicity_interpolates),
        cmocka_unit_test(test_linear),
        cmocka_unit_test(test_checks),
        cmocka_unit_test(test_func_round_trip),
        cmocka_unit_test(test_fset_round_trip),
        cmocka_unit_test(test_errors_name_line_and_column),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
