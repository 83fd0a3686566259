/* Fault injection on the server's durable path (server/journal.c,
 * checkpoint.c): every write and flush a journal append or a checkpoint makes
 * is failed in turn, as a full disk (ENOSPC after a short write), an I/O error
 * (EIO) or a failed fsync would. Each failure must be reported (the append or
 * the checkpoint returns -1, so the session answers 503 and nothing is
 * acknowledged), must leave the journal holding exactly the acknowledged
 * records, and the next append, the fault gone, must work. */
#include "config.h"

#include <errno.h>
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

#include <meristem.h>

#include "server/checkpoint.h"
#include "server/io_hooks.h"
#include "server/journal.h"

/* ---- the faults ---- */

typedef enum fault { SHORT_ENOSPC, WRITE_EIO, SYNC_EIO, FAULTS } fault;

static fault kind;
static long calls, fail_at; /* fail the fail_at-th call (1-based) of the faulted kind; 0: never */

static ssize_t faulty_write(int fd, const void *bytes, size_t n)
{
    if (kind != SYNC_EIO && fail_at > 0 && ++calls == fail_at) {
        if (kind == SHORT_ENOSPC && n > 1) {
            // Part of the bytes reach the file; the retry then finds the disk full.
            ssize_t w = write(fd, bytes, n / 2);
            fail_at++;
            return w;
        }
        errno = kind == SHORT_ENOSPC ? ENOSPC : EIO;
        return -1;
    }
    return write(fd, bytes, n);
}

static int faulty_sync(int fd, int (*real)(int))
{
    if (kind == SYNC_EIO && fail_at > 0 && ++calls == fail_at) {
        errno = EIO;
        return -1;
    }
    return real(fd);
}

static int faulty_fsync(int fd) { return faulty_sync(fd, fsync); }
static int faulty_fdatasync(int fd) { return faulty_sync(fd, fdatasync); }

static void arm(fault k, long n)
{
    kind = k;
    calls = 0;
    fail_at = n;
}

/* ---- files ---- */

static char dir[64], jpath[128], cpath[128];

static int setup(void **state)
{
    (void)state;
    snprintf(dir, sizeof dir, "/tmp/meristem-faults-XXXXXX");
    assert_non_null(mkdtemp(dir));
    snprintf(jpath, sizeof jpath, "%s/s.journal", dir);
    snprintf(cpath, sizeof cpath, "%s/s.checkpoint", dir);
    merd_io = (merd_io_calls){faulty_write, faulty_fsync, faulty_fdatasync};
    arm(SHORT_ENOSPC, 0);
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    char tmp[160];
    snprintf(tmp, sizeof tmp, "%s.tmp", cpath);
    assert_int_not_equal(access(tmp, F_OK), 0); /* no temporary left behind */
    unlink(jpath);
    unlink(cpath);
    rmdir(dir);
    return 0;
}

typedef struct seen {
    size_t count;
    char text[64][32];
} seen;

static int collect(void *ctx, size_t index, const char *payload, size_t size)
{
    seen *s = ctx;
    assert_int_equal(index, s->count);
    assert_true(size < sizeof s->text[0] && s->count < 64);
    memcpy(s->text[s->count], payload, size);
    s->text[s->count][size] = '\0';
    s->count++;
    return 0;
}

/* The journal reopened holds exactly the `n` acknowledged records, whole. */
static void assert_journal(const char acked[][32], size_t n)
{
    seen s = {0};
    char error[MERD_JOURNAL_ERROR_MAX];
    merd_journal_report report;
    arm(kind, 0);
    merd_journal *j = merd_journal_open(jpath, MERD_FSYNC_ALWAYS, collect, &s, &report, error);
    assert_non_null(j);
    assert_int_equal(report.fault, MERD_JOURNAL_SOUND);
    assert_int_equal(report.dropped, 0); /* a failed append left nothing to drop */
    assert_int_equal(s.count, n);
    for (size_t i = 0; i < n; i++)
        assert_string_equal(s.text[i], acked[i]);
    merd_journal_close(j, false);
}

/* ---- journal appends ---- */

static void test_append_faults(void **state)
{
    (void)state;
    static char acked[64][32];
    size_t n = 0;
    char error[MERD_JOURNAL_ERROR_MAX];
    snprintf(acked[n], sizeof acked[n], "{\"create\":1}");
    merd_journal *j = merd_journal_create(jpath, acked[n], strlen(acked[n]), MERD_FSYNC_ALWAYS, error);
    assert_non_null(j);
    n++;
    for (fault k = 0; k < FAULTS; k++)
        for (long at = 1; at <= 2; at++) {
            char rec[32];
            snprintf(rec, sizeof rec, "{\"revision\":%zu}", n);
            arm(k, at);
            int rc = merd_journal_append(j, rec, strlen(rec), error);
            if (at == 1) {
                // The first write or flush of the record failed: refused.
                assert_int_equal(rc, -1);
                assert_non_null(strstr(error, "cannot append"));
            } else {
                // Only one call is made per append: the fault is past it.
                assert_int_equal(rc, 0);
                snprintf(acked[n++], sizeof acked[0], "%s", rec);
            }
            arm(k, 0);
            assert_journal((const char(*)[32])acked, n);
            // The journal goes on with no gap, no torn record, after a failure.
            snprintf(rec, sizeof rec, "{\"revision\":%zu}", n);
            assert_int_equal(merd_journal_append(j, rec, strlen(rec), error), 0);
            snprintf(acked[n++], sizeof acked[0], "%s", rec);
            assert_journal((const char(*)[32])acked, n);
        }
    merd_journal_close(j, false);
    assert_journal((const char(*)[32])acked, n);
}

static void test_create_faults(void **state)
{
    (void)state;
    char error[MERD_JOURNAL_ERROR_MAX];
    for (fault k = 0; k < FAULTS; k++)
        for (long at = 1; at <= 3; at++) {
            arm(k, at);
            merd_journal *j = merd_journal_create(jpath, "{\"c\":1}", 7, MERD_FSYNC_ALWAYS, error);
            arm(k, 0);
            if (j != NULL) {
                merd_journal_close(j, false);
                assert_journal((const char[][32]){"{\"c\":1}"}, 1);
            } else {
                // Never acknowledged: no file, or only a torn creation to drop.
                seen s = {0};
                merd_journal_report report;
                merd_journal *o = merd_journal_open(jpath, MERD_FSYNC_ALWAYS, collect, &s, &report, error);
                assert_true(o == NULL || s.count == 0 || s.count == 1);
                merd_journal_close(o, false);
            }
            unlink(jpath);
        }
}

/* ---- checkpoints ---- */

static mer_scene *scene_at(uint32_t steps)
{
    mer_params p = mer_params_default();
    mer_scene *s = NULL;
    mer_error err;
    assert_int_equal(mer_scene_new(&p, 3, &s, &err), MER_OK);
    uint32_t done;
    assert_int_equal(mer_scene_step(s, steps, NULL, NULL, NULL, &done, &err), MER_OK);
    return s;
}

static void test_checkpoint_faults(void **state)
{
    (void)state;
    const char *id = "0123456789abcdef0123456789abcdef";
    char error[MERD_JOURNAL_ERROR_MAX];
    mer_scene *old = scene_at(2), *next = scene_at(4);
    assert_int_equal(merd_checkpoint_write(cpath, id, 2, old, true, error), 0);
    for (fault k = 0; k < FAULTS; k++)
        for (long at = 1; at <= 4; at++) {
            arm(k, at);
            int rc = merd_checkpoint_write(cpath, id, 4, next, true, error);
            arm(k, 0);
            uint64_t revision = 0;
            mer_scene *back = merd_checkpoint_read(cpath, id, &revision, error);
            assert_non_null(back);
            // Written: the new one. Failed: the old one, whole, or the new one
            // whole when only the folder's flush after the rename failed.
            if (rc == 0)
                assert_int_equal(revision, 4);
            assert_true(revision == 2 || revision == 4);
            assert_true(mer_scene_hash(back) == mer_scene_hash(revision == 4 ? next : old));
            mer_scene_free(back);
            if (revision == 4)
                assert_int_equal(merd_checkpoint_write(cpath, id, 2, old, true, error), 0);
            if (rc != 0)
                assert_true(strlen(error) > 0);
        }
    mer_scene_free(old);
    mer_scene_free(next);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_append_faults, setup, teardown),
        cmocka_unit_test_setup_teardown(test_create_faults, setup, teardown),
        cmocka_unit_test_setup_teardown(test_checkpoint_faults, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
