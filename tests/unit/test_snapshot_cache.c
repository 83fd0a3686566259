/* Unit tests for server/snapshot.c: the per-session cache keeps a few variants
 * of the current revision, drops the least recently used one and every stale
 * revision, and shares bytes by reference. */
#include "config.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "server/snapshot.h"

static merd_snapshot *snapshot(size_t size)
{
    uint8_t *bytes = malloc(size);
    assert_non_null(bytes);
    memset(bytes, (int)size, size);
    merd_snapshot *s = merd_snapshot_new(bytes, size);
    assert_non_null(s);
    return s;
}

static size_t size_of(merd_snapshot *s)
{
    size_t size = 0;
    merd_snapshot_bytes(s, &size);
    return size;
}

static void test_variants_live_together(void **state)
{
    (void)state;
    merd_snapshot_cache c = {0};
    const char *keys[] = {"a", "b", "c", "d", "e"};
    for (size_t i = 0; i < MERD_SNAPSHOT_VARIANTS; i++) {
        merd_snapshot *s = snapshot(i + 1);
        merd_snapshot_cache_put(&c, 7, keys[i], s);
        merd_snapshot_release(s);
    }
    for (size_t i = 0; i < MERD_SNAPSHOT_VARIANTS; i++) {
        merd_snapshot *s = merd_snapshot_cache_get(&c, keys[i]);
        assert_non_null(s);
        assert_int_equal(size_of(s), i + 1);
        merd_snapshot_release(s);
    }
    // "a" was asked for least recently: a fifth variant takes its place.
    merd_snapshot_release(merd_snapshot_cache_get(&c, "b"));
    merd_snapshot *e = snapshot(9);
    merd_snapshot_cache_put(&c, 7, "e", e);
    assert_null(merd_snapshot_cache_get(&c, "a"));
    merd_snapshot *b = merd_snapshot_cache_get(&c, "b");
    assert_non_null(b);
    // A new revision drops every variant of the old one; references outlive it.
    merd_snapshot *f = snapshot(3);
    merd_snapshot_cache_put(&c, 8, "f", f);
    assert_null(merd_snapshot_cache_get(&c, "b"));
    assert_null(merd_snapshot_cache_get(&c, "e"));
    assert_int_equal(size_of(b), 2);
    assert_int_equal(size_of(e), 9);
    merd_snapshot_release(b);
    merd_snapshot_release(e);
    merd_snapshot_release(f);
    merd_snapshot_cache_clear(&c);
    assert_null(merd_snapshot_cache_get(&c, "f"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_variants_live_together),
    };
    return cmocka_run_group_tests_name("snapshot_cache", tests, NULL, NULL);
}
