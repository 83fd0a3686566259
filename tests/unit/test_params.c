/* Unit tests for lib/params.c: defaults, ranges, schedules. */
#include "config.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include <meristem/params.h>

#define assert_close(a, b) assert_true(fabsf((float)(a) - (float)(b)) < 1e-5f)

static void test_defaults_are_the_papers(void **state)
{
    (void)state;
    mer_params p = mer_params_default();
    assert_int_equal(mer_params_validate(&p, NULL), MER_OK);
    assert_close(p.theta, 90.0f);   /* θ ≈ 90° */
    assert_close(p.rho, 2.0f);      /* ρ = 2 internode lengths */
    assert_close(p.r, 4.0f);        /* r = 4 to 6 */
    assert_close(p.alpha, 2.0f);    /* α = 2, Fig. 7 */
    assert_close(p.lambda, 0.5f);
    assert_close(p.w_min, 0.006f);  /* Fig. 9 */
    assert_close(p.kappa, 0.5f);
    assert_close(p.divergence, 137.5f);
    assert_int_equal(p.q_max, 6);
    assert_close(p.pipe_n, 2.5f);
    assert_close(p.shed_threshold, 0.0f); /* off */
    assert_int_equal(p.schedule.apical_off[0], MER_NEVER);
    assert_close(p.schedule.eta_order_scale[3], 1.0f);
}

static void test_all_zero_and_null_mean_defaults(void **state)
{
    (void)state;
    mer_params zero, out;
    memset(&zero, 0, sizeof zero);
    assert_int_equal(mer_params_validate(&zero, NULL), MER_OK);
    assert_int_equal(mer_params_validate(NULL, NULL), MER_OK);
    mer_params_resolve(&zero, &out);
    mer_params d = mer_params_default();
    assert_memory_equal(&out, &d, sizeof d);
    mer_params_resolve(NULL, &out);
    assert_memory_equal(&out, &d, sizeof d);
    /* A struct that is not all zero is taken as given: ρ = 0 is then out of range. */
    mer_params partly = zero;
    partly.lambda = 0.5f;
    mer_error err;
    assert_int_equal(mer_params_validate(&partly, &err), MER_ERR_RANGE);
}

static void test_set_checks_range_and_names_field(void **state)
{
    (void)state;
    mer_params p = mer_params_default();
    mer_error err;
    assert_int_equal(mer_params_set(&p, "lambda", 0.54, &err), MER_OK);
    assert_close(p.lambda, 0.54f);
    assert_int_equal(mer_params_set(&p, "lambda", 1.5, &err), MER_ERR_RANGE);
    assert_string_equal(err.field, "lambda");
    assert_string_equal(err.message, "lambda must be in [0, 1], got 1.5");
    assert_close(p.lambda, 0.54f); /* unchanged */
    assert_int_equal(mer_params_set(&p, "rho", 0.0, &err), MER_ERR_RANGE);
    assert_string_equal(err.message, "rho must be in (0, 100], got 0");
    assert_int_equal(mer_params_set(&p, "q_max", 4.5, &err), MER_ERR_RANGE);
    assert_string_equal(err.message, "q_max must be an integer from 0 to 32, got 4.5");
    assert_int_equal(mer_params_set(&p, "nope", 1.0, &err), MER_ERR_INVALID);
    assert_string_equal(err.field, "nope");
    assert_int_equal(mer_params_set(&p, "bounds_min.y", -5.0, &err), MER_OK);
    assert_close(p.bounds_min[1], -5.0f);
    assert_int_equal(mer_params_set(&p, "apical_off.1", 12, &err), MER_OK);
    assert_int_equal(p.schedule.apical_off[1], 12);
    double v;
    assert_int_equal(mer_params_get(&p, "apical_off.1", &v, &err), MER_OK);
    assert_close(v, 12.0);
    assert_int_equal(mer_params_get(NULL, "theta", &v, &err), MER_OK);
    assert_close(v, 90.0);
    /* Every field has a name, and its default lies in its range. */
    for (size_t i = 0; i < mer_params_field_count(); i++) {
        double lo, hi, d;
        mer_params_field_range(i, &lo, &hi);
        assert_int_equal(mer_params_get(NULL, mer_params_field_name(i), &d, NULL), MER_OK);
        assert_true(d >= lo && d <= hi);
        assert_non_null(mer_params_field_symbol(i));
    }
    assert_null(mer_params_field_name(mer_params_field_count()));
}

static void test_cross_field_rules(void **state)
{
    (void)state;
    mer_params p = mer_params_default();
    mer_error err;
    p.w_min = 2.0f;
    assert_int_equal(mer_params_validate(&p, &err), MER_ERR_RANGE);
    assert_string_equal(err.field, "w_min");
    p = mer_params_default();
    p.bounds_max[1] = p.bounds_min[1];
    assert_int_equal(mer_params_validate(&p, &err), MER_ERR_RANGE);
    assert_string_equal(err.field, "bounds_max.y");
    p = mer_params_default();
    p.voxel = 0.05f; /* 2000³ voxels */
    assert_int_equal(mer_params_validate(&p, &err), MER_ERR_LIMIT);
    assert_string_equal(err.field, "voxel");
    p = mer_params_default();
    p.schedule.lambda_key_count = 2;
    p.schedule.lambda_keys[0] = (mer_keyframe){10.0f, 0.5f};
    p.schedule.lambda_keys[1] = (mer_keyframe){5.0f, 0.5f};
    assert_int_equal(mer_params_validate(&p, &err), MER_ERR_RANGE);
    assert_string_equal(err.field, "schedule.lambda_keys");
}

static void test_schedules(void **state)
{
    (void)state;
    mer_params p = mer_params_default();
    /* λ: 0.54 until step 10, down to 0.46 at step 30 */
    p.schedule.lambda_key_count = 2;
    p.schedule.lambda_keys[0] = (mer_keyframe){10.0f, 0.54f};
    p.schedule.lambda_keys[1] = (mer_keyframe){30.0f, 0.46f};
    assert_close(mer_params_lambda_at(&p, 0), 0.54f);
    assert_close(mer_params_lambda_at(&p, 20), 0.50f);
    assert_close(mer_params_lambda_at(&p, 25), 0.48f);
    assert_close(mer_params_lambda_at(&p, 99), 0.46f);
    p.schedule.lambda_key_count = 0;
    assert_close(mer_params_lambda_at(&p, 20), 0.5f);
    /* η by time and order */
    p.eta = 0.2f;
    p.schedule.eta_order_scale[1] = -1.0f;
    assert_close(mer_params_eta_at(&p, 5, 0), 0.2f);
    assert_close(mer_params_eta_at(&p, 5, 1), -0.2f);
    assert_close(mer_params_eta_at(&p, 5, 100), 0.2f); /* orders past the table: last entry */
    /* apical control ends at the scheduled step, per order */
    p.schedule.apical_off[0] = 7;
    p.schedule.apical_off[MER_ORDERS_MAX - 1] = 3;
    assert_true(mer_params_apical_at(&p, 6, 0));
    assert_false(mer_params_apical_at(&p, 7, 0));
    assert_true(mer_params_apical_at(&p, 1000, 1));
    assert_true(mer_params_apical_at(&p, 2, 50));
    assert_false(mer_params_apical_at(&p, 3, 50));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_defaults_are_the_papers),
        cmocka_unit_test(test_all_zero_and_null_mean_defaults),
        cmocka_unit_test(test_set_checks_range_and_names_field),
        cmocka_unit_test(test_cross_field_rules),
        cmocka_unit_test(test_schedules),
    };
    return cmocka_run_group_tests_name("params", tests, NULL, NULL);
}
