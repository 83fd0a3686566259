/* Unit tests for server/journal.c: records survive reopening, compaction
 * leaves one record, a torn tail is dropped whole and cut off, appends go on
 * after it; damage anywhere else leaves the file untouched, and only regular
 * files are opened. */
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
    merd_journal_report report = {MERD_JOURNAL_IO, 99};
    char error[MERD_JOURNAL_ERROR_MAX];
    merd_journal *j = merd_journal_open(path, MERD_FSYNC_ALWAYS, collect, &s, &report, error);
    assert_non_null(j);
    assert_int_equal(s.count, 3);
    assert_int_equal(report.dropped, 0);
    assert_int_equal(report.fault, MERD_JOURNAL_SOUND);
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

/* Compaction leaves one record, renamed into place (no temporary file stays),
 * and appends go on in the new file through the same journal. */
static void test_compact_keeps_one_record(void **state)
{
    (void)state;
    merd_journal *j = write_three();
    char error[MERD_JOURNAL_ERROR_MAX], tmp[160];
    assert_int_equal(merd_journal_compact(j, "{\"create\":2}", 12, error), 0);
    assert_int_equal(merd_journal_records(j), 1);
    assert_int_equal(file_size(), 8 + 12);
    snprintf(tmp, sizeof tmp, "%s.tmp", path);
    assert_int_equal(access(tmp, F_OK), -1);
    assert_int_equal(merd_journal_append(j, "{\"rev\":3}", 9, error), 0);
    merd_journal_close(j, false);
    seen s = {0};
    j = merd_journal_open(path, MERD_FSYNC_ALWAYS, collect, &s, NULL, error);
    assert_non_null(j);
    assert_int_equal(s.count, 2);
    assert_string_equal(s.text[0], "{\"create\":2}");
    assert_string_equal(s.text[1], "{\"rev\":3}");
    merd_journal_close(j, true);
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
        merd_journal_report report = {0};
        char error[MERD_JOURNAL_ERROR_MAX];
        merd_journal *j = merd_journal_open(path, MERD_FSYNC_ALWAYS, collect, &s, &report, error);
        assert_non_null(j);
        assert_int_equal(s.count, 2);  // the torn third record is not replayed
        assert_int_equal(report.dropped, (size_t)(8 + 9 - cut));
        assert_int_equal(file_size(), whole - 8 - 9);  // cut back to a boundary
        // Appending again restores a third, whole record.
        assert_int_equal(merd_journal_append(j, "{\"rev\":2}", 9, error), 0);
        merd_journal_close(j, false);
        assert_int_equal(file_size(), whole);
    }
}

static void *slurp(size_t *size)
{
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    static char buf[4096];
    *size = fread(buf, 1, sizeof buf, f);
    fclose(f);
    void *copy = malloc(*size);
    memcpy(copy, buf, *size);
    return copy;
}

/* Opening must fail as damaged and leave every byte as it was. */
static void assert_damaged_and_kept(void)
{
    size_t before_size = 0, after_size = 0;
    void *before = slurp(&before_size);
    seen s = {0};
    merd_journal_report report = {0};
    char error[MERD_JOURNAL_ERROR_MAX];
    assert_null(merd_journal_open(path, MERD_FSYNC_ALWAYS, collect, &s, &report, error));
    assert_int_equal(report.fault, MERD_JOURNAL_DAMAGED);
    void *after = slurp(&after_size);
    assert_int_equal(before_size, after_size);
    assert_memory_equal(before, after, before_size);
    free(before);
    free(after);
}

static void put(off_t at, const void *bytes, size_t n)
{
    int fd = open(path, O_WRONLY);
    assert_true(fd >= 0);
    assert_int_equal(pwrite(fd, bytes, n, at), (ssize_t)n);
    close(fd);
}

/* A flipped byte, a wrong length or a cut inside a record with whole records
 * after it is damage, not a torn tail: nothing may be cut away. */
static void test_damage_before_whole_records_is_kept(void **state)
{
    (void)state;
    merd_journal_close(write_three(), false);
    put(8 + 12 + 8 + 3, "X", 1);  // in the second record's payload
    assert_damaged_and_kept();

    unlink(path);
    merd_journal_close(write_three(), false);
    put(8 + 12, "\x40\0\0\0", 4);  // the second record's length runs into the third
    assert_damaged_and_kept();

    unlink(path);
    merd_journal_close(write_three(), false);
    put(8 + 12, "\xff\xff\xff\x7f", 4);  // a length over the limit
    assert_damaged_and_kept();

    // Bytes cut out of the middle of the second record.
    unlink(path);
    merd_journal_close(write_three(), false);
    size_t n = 0;
    char *all = slurp(&n);
    FILE *f = fopen(path, "wb");
    fwrite(all, 1, 8 + 12 + 8 + 2, f);
    fwrite(all + 8 + 12 + 8 + 6, 1, n - (8 + 12 + 8 + 6), f);
    fclose(f);
    free(all);
    assert_damaged_and_kept();

    // A whole-length last record whose bytes changed was written whole once.
    unlink(path);
    merd_journal_close(write_three(), false);
    put(3 * 8 + 12 + 9 + 4, "Y", 1);
    assert_damaged_and_kept();
}

/* Blocks a power cut left unwritten read as zeros: a tail, dropped. */
static void test_zeroed_tail_is_torn(void **state)
{
    (void)state;
    merd_journal_close(write_three(), false);
    put(2 * 8 + 12 + 9 + 8 + 2, "\0\0\0\0", 4);
    seen s = {0};
    merd_journal_report report = {0};
    char error[MERD_JOURNAL_ERROR_MAX];
    merd_journal *j = merd_journal_open(path, MERD_FSYNC_ALWAYS, collect, &s, &report, error);
    assert_non_null(j);
    assert_int_equal(s.count, 2);
    assert_int_equal(report.dropped, 8 + 9);
    merd_journal_close(j, false);
    // A file of zeros only is a creation cut short.
    assert_int_equal(truncate(path, 0), 0);
    assert_int_equal(truncate(path, 64), 0);
    assert_null(merd_journal_open(path, MERD_FSYNC_ALWAYS, collect, &s, &report, error));
    assert_int_equal(report.fault, MERD_JOURNAL_TORN_CREATION);
}

/* A link is never followed (what it points to stays as it is); a FIFO does
 * not block the open. */
static void test_only_regular_files(void **state)
{
    (void)state;
    char target[160];
    snprintf(target, sizeof target, "%s/elsewhere", dir);
    merd_journal_close(write_three(), false);
    assert_int_equal(rename(path, target), 0);
    off_t whole = 3 * 8 + 12 + 9 + 9;
    assert_int_equal(truncate(target, whole - 3), 0);  // a torn tail that must not be cut
    assert_int_equal(symlink(target, path), 0);
    merd_journal_report report = {0};
    char error[MERD_JOURNAL_ERROR_MAX];
    assert_null(merd_journal_open(path, MERD_FSYNC_ALWAYS, NULL, NULL, &report, error));
    assert_int_equal(report.fault, MERD_JOURNAL_DAMAGED);
    assert_non_null(strstr(error, "not a regular file"));
    struct stat st;
    assert_int_equal(stat(target, &st), 0);
    assert_int_equal(st.st_size, whole - 3);
    unlink(path);
    unlink(target);

    assert_int_equal(mkfifo(path, 0600), 0);
    assert_null(merd_journal_open(path, MERD_FSYNC_ALWAYS, NULL, NULL, &report, error));
    assert_int_equal(report.fault, MERD_JOURNAL_DAMAGED);
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
    merd_journal_report report = {0};
    assert_null(merd_journal_open(path, MERD_FSYNC_ALWAYS, NULL, NULL, &report, error));
    assert_non_null(strstr(error, "no whole record"));
    assert_int_equal(report.fault, MERD_JOURNAL_TORN_CREATION);
    unlink(path);
    assert_null(merd_journal_open(path, MERD_FSYNC_ALWAYS, NULL, NULL, &report, error));
    assert_int_equal(report.fault, MERD_JOURNAL_IO);
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
        cmocka_unit_test_setup_teardown(test_compact_keeps_one_record, setup, teardown),
        cmocka_unit_test_setup_teardown(test_torn_tail_is_dropped_whole, setup, teardown),
        cmocka_unit_test_setup_teardown(test_damage_before_whole_records_is_kept, setup, teardown),
        cmocka_unit_test_setup_teardown(test_zeroed_tail_is_torn, setup, teardown),
        cmocka_unit_test_setup_teardown(test_only_regular_files, setup, teardown),
        cmocka_unit_test_setup_teardown(test_errors, setup, teardown),
        cmocka_unit_test_setup_teardown(test_interval_mode_syncs_on_demand, setup, teardown),
    };
    return cmocka_run_group_tests_name("journal", tests, NULL, NULL);
}
