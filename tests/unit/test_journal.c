/* Unit tests for server/journal.c: records survive reopening, a torn or
 * corrupt tail is dropped whole and cut off, appends go on after it. */
#include "config.h"

#include <fcntl.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmocka.h>

#include "server/journal.h"

typedef struct seen {
    size_t count;
    char text[16][64];
} seen;

static int collect(void *ctx, size_t index, const char *payload, size_t size)
{
    seen *s = ctx;
    assert_int_equal(index, s->count);
    assert_true(size < sizeof s->text[0]);
    memcpy(s->text[s->count], payload, size);
    s->text[s->count][size] = '\0';
    s->count++;
    return 0;
}

static char dir[64];
static char path[128];

static int setup(void **state)
{
    (void)state;
    snprintf(dir, sizeof dir, "/tmp/meristem-journal-XXXXXX");
    assert_non_null(mkdtemp(dir));
    snprintf(path, sizeof path, "%s/s.journal", dir);
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    unlink(path);
    rmdir(dir);
    return 0;
}

static off_t file_size(void)
{
    struct stat st;
    assert_int_equal(stat(path, &st), 0);
    return st.st_size;
}

static merd_journal *write_three(void)
{
    char error[MERD_JOURNAL_ERROR_MAX];
    merd_journal *j = merd_journal_create(path, "{\"create\":1}", 12, MERD_FSYNC_ALWAYS, error);
    assert_non_null(j);
    assert_int_equal(merd_journal_append(j, "{\"rev\":1}", 9, error), 0);
    assert_int_equal(merd_journal_append(j, "{\"rev\":2}", 9, error), 0);
    assert_int_equal(merd_journal_records(j), 3);
    return j;
}

static void test_records_survive_reopening(void **state)
{
    (void)state;
    merd_journal_close(write_three(), false);
    assert_int_equal(file_size(), 3 * 8 + 12 + 9 + 9);
    seen s = {0};
    size_t dropped = 99;
    char error[MERD_JOURNAL_ERROR_MAX];
    merd_journal *j = merd_journal_open(path, MERD_FSYNC_ALWAYS, collect, &s, &dropped, error);
    assert_non_null(j);
    assert_int_equal(s.count, 3);
    assert_int_equal(dropped, 0);
    assert_string_equal(s.text[0], "{\"create\":1}");
    assert_string_equal(s.text[2], "{\"rev\":2}");
    assert_int_equal(merd_journal_append(j, "{\"rev\":3}", 9, error), 0);
    merd_journal_close(j, false);
    memset(&s, 0, sizeof s);
    j = merd_journal_open(path, MERD_FSYNC_ALWAYS, collect, &s, NULL, error);
    assert_int_equal(s.count, 4);
    merd_journal_close(j, true);
    assert_int_equal(access(path, F_OK), -1);  // removed
}

/* A power cut in the middle of the last write: any prefix of its bytes. */
static void test_torn_tail_is_dropped_whole(void **state)
{
    (void)state;
    merd_journal_close(write_three(), false);
    off_t whole = file_size();
    for (off_t cut = 1; cut < 8 + 9; cut++) {
        merd_journal_close(NULL, false);
        assert_int_equal(truncate(path, whole - cut), 0);
        seen s = {0};
        size_t dropped = 0;
        char error[MERD_JOURNAL_ERROR_MAX];
        merd_journal *j = merd_journal_open(path, MERD_FSYNC_ALWAYS, collect, &s, &dropped, error);
        assert_non_null(j);
        assert_int_equal(s.count, 2);  // the torn third record is not replayed
        assert_int_equal(dropped, (size_t)(8 + 9 - cut));
        assert_int_equal(file_size(), whole - 8 - 9);  // cut back to a boundary
        // Appending again restores a third, whole record.
        assert_int_equal(merd_journal_append(j, "{\"rev\":2}", 9, error), 0);
        merd_journal_close(j, false);
        assert_int_equal(file_size(), whole);
    }
}

static void test_corrupt_record_ends_the_journal(void **state)
{
    (void)state;
    merd_journal_close(write_three(), false);
    int fd = open(path, O_WRONLY);
    assert_true(fd >= 0);
    // Flip a byte inside the second record's payload.
    assert_int_equal(pwrite(fd, "X", 1, 8 + 12 + 8 + 3), 1);
    close(fd);
    seen s = {0};
    size_t dropped = 0;
    char error[MERD_JOURNAL_ERROR_MAX];
    merd_journal *j = merd_journal_open(path, MERD_FSYNC_ALWAYS, collect, &s, &dropped, error);
    assert_non_null(j);
    assert_int_equal(s.count, 1);
    assert_int_equal(dropped, 8 + 9 + 8 + 9);
    merd_journal_close(j, true);
}

static int refuse_second(void *ctx, size_t index, const char *payload, size_t size)
{
    (void)ctx;
    (void)payload;
    (void)size;
    return index == 1;
}

static void test_errors(void **state)
{
    (void)state;
    char error[MERD_JOURNAL_ERROR_MAX];
    merd_journal_close(write_three(), false);
    // Creating over an existing journal is refused.
    assert_null(merd_journal_create(path, "x", 1, MERD_FSYNC_ALWAYS, error));
    assert_non_null(strstr(error, "cannot create"));
    // A replay callback can stop the open.
    assert_null(merd_journal_open(path, MERD_FSYNC_ALWAYS, refuse_second, NULL, NULL, error));
    assert_non_null(strstr(error, "record 1"));
    // An empty file holds no whole record.
    assert_int_equal(truncate(path, 0), 0);
    assert_null(merd_journal_open(path, MERD_FSYNC_ALWAYS, NULL, NULL, NULL, error));
    assert_non_null(strstr(error, "no whole record"));
    unlink(path);
    assert_null(merd_journal_open(path, MERD_FSYNC_ALWAYS, NULL, NULL, NULL, error));
}

static void test_interval_mode_syncs_on_demand(void **state)
{
    (void)state;
    char error[MERD_JOURNAL_ERROR_MAX];
    merd_journal *j = merd_journal_create(path, "{}", 2, MERD_FSYNC_INTERVAL, error);
    assert_non_null(j);
    assert_int_equal(merd_journal_append(j, "{\"rev\":1}", 9, error), 0);
    assert_int_equal(merd_journal_sync(j), 0);
    assert_int_equal(file_size(), 8 + 2 + 8 + 9);  // written at once, synced later
    merd_journal_close(j, true);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_records_survive_reopening, setup, teardown),
        cmocka_unit_test_setup_teardown(test_torn_tail_is_dropped_whole, setup, teardown),
        cmocka_unit_test_setup_teardown(test_corrupt_record_ends_the_journal, setup, teardown),
        cmocka_unit_test_setup_teardown(test_errors, setup, teardown),
        cmocka_unit_test_setup_teardown(test_interval_mode_syncs_on_demand, setup, teardown),
    };
    return cmocka_run_group_tests_name("journal", tests, NULL, NULL);
}
