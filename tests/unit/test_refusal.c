/* Unit tests for server/refusal.c and server/decode.c: every library result
 * maps to its documented problem, and the field helpers name the field at
 * fault with its JSON path. */
#include "config.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "server/decode.h"
#include "server/refusal.h"

static void test_library_results_map_once(void **state)
{
    (void)state;
    static const struct {
        mer_result rc;
        unsigned status;
        const char *slug;
    } want[] = {
        {MER_ERR_INVALID, 422, "invalid-field"}, {MER_ERR_RANGE, 422, "out-of-range"},
        {MER_ERR_NOMEM, 503, "out-of-memory"},   {MER_ERR_FORMAT, 422, "invalid-field"},
        {MER_ERR_LIMIT, 409, "limit"},           {MER_ERR_INTERNAL, 500, "internal"},
        {MER_ERR_NOT_FOUND, 404, "unknown-node"}, {MER_ERR_GONE, 409, "dead-node"},
        {MER_ERR_ROOT, 422, "root-node"},
    };
    for (size_t i = 0; i < sizeof want / sizeof want[0]; i++) {
        mer_error err = {.code = want[i].rc, .field = "node", .message = "why"};
        merd_refusal why = {0};
        assert_int_equal(merd_refuse_lib(&why, want[i].rc, &err, "edits[1]"), -1);
        assert_int_equal(why.status, want[i].status);
        assert_string_equal(why.slug, want[i].slug);
        assert_string_equal(why.field, "edits[1].node");
        assert_string_equal(why.detail, "why");
    }
    // A code the table does not know is a bad field, not a crash.
    mer_error err = {.field = "", .message = "?"};
    merd_refusal why = {0};
    merd_refuse_lib(&why, (mer_result)99, &err, "");
    assert_int_equal(why.status, 422);
    assert_string_equal(why.field, "");
}

static void test_paths_join(void **state)
{
    (void)state;
    char f[MERD_FIELD_MAX];
    merd_path(f, sizeof f, "edits[2]", "count");
    assert_string_equal(f, "edits[2].count");
    merd_path(f, sizeof f, "", "count");
    assert_string_equal(f, "count");
    merd_path(f, sizeof f, "scene.plants[0]", "");
    assert_string_equal(f, "scene.plants[0]");
    char tiny[6];
    merd_path(tiny, sizeof tiny, "edits", "count");
    assert_string_equal(tiny, "edits");
}

static void test_fields_are_checked(void **state)
{
    (void)state;
    json_t *o = json_pack("{s:s, s:i, s:[i, i, f], s:f}", "op", "bend", "node", 3, "axis", 0, 0, 2e6,
                          "angle", 10.0);
    merd_refusal why = {0};
    static const char *const fields[] = {"op", "node", "axis", NULL};
    assert_int_equal(merd_only_fields(o, fields, "a bend edit", "edits[0]", true, &why), -1);
    assert_int_equal(why.status, 400);
    assert_string_equal(why.field, "edits[0].angle");
    assert_string_equal(why.detail, "unknown field 'angle' in a bend edit; allowed: op, node, axis");
    uint64_t node = 0;
    assert_int_equal(merd_get_uint(o, "node", "", 0, 10, true, 0, &node, &why), 0);
    assert_int_equal(node, 3);
    assert_int_equal(merd_get_uint(o, "node", "", 5, 10, true, 0, &node, &why), -1);
    assert_string_equal(why.slug, "out-of-range");
    double x = 0;
    assert_int_equal(merd_get_number(o, "pressure", "", 0, 1, false, 0.5, &x, &why), 0);
    assert_true(x == 0.5);
    assert_int_equal(merd_get_number(o, "pressure", "e", 0, 1, true, 0.5, &x, &why), -1);
    assert_string_equal(why.slug, "missing-field");
    assert_string_equal(why.field, "e.pressure");
    float v[3];
    assert_int_equal(merd_get_vec3(o, "axis", "", true, v, &why), -1);
    assert_string_equal(why.slug, "out-of-range");
    assert_string_equal(why.detail, "axis must hold 3 numbers from -1e+06 to 1e+06");
    assert_int_equal(merd_vec3(json_object_get(o, "node"), "base", &merd_words_spec, v, &why), -1);
    assert_string_equal(why.detail, "base must be [x, y, z]");
    json_decref(o);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_library_results_map_once),
        cmocka_unit_test(test_paths_join),
        cmocka_unit_test(test_fields_are_checked),
    };
    return cmocka_run_group_tests_name("refusal", tests, NULL, NULL);
}
