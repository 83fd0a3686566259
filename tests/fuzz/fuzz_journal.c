/* meristem — libFuzzer harness: a journal file replayed as meristemd restores
 * a session (server/session.c): the reader frames records (length, CRC-32),
 * the first record's "create" builds the scene, each later record's "edits"
 * are replayed onto it.
 *
 * Input: a first byte choosing the mode, then the rest. Even: the rest is the
 * file, byte for byte (the framing and torn-tail code). Odd: the rest is split
 * at newlines into record payloads, which the harness frames with correct
 * lengths and checksums, so that inputs reach the replay of the records. */
#include "config.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <jansson.h>
#include <zlib.h>

#include "server/edits.h"
#include "server/journal.h"
#include "server/spec.h"
#include "tests/fuzz/fuzz_common.h"

static mer_scene *scene;

/* As session.c's replay_record, under the harness's small limits. */
static int replay(void *ctx, size_t index, const char *payload, size_t size)
{
    (void)ctx;
    json_t *doc = json_loadb(payload, size, JSON_REJECT_DUPLICATES, NULL);
    merd_refusal why = {0};
    int rc = -1;
    if (doc == NULL)
        return -1;
    if (index == 0) {
        const json_t *create = json_object_get(doc, "create");
        if (create != NULL && json_is_string(json_object_get(doc, "id")) &&
            (scene = merd_scene_from_spec(create, &fuzz_limits, &why)) != NULL)
            rc = 0;
    } else {
        const json_t *edits = json_object_get(doc, "edits");
        merd_batch *b = NULL;
        json_t *body = json_is_array(edits) ? json_pack("{s:O}", "edits", (json_t *)edits) : NULL;
        if (scene != NULL && json_is_integer(json_object_get(doc, "revision")) && body != NULL &&
            merd_batch_decode(body, &fuzz_limits, &b, &why) == 0) {
            merd_batch_outcome outcome;
            json_t *applied = NULL;
            rc = merd_batch_apply(b, &scene, NULL, NULL, NULL, &outcome, &applied, &why);
            json_decref(applied);
        }
        merd_batch_free(b);
        json_decref(body);
    }
    if (rc != 0 && why.status != 0)
        fuzz_check_refusal(&why);
    json_decref(doc);
    return rc;
}

static void put_u32(FILE *f, uint32_t v)
{
    unsigned char b[4] = {(unsigned char)v, (unsigned char)(v >> 8), (unsigned char)(v >> 16),
                          (unsigned char)(v >> 24)};
    fwrite(b, 1, 4, f);
}

static void write_framed(FILE *f, const uint8_t *data, size_t size)
{
    size_t at = 0;
    while (at < size) {
        const uint8_t *nl = memchr(data + at, '\n', size - at);
        size_t len = nl ? (size_t)(nl - (data + at)) : size - at;
        put_u32(f, (uint32_t)len);
        put_u32(f, (uint32_t)crc32(crc32(0L, Z_NULL, 0), data + at, (uInt)len));
        fwrite(data + at, 1, len, f);
        at += len + 1;
    }
}

/* The whole of file `path` (NULL and 0 for an empty one). */
static uint8_t *slurp(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (f == NULL)
        abort();
    uint8_t *buf = NULL;
    size_t n = 0, cap = 0, got;
    do {
        if (n == cap && (buf = realloc(buf, cap = cap ? 2 * cap : 4096)) == NULL)
            abort();
        got = fread(buf + n, 1, cap - n, f);
        n += got;
    } while (got > 0);
    fclose(f);
    *size = n;
    return buf;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size == 0)
        return 0;
    char path[64];
    snprintf(path, sizeof path, "%s/meristem-fuzz-%ld.journal",
             access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp", (long)getpid());
    FILE *f = fopen(path, "wb");
    if (f == NULL)
        abort();
    if (data[0] & 1)
        write_framed(f, data + 1, size - 1);
    else
        fwrite(data + 1, 1, size - 1, f);
    if (fclose(f) != 0)
        abort();
    char error[MERD_JOURNAL_ERROR_MAX] = "";
    size_t before_size = 0;
    uint8_t *before = slurp(path, &before_size);
    merd_journal_report report = {0};
    merd_journal *j = merd_journal_open(path, MERD_FSYNC_INTERVAL, replay, NULL, &report, error);
    if (j != NULL && scene == NULL)
        abort(); // a journal opened without its creation record
    if (j == NULL) {
        // A journal that is refused is not ours to cut: it must be left byte for byte.
        size_t after_size = 0;
        uint8_t *after = slurp(path, &after_size);
        if (after_size != before_size || (after_size > 0 && memcmp(before, after, after_size) != 0))
            abort();
        free(after);
    }
    free(before);
    merd_journal_close(j, false);
    mer_scene_free(scene);
    scene = NULL;
    unlink(path);
    return 0;
}
