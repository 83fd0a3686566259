/* meristemd — shared snapshot bytes and the per-session LRU of variants (see
 * snapshot.h). */
#include "config.h"

#include <assert.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <meristem/gltf.h>

#include "server/snapshot.h"

struct merd_snapshot {
    atomic_int refs;
    uint8_t *bytes;
    size_t size;
};

merd_snapshot *merd_snapshot_new(uint8_t *bytes, size_t size)
{
    merd_snapshot *snap = calloc(1, sizeof *snap);
    if (snap == NULL) {
        mer_gltf_free(bytes);
        return NULL;
    }
    atomic_init(&snap->refs, 1);
    snap->bytes = bytes;
    snap->size = size;
    return snap;
}

merd_snapshot *merd_snapshot_ref(merd_snapshot *snap)
{
    atomic_fetch_add(&snap->refs, 1);
    return snap;
}

void merd_snapshot_release(merd_snapshot *snap)
{
    if (snap != NULL && atomic_fetch_sub(&snap->refs, 1) == 1) {
        mer_gltf_free(snap->bytes);
        free(snap);
    }
}

const uint8_t *merd_snapshot_bytes(const merd_snapshot *snap, size_t *size)
{
    *size = snap->size;
    return snap->bytes;
}

merd_snapshot *merd_snapshot_cache_get(merd_snapshot_cache *c, const char *key)
{
    for (size_t i = 0; i < MERD_SNAPSHOT_VARIANTS; i++)
        if (c->slot[i].snap != NULL && strcmp(c->slot[i].key, key) == 0) {
            c->slot[i].used = ++c->clock;
            return merd_snapshot_ref(c->slot[i].snap);
        }
    return NULL;
}

void merd_snapshot_cache_put(merd_snapshot_cache *c, uint64_t revision, const char *key,
                             merd_snapshot *snap)
{
    assert(snap != NULL && key != NULL);
    for (size_t i = 0; i < MERD_SNAPSHOT_VARIANTS; i++)
        if (c->slot[i].snap != NULL && c->slot[i].revision != revision) {
            merd_snapshot_release(c->slot[i].snap);
            c->slot[i].snap = NULL;
        }
    size_t victim = 0;
    for (size_t i = 0; i < MERD_SNAPSHOT_VARIANTS; i++) {
        if (c->slot[i].snap == NULL) {
            victim = i;
            break;
        }
        if (c->slot[i].used < c->slot[victim].used)
            victim = i;
    }
    merd_snapshot_release(c->slot[victim].snap);
    c->slot[victim].snap = merd_snapshot_ref(snap);
    c->slot[victim].revision = revision;
    c->slot[victim].used = ++c->clock;
    snprintf(c->slot[victim].key, sizeof c->slot[victim].key, "%s", key);
}

void merd_snapshot_cache_clear(merd_snapshot_cache *c)
{
    for (size_t i = 0; i < MERD_SNAPSHOT_VARIANTS; i++)
        merd_snapshot_release(c->slot[i].snap);
    memset(c, 0, sizeof *c);
}
