/* Unit tests for how a refused edit is undone (server/edits.c merd_batch_undo):
 * never by replaying the session's journal, which costs every edit ever made
 * while the session is locked. One library call that changes nothing when
 * refused needs no undo; a step edit (its refusal may leave whole steps, or out
 * of memory a partial one) and a batch are undone from a copy taken before. */
#include "config.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <jansson.h>

#include "server/edits.h"

static merd_undo undo_of(const char *body)
{
    json_error_t jerr;
    json_t *doc = json_loads(body, 0, &jerr);
    assert_non_null(doc);
    const merd_edit_limits lim = {.max_steps = 100, .max_markers = 1000};
    merd_batch *b = NULL;
    merd_refusal why = {0};
    assert_int_equal(merd_batch_decode(doc, &lim, &b, &why), 0);
    merd_undo how = merd_batch_undo(b);
    merd_batch_free(b);
    json_decref(doc);
    return how;
}

static void test_single_step_is_undone_from_a_copy(void **state)
{
    (void)state;
    assert_int_equal(undo_of("{\"op\": \"step\"}"), MERD_UNDO_COPY);
    assert_int_equal(undo_of("{\"op\": \"step\", \"count\": 24}"), MERD_UNDO_COPY);
    assert_int_equal(undo_of("{\"edits\": [{\"op\": \"step\", \"count\": 2}]}"), MERD_UNDO_COPY);
}

static void test_no_batch_replays_the_journal(void **state)
{
    (void)state;
    static const char *const bodies[] = {
        "{\"op\": \"prune\", \"node\": 3}",
        "{\"op\": \"step\", \"count\": 5}",
        "{\"edits\": [{\"op\": \"step\"}, {\"op\": \"prune\", \"node\": 3}]}",
        "{\"edits\": [{\"op\": \"prune\", \"node\": 3}, {\"op\": \"prune\", \"node\": 4}]}",
    };
    for (size_t i = 0; i < sizeof bodies / sizeof bodies[0]; i++)
        assert_int_not_equal(undo_of(bodies[i]), MERD_UNDO_REPLAY);
    // One call that changes nothing when refused: nothing to copy.
    assert_int_equal(undo_of(bodies[0]), MERD_UNDO_NOTHING);
    assert_int_equal(undo_of(bodies[2]), MERD_UNDO_COPY);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_single_step_is_undone_from_a_copy),
        cmocka_unit_test(test_no_batch_replays_the_journal),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
