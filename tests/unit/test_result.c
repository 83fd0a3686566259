/* Unit tests for lib/result.c: error records as the server will copy them. */
#include "config.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include <meristem/result.h>
#include <meristem/version.h>

static void test_error_set_fills_and_returns(void **state)
{
    (void)state;
    mer_error err;
    mer_error_clear(&err);
    assert_int_equal(err.code, MER_OK);
    assert_int_equal(mer_error_set(&err, MER_ERR_RANGE, "edits[0].count",
                                   "count must be from %d to %d, got %d", 1, 1000, 0),
                     MER_ERR_RANGE);
    assert_int_equal(err.code, MER_ERR_RANGE);
    assert_string_equal(err.field, "edits[0].count");
    assert_string_equal(err.message, "count must be from 1 to 1000, got 0");
    assert_int_equal(mer_error_set(NULL, MER_ERR_NOMEM, NULL, "ignored"), MER_ERR_NOMEM);
}

static void test_error_truncates_long_messages(void **state)
{
    (void)state;
    mer_error err;
    char longer[2 * MER_ERROR_MESSAGE_MAX];
    memset(longer, 'x', sizeof longer - 1);
    longer[sizeof longer - 1] = '\0';
    mer_error_set(&err, MER_ERR_INVALID, longer, "%s", longer);
    assert_int_equal(strlen(err.message), MER_ERROR_MESSAGE_MAX - 1);
    assert_int_equal(strlen(err.field), MER_ERROR_FIELD_MAX - 1);
}

static void test_result_names(void **state)
{
    (void)state;
    assert_string_equal(mer_result_name(MER_OK), "ok");
    assert_string_equal(mer_result_name(MER_ERR_LIMIT), "limit");
    assert_string_equal(mer_result_name((mer_result)999), "unknown");
    assert_string_equal(mer_version(), PACKAGE_VERSION);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_error_set_fills_and_returns),
        cmocka_unit_test(test_error_truncates_long_messages),
        cmocka_unit_test(test_result_names),
    };
    return cmocka_run_group_tests_name("result", tests, NULL, NULL);
}
