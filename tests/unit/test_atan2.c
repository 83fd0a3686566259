/* The fast arctangent (core/atan2.h) against libm's, in double. */
#include "config.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "core/atan2.h"

#define TOLERANCE 4e-7 /* rad: the header's promise */

/* The error against atan2 in double, the branch cut at ±π folded: the
 * polynomial may return π where atan2 gives −π for a y of −0. */
static double error_at(float y, float x)
{
    double d = fabs((double)merp_atan2f(y, x) - atan2((double)y, (double)x));
    return d > M_PI ? fabs(d - 2.0 * M_PI) : d;
}

/* A dense turn at several radii, each octant's edges (the axes, the
 * diagonals, where the polynomial's argument is 0 or 1) and a sweep of
 * ratios near 0 and near 1. */
static void within_tolerance_all_round(void **state)
{
    (void)state;
    static const float radii[] = {1e-6f, 1e-2f, 0.37f, 1.0f, 29.0f, 4e4f};
    double worst = 0.0;
    for (size_t r = 0; r < sizeof radii / sizeof *radii; r++)
        for (int i = 0; i < 100000; i++) {
            double a = -M_PI + 2.0 * M_PI * (i + 0.5) / 100000.0;
            float x = (float)((double)radii[r] * cos(a)), y = (float)((double)radii[r] * sin(a));
            worst = fmax(worst, error_at(y, x));
        }
    static const float edges[][2] = {{0, 1}, {1, 0}, {0, -1}, {-1, 0}, {1, 1}, {1, -1}, {-1, 1}, {-1, -1},
                                     {-0.0f, 1}, {0, -0.0f + 1e-30f}, {3, 3.0000002f}};
    for (size_t k = 0; k < sizeof edges / sizeof *edges; k++)
        worst = fmax(worst, error_at(edges[k][0], edges[k][1]));
    for (int i = 0; i <= 1000; i++) {
        float t = (float)i / 1000.0f;
        worst = fmax(worst, error_at(t * 1e-3f, 1.0f));
        worst = fmax(worst, error_at(1.0f - t * 1e-3f, -1.0f));
    }
    print_message("worst error %.3g rad\n", worst);
    assert_true(worst <= TOLERANCE);
}

/* Each quadrant maps where atan2 maps it; on the branch cut and at the
 * origin, what the header says. */
static void quadrants_and_the_cut(void **state)
{
    (void)state;
    assert_true(merp_atan2f(0.0f, 0.0f) == 0.0f);
    assert_true(merp_atan2f(1.0f, 2.0f) > 0.0f && merp_atan2f(1.0f, 2.0f) < (float)M_PI_2);
    assert_true(merp_atan2f(2.0f, -1.0f) > (float)M_PI_2 && merp_atan2f(2.0f, -1.0f) < (float)M_PI);
    assert_true(merp_atan2f(-2.0f, -1.0f) < -(float)M_PI_2 && merp_atan2f(-2.0f, -1.0f) > -(float)M_PI);
    assert_true(merp_atan2f(-1.0f, 2.0f) < 0.0f && merp_atan2f(-1.0f, 2.0f) > -(float)M_PI_2);
    assert_true(merp_atan2f(0.0f, -1.0f) == (float)M_PI);
    assert_true(merp_atan2f(-0.0f, -1.0f) == (float)M_PI);
    assert_true(merp_atan2f(1.0f, 0.0f) == (float)M_PI_2 && merp_atan2f(-1.0f, 0.0f) == -(float)M_PI_2);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(within_tolerance_all_round),
        cmocka_unit_test(quadrants_and_the_cut),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
