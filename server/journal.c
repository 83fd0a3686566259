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

/* A new file's name is durable only once its folder is synced. */
static int sync_folder(const char *path)
{
    char copy[PATH_MAX];
    snprintf(copy, sizeof copy, "%s", path);
    int fd = open(dirname(copy), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0)
        return -1;
    int rc = fsync(fd);
    close(fd);
    return rc;
}

static int write_all(int fd, const unsigned char *p, size_t n)
{
    while (n > 0) {
        ssize_t w = write(fd, p, n);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0)
            return -1;
        p += w;
        n -= (size_t)w;
    }
    return 0;
}

int merd_journal_append(merd_journal *j, const char *payload, size_t size, char *error)
{
    if (size > MERD_JOURNAL_RECORD_MAX) {
        snprintf(error, MERD_JOURNAL_ERROR_MAX, "a journal record is at most %u bytes, not %zu",
                 MERD_JOURNAL_RECORD_MAX, size);
        return -1;
    }
    unsigned char *buf = malloc(HEADER + size);
    if (buf == NULL) {
        snprintf(error, MERD_JOURNAL_ERROR_MAX, "out of memory for a journal record");
        return -1;
    }
    put_u32(buf, (uint32_t)size);
    put_u32(buf + 4, checksum(payload, size));
    memcpy(buf + HEADER, payload, size);
    // One write of header and payload: a crash leaves a whole record or a torn
    // one that replay detects, never a record that reads as whole but is not.
    int rc = write_all(j->fd, buf, HEADER + size);
    free(buf);
    if (rc == 0 && j->mode == MERD_FSYNC_ALWAYS)
        rc = fdatasync(j->fd);
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
        (mode == MERD_FSYNC_ALWAYS && sync_folder(path) != 0 && fail(error, "cannot sync the folder of", path))) {
        merd_journal_close(j, true);
        return NULL;
    }
    return j;
}

static int read_file(const char *path, unsigned char **out, size_t *size, char *error)
{
    int fd = open(path, O_RDONLY | O_CLOEXEC);
    if (fd < 0)
        return fail(error, "cannot open", path);
    struct stat st;
    if (fstat(fd, &st) != 0) {
        close(fd);
        return fail(error, "cannot stat", path);
    }
    unsigned char *buf = malloc((size_t)st.st_size + 1);
    size_t have = 0;
    while (buf != NULL && have < (size_t)st.st_size) {
        ssize_t r = read(fd, buf + have, (size_t)st.st_size - have);
        if (r < 0 && errno == EINTR)
            continue;
        if (r <= 0)
            break;
        have += (size_t)r;
    }
    close(fd);
    if (buf == NULL) {
        snprintf(error, MERD_JOURNAL_ERROR_MAX, "out of memory reading %.200s", path);
        return -1;
    }
    *out = buf;
    *size = have;
    return 0;
}

merd_journal *merd_journal_open(const char *path, merd_fsync_mode mode, merd_journal_record_fn fn,
                                void *ctx, size_t *dropped, char *error)
{
    unsigned char *data = NULL;
    size_t size = 0;
    if (read_file(path, &data, &size, error) != 0)
        return NULL;
    size_t at = 0, index = 0;
    while (size - at >= HEADER) {
        uint32_t len = get_u32(data + at);
        if (len > MERD_JOURNAL_RECORD_MAX || len > size - at - HEADER ||
            get_u32(data + at + 4) != checksum((const char *)data + at + HEADER, len))
            break;  // torn or corrupt: the journal ends at the last whole record
        if (fn != NULL && fn(ctx, index, (const char *)data + at + HEADER, len) != 0) {
            snprintf(error, MERD_JOURNAL_ERROR_MAX, "record %zu of %.180s could not be replayed", index, path);
            free(data);
            return NULL;
        }
        at += HEADER + len;
        index++;
    }
    free(data);
    if (index == 0) {
        snprintf(error, MERD_JOURNAL_ERROR_MAX, "%.200s has no whole record", path);
        return NULL;
    }
    if (dropped != NULL)
        *dropped = size - at;

    merd_journal *j = journal_new(path, mode, error);
    if (j == NULL)
        return NULL;
    j->size = (off_t)at;
    j->records = index;
    j->fd = open(path, O_WRONLY | O_APPEND | O_CLOEXEC);
    if (j->fd < 0 || (at < size && (ftruncate(j->fd, (off_t)at) != 0 || fsync(j->fd) != 0))) {
        fail(error, "cannot reopen", path);
        if (j->fd >= 0)
            close(j->fd);
        free(j);
        return NULL;
    }
    return j;
}

int merd_journal_sync(merd_journal *j)
{
    if (j == NULL || !j->dirty)
        return 0;
    if (fdatasync(j->fd) != 0)
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
    if (remove) {
        unlink(j->path);
        sync_folder(j->path);
    }
    free(j);
}
