/* Unit tests for lib/presets.c: every preset is valid and grows. The paper's claims
 * about form (Figs. 7, 9, 10, 14) are measured in test_forms.c. */
#include "config.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include <meristem/edit.h>
#include <meristem/presets.h>
#include <meristem/scene.h>

#define SEEDS 8

static mer_scene *grow(const char *name, const mer_params *p, uint64_t seed, uint32_t steps)
{
    mer_scene *s = NULL;
    mer_error err;
    if (mer_scene_new(p, seed, &s, &err) != MER_OK)
        fail_msg("new: %s", err.message);
    const char *text = mer_preset_definition(name);
    if (text != NULL && mer_scene_set_definition(s, text, strlen(text), &err) != MER_OK)
        fail_msg("%s: line %u, column %u: %s", name, err.line, err.column, err.message);
    if (mer_scene_step(s, steps, NULL, NULL, NULL, NULL, &err) != MER_OK)
        fail_msg("step: %s", err.message);
    return s;
}

static void test_every_preset_grows(void **state)
{
    (void)state;
    assert_true(mer_preset_count() >= 20);
    for (size_t i = 0; i < mer_preset_count(); i++) {
        const char *name = mer_preset_name(i);
        assert_non_null(mer_preset_description(i));
        mer_params p;
        assert_int_equal(mer_preset_params(name, &p, NULL), MER_OK);
        assert_int_equal(mer_params_validate(&p, NULL), MER_OK);
        mer_scene *s = grow(name, &p, 1, 20);
        if (strcmp(name, "fig15-brushed") == 0) {
            /* the sketched stem, then two heavy dabs for the crown (Fig. 15c, d) */
            mer_brush dab = {{0, 15, 0}, 6.0f, 1.0f, 400};
            assert_int_equal(mer_scene_brush(s, &dab, NULL, NULL, NULL), MER_OK);
            dab.center[1] = 20.0f;
            assert_int_equal(mer_scene_brush(s, &dab, NULL, NULL, NULL), MER_OK);
            assert_int_equal(mer_scene_step(s, 15, NULL, NULL, NULL, NULL, NULL), MER_OK);
        }
        mer_summary m;
        mer_scene_summary(s, &m);
        print_message("# %s: %u internodes, height %.1f, width %.1f\n", name, m.internodes,
                      (double)m.height, (double)m.crown_width);
        if (strcmp(name, "abop-1.2-algae") == 0) /* a string, no drawing */
            assert_int_equal(m.internodes, 0);
        else if (m.internodes < 60 || m.height < 5.0f || m.crown_width < 2.0f)
            fail_msg("preset %s: %u internodes, height %g, width %g", name, m.internodes,
                     (double)m.height, (double)m.crown_width);
        mer_scene_free(s);
    }
    mer_params p;
    mer_error err;
    assert_int_equal(mer_preset_params("fig99", &p, &err), MER_ERR_INVALID);
    assert_string_equal(err.field, "preset");
    assert_null(mer_preset_name(mer_preset_count()));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_preset_grows),
    };
    return cmocka_run_group_tests_name("presets", tests, NULL, NULL);
}
