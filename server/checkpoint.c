/* meristemd — checkpoints beside the journals (see checkpoint.h). */
#include "config.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include "server/checkpoint.h"
#include "server/io_hooks.h"
#include "server/journal.h"

#define MAGIC "MERDCKP1"
#define ID_LEN 32
#define HEAD (8 + ID_LEN + 8 + 8) /* magic, id, revision, digest of the three */

/* The CRC-32 of a head's magic, id and revision, as the journal's records use. */
static uint64_t digest_of(const unsigned char *head)
{
    return crc32(crc32(0L, Z_NULL, 0), head, 8 + ID_LEN + 8);
}

static int failed(char *error, const char *what, const char *path)
{
    snprintf(error, MERD_JOURNAL_ERROR_MAX, "%s %.180s: %s", what, path, strerror(errno));
    return -1;
}

int merd_checkpoint_write(const char *path, const char *id, uint64_t revision,
                          const mer_scene *scene, bool sync, char *error)
{
    uint8_t *bytes = NULL;
    size_t size = 0;
    mer_error err = {0};
    if (strlen(id) != ID_LEN || mer_scene_save(scene, &bytes, &size, &err) != MER_OK) {
        snprintf(error, MERD_JOURNAL_ERROR_MAX, "the scene could not be saved: %.200s", err.message);
        return -1;
    }
    unsigned char head[HEAD];
    memcpy(head, MAGIC, 8);
    memcpy(head + 8, id, ID_LEN);
    memcpy(head + 8 + ID_LEN, &revision, 8);
    uint64_t digest = digest_of(head);
    memcpy(head + 8 + ID_LEN + 8, &digest, 8);
    char tmp[PATH_MAX];
    snprintf(tmp, sizeof tmp, "%s.tmp", path);
    int rc = -1;
    int fd = open(tmp, O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (fd < 0) {
        failed(error, "cannot create", tmp);
    } else {
        if (merd_write_all(fd, head, sizeof head) != 0 || merd_write_all(fd, bytes, size) != 0)
            failed(error, "cannot write", tmp);
        else if (sync && merd_io.fsync(fd) != 0)
            failed(error, "cannot flush", tmp);
        else
            rc = 0;
        if (close(fd) != 0 && rc == 0)
            rc = failed(error, "cannot close", tmp);
    }
    if (rc == 0 && rename(tmp, path) != 0)
        rc = failed(error, "cannot rename", tmp);
    if (rc == 0 && sync && merd_sync_folder(path) != 0)
        rc = failed(error, "cannot sync the folder of", path);
    if (rc != 0)
        unlink(tmp);
    free(bytes);
    return rc;
}

static unsigned char *read_whole(const char *path, size_t *size, char *error)
{
    int fd = open(path, O_RDONLY | O_NOFOLLOW | O_CLOEXEC | O_NONBLOCK);
    struct stat st;
    if (fd < 0 || fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        if (fd >= 0)
            close(fd);
        failed(error, "no checkpoint at", path);
        return NULL;
    }
    unsigned char *buf = malloc(st.st_size > 0 ? (size_t)st.st_size : 1);
    size_t n = 0;
    while (buf != NULL && n < (size_t)st.st_size) {
        ssize_t r = read(fd, buf + n, (size_t)st.st_size - n);
        if (r < 0 && errno == EINTR)
            continue;
        if (r <= 0)
            break;
        n += (size_t)r;
    }
    close(fd);
    if (buf == NULL || n != (size_t)st.st_size) {
        free(buf);
        snprintf(error, MERD_JOURNAL_ERROR_MAX, "cannot read %.200s", path);
        return NULL;
    }
    *size = n;
    return buf;
}

mer_scene *merd_checkpoint_read(const char *path, const char *id, uint64_t *revision, char *error)
{
    size_t size = 0;
    unsigned char *buf = read_whole(path, &size, error);
    if (buf == NULL)
        return NULL;
    mer_scene *scene = NULL;
    uint64_t digest;
    if (size >= HEAD)
        memcpy(&digest, buf + 8 + ID_LEN + 8, 8);
    if (size < HEAD || memcmp(buf, MAGIC, 8) != 0 || digest_of(buf) != digest ||
        strlen(id) != ID_LEN || memcmp(buf + 8, id, ID_LEN) != 0) {
        snprintf(error, MERD_JOURNAL_ERROR_MAX, "%.200s is not a checkpoint of this session", path);
    } else {
        mer_error err = {0};
        if (mer_scene_load(buf + HEAD, size - HEAD, &scene, &err) != MER_OK)
            snprintf(error, MERD_JOURNAL_ERROR_MAX, "a damaged checkpoint: %.200s", err.message);
        else
            memcpy(revision, buf + 8 + ID_LEN, 8);
    }
    free(buf);
    return scene;
}
