/* meristemd — the edit journal (see journal.h for the format and guarantees). */
#include "config.h"

#include <errno.h>
#include <fcntl.h>
#include <libgen.h>
#include <limits.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include "server/io_hooks.h"
#include "server/journal.h"

struct merd_journal {
    int fd;
    char path[PATH_MAX];
    merd_fsync_mode mode;
    off_t size;      /* bytes of whole records */
    size_t records;
    bool dirty;      /* appended since the last fsync */
};

#define HEADER 8

merd_io_calls merd_io = {write, fsync, fdatasync};

static void put_u32(unsigned char *p, uint32_t v)
{
    p[0] = (unsigned char)v;
    p[1] = (unsigned char)(v >> 8);
    p[2] = (unsigned char)(v >> 16);
    p[3] = (unsigned char)(v >> 24);
}

static uint32_t get_u32(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static uint32_t checksum(const char *payload, size_t size)
{
    return (uint32_t)crc32(crc32(0L, Z_NULL, 0), (const Bytef *)payload, (uInt)size);
}

static int fail(char *error, const char *what, const char *path)
{
    snprintf(error, MERD_JOURNAL_ERROR_MAX, "%.40s %.140s: %.60s", what, path, strerror(errno));
    return -1;
}

int merd_sync_folder(const char *path)
{
    char copy[PATH_MAX];
    snprintf(copy, sizeof copy, "%s", path);
    int fd = open(dirname(copy), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0)
        return -1;
    int rc = merd_io.fsync(fd);
    close(fd);
    return rc;
}

int merd_write_all(int fd, const void *bytes, size_t n)
{
    const unsigned char *p = bytes;
    while (n > 0) {
        ssize_t w = merd_io.write(fd, p, n);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0)
            return -1;
        p += w;
        n -= (size_t)w;
    }
    return 0;
}

/* The record of `payload` as the file holds it (caller frees), or NULL with
 * `error` filled. */
static unsigned char *frame(const char *payload, size_t size, char *error)
{
    if (size > MERD_JOURNAL_RECORD_MAX) {
        snprintf(error, MERD_JOURNAL_ERROR_MAX, "a journal record is at most %u bytes, not %zu",
                 MERD_JOURNAL_RECORD_MAX, size);
        return NULL;
    }
    unsigned char *buf = malloc(HEADER + size);
    if (buf == NULL) {
        snprintf(error, MERD_JOURNAL_ERROR_MAX, "out of memory for a journal record");
        return NULL;
    }
    put_u32(buf, (uint32_t)size);
    put_u32(buf + 4, checksum(payload, size));
    memcpy(buf + HEADER, payload, size);
    return buf;
}

int merd_journal_append(merd_journal *j, const char *payload, size_t size, char *error)
{
    unsigned char *buf = frame(payload, size, error);
    if (buf == NULL)
        return -1;
    // One write of header and payload: a crash leaves a whole record or a torn
    // one that replay detects, never a record that reads as whole but is not.
    int rc = merd_write_all(j->fd, buf, HEADER + size);
    free(buf);
    if (rc == 0 && j->mode == MERD_FSYNC_ALWAYS)
        rc = merd_io.fdatasync(j->fd);
    if (rc != 0) {
        fail(error, "cannot append to", j->path);
        // Cut back a partial write so the next append starts on a boundary.
        if (ftruncate(j->fd, j->size) == 0)
            lseek(j->fd, j->size, SEEK_SET);
        return -1;
    }
    j->size += (off_t)(HEADER + size);
    j->records++;
    j->dirty = j->mode != MERD_FSYNC_ALWAYS;
    return 0;
}

int merd_journal_compact(merd_journal *j, const char *first, size_t size, char *error)
{
    unsigned char *buf = frame(first, size, error);
    if (buf == NULL)
        return -1;
    char tmp[PATH_MAX + 8];
    snprintf(tmp, sizeof tmp, "%s.tmp", j->path);
    int fd = open(tmp, O_WRONLY | O_CREAT | O_TRUNC | O_APPEND | O_NOFOLLOW | O_CLOEXEC, 0644);
    int rc = fd < 0 ? fail(error, "cannot create", tmp) : 0;
    if (rc == 0 && merd_write_all(fd, buf, HEADER + size) != 0)
        rc = fail(error, "cannot write", tmp);
    if (rc == 0 && fsync(fd) != 0)
        rc = fail(error, "cannot flush", tmp);
    if (rc == 0 && rename(tmp, j->path) != 0)
        rc = fail(error, "cannot rename", tmp);
    free(buf);
    if (rc != 0) {
        if (fd >= 0)
            close(fd);
        unlink(tmp);
        return -1;
    }
    // Renamed: from here the new file is the journal, whether or not the
    // folder's flush below succeeds (the old one, if it comes back after a
    // crash, fits the checkpoint as well).
    close(j->fd);
    j->fd = fd;
    j->size = (off_t)(HEADER + size);
    j->records = 1;
    j->dirty = false;
    if (merd_sync_folder(j->path) != 0)
        return fail(error, "cannot sync the folder of", j->path);
    return 0;
}

static merd_journal *journal_new(const char *path, merd_fsync_mode mode, char *error)
{
    merd_journal *j = calloc(1, sizeof *j);
    if (j == NULL) {
        snprintf(error, MERD_JOURNAL_ERROR_MAX, "out of memory for a journal");
        return NULL;
    }
    snprintf(j->path, sizeof j->path, "%s", path);
    j->mode = mode;
    j->fd = -1;
    return j;
}

merd_journal *merd_journal_create(const char *path, const char *first, size_t size,
                                  merd_fsync_mode mode, char *error)
{
    merd_journal *j = journal_new(path, mode, error);
    if (j == NULL)
        return NULL;
    j->fd = open(path, O_WRONLY | O_CREAT | O_EXCL | O_APPEND | O_CLOEXEC, 0644);
    if (j->fd < 0) {
        fail(error, "cannot create", path);
        free(j);
        return NULL;
    }
    if (merd_journal_append(j, first, size, error) != 0 ||
        (mode == MERD_FSYNC_ALWAYS && merd_sync_folder(path) != 0 && fail(error, "cannot sync the folder of", path))) {
        merd_journal_close(j, true);
        return NULL;
    }
    return j;
}

/* Opens `path` for reading and appending only if it is a regular file: never
 * follows a link, never blocks on a FIFO. -1 with `fault` set otherwise. */
static int open_regular(const char *path, merd_journal_fault *fault, char *error)
{
    int fd = open(path, O_RDWR | O_NOFOLLOW | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
    struct stat st;
    if (fd < 0) {
        bool odd = errno == ELOOP || errno == EISDIR || errno == ENXIO || errno == EWOULDBLOCK;
        *fault = odd ? MERD_JOURNAL_DAMAGED : MERD_JOURNAL_IO;
        return odd ? (snprintf(error, MERD_JOURNAL_ERROR_MAX, "%.200s is not a regular file", path), -1)
                   : fail(error, "cannot open", path);
    }
    if (fstat(fd, &st) != 0) {
        *fault = MERD_JOURNAL_IO;
        fail(error, "cannot stat", path);
    } else if (!S_ISREG(st.st_mode)) {
        *fault = MERD_JOURNAL_DAMAGED;
        snprintf(error, MERD_JOURNAL_ERROR_MAX, "%.200s is not a regular file", path);
    } else if (fcntl(fd, F_SETFL, O_APPEND) != 0) {
        *fault = MERD_JOURNAL_IO;
        fail(error, "cannot set up", path);
    } else {
        return fd;
    }
    close(fd);
    return -1;
}

static int read_all(int fd, const char *path, unsigned char **out, size_t *size, char *error)
{
    struct stat st;
    if (fstat(fd, &st) != 0)
        return fail(error, "cannot stat", path);
    unsigned char *buf = malloc((size_t)st.st_size + 1);
    size_t have = 0;
    while (buf != NULL && have < (size_t)st.st_size) {
        ssize_t r = pread(fd, buf + have, (size_t)st.st_size - have, (off_t)have);
        if (r < 0 && errno == EINTR)
            continue;
        if (r < 0) {
            free(buf);
            return fail(error, "cannot read", path);
        }
        if (r == 0)
            break;
        have += (size_t)r;
    }
    if (buf == NULL) {
        snprintf(error, MERD_JOURNAL_ERROR_MAX, "out of memory reading %.200s", path);
        return -1;
    }
    *out = buf;
    *size = have;
    return 0;
}

/* Whether a record we could have written starts at `at`: a non-empty JSON
 * payload that fits in the file and matches its checksum. */
static bool whole_record_at(const unsigned char *data, size_t size, size_t at)
{
    if (size - at < HEADER + 2)
        return false;
    uint32_t len = get_u32(data + at);
    return len >= 2 && len <= MERD_JOURNAL_RECORD_MAX && len <= size - at - HEADER &&
           data[at + HEADER] == '{' &&
           get_u32(data + at + 4) == checksum((const char *)data + at + HEADER, len);
}

/* Whether the bytes from `at` (where no whole record starts) to the end are a
 * torn tail, as journal.h defines it. */
static bool torn_tail(const unsigned char *data, size_t size, size_t at)
{
    for (size_t p = at + 1; p + HEADER < size; p++)
        if (whole_record_at(data, size, p))
            return false;
    if (size - at < HEADER)
        return true;
    uint32_t len = get_u32(data + at);
    if (len > size - at - HEADER)
        return true;  // runs past the end of the file: cut short
    return len == 0 || memchr(data + at + HEADER, 0, len) != NULL;
}

/* Hands every whole record to `fn`; *end gets where the whole records end. */
static int replay(const unsigned char *data, size_t size, const char *path, merd_journal_record_fn fn,
                  void *ctx, size_t *end, size_t *records, merd_journal_report *report, char *error)
{
    size_t at = 0, index = 0;
    while (at < size && whole_record_at(data, size, at)) {
        uint32_t len = get_u32(data + at);
        if (fn != NULL && fn(ctx, index, (const char *)data + at + HEADER, len) != 0) {
            snprintf(error, MERD_JOURNAL_ERROR_MAX, "record %zu of %.180s could not be replayed", index, path);
            report->fault = MERD_JOURNAL_DAMAGED;
            return -1;
        }
        at += HEADER + len;
        index++;
    }
    if (at < size && !torn_tail(data, size, at)) {
        snprintf(error, MERD_JOURNAL_ERROR_MAX, "record %zu (byte %zu) of %.140s is damaged and "
                 "whole records follow it", index, at, path);
        report->fault = MERD_JOURNAL_DAMAGED;
        return -1;
    }
    if (index == 0) {
        snprintf(error, MERD_JOURNAL_ERROR_MAX, "%.200s has no whole record", path);
        report->fault = MERD_JOURNAL_TORN_CREATION;
        return -1;
    }
    report->dropped = size - at;
    *end = at;
    *records = index;
    return 0;
}

merd_journal *merd_journal_open(const char *path, merd_fsync_mode mode, merd_journal_record_fn fn,
                                void *ctx, merd_journal_report *report, char *error)
{
    merd_journal_report ignored;
    report = report != NULL ? report : &ignored;
    *report = (merd_journal_report){MERD_JOURNAL_IO, 0};
    int fd = open_regular(path, &report->fault, error);
    if (fd < 0)
        return NULL;
    unsigned char *data = NULL;
    size_t size = 0, at = 0, records = 0;
    int rc = read_all(fd, path, &data, &size, error);
    if (rc == 0)
        rc = replay(data, size, path, fn, ctx, &at, &records, report, error);
    free(data);
    merd_journal *j = rc == 0 ? journal_new(path, mode, error) : NULL;
    if (j == NULL) {
        close(fd);
        return NULL;
    }
    j->fd = fd;
    j->size = (off_t)at;
    j->records = records;
    if (at < size && (ftruncate(fd, (off_t)at) != 0 || merd_io.fsync(fd) != 0)) {
        report->fault = MERD_JOURNAL_IO;
        fail(error, "cannot cut the torn tail of", path);
        close(fd);
        free(j);
        return NULL;
    }
    report->fault = MERD_JOURNAL_SOUND;
    return j;
}

int merd_journal_unlink(const char *path, char *error)
{
    if (unlink(path) != 0 && errno != ENOENT)
        return fail(error, "cannot remove", path);
    if (merd_sync_folder(path) != 0)
        return fail(error, "cannot sync the folder of", path);
    return 0;
}

int merd_journal_sync(merd_journal *j)
{
    if (j == NULL || !j->dirty)
        return 0;
    if (merd_io.fdatasync(j->fd) != 0)
        return -1;
    j->dirty = false;
    return 0;
}

size_t merd_journal_records(const merd_journal *j)
{
    return j->records;
}

void merd_journal_close(merd_journal *j, bool remove)
{
    if (j == NULL)
        return;
    if (!remove)
        merd_journal_sync(j);
    close(j->fd);
    if (remove && unlink(j->path) == 0)
        merd_sync_folder(j->path);
    free(j);
}
