/* meristemd — snapshots: GLB bytes shared between a session's cache and the
 * responses that send them, and the small per-session cache of variants.
 *
 * A page asks for its compact snapshot (meshopt, twig lines) while a person
 * downloads the default one: the cache keeps a few variants of the current
 * revision so neither evicts the other.
 */
#ifndef MERISTEMD_SNAPSHOT_H
#define MERISTEMD_SNAPSHOT_H

#include <stdatomic.h>
#include <stddef.h>
#include <stdint.h>

/* Variants of one session's tree kept at once. */
#define MERD_SNAPSHOT_VARIANTS 4

/* Room for a snapshot's key, its ETag: "\"r{revision}-{options}\"". */
#define MERD_ETAG_MAX 96

/* Immutable GLB bytes with a reference count. */
typedef struct merd_snapshot merd_snapshot;

/* Takes over `bytes` (freed with mer_gltf_free when the last reference goes),
 * with one reference. NULL when out of memory: `bytes` are then freed. */
merd_snapshot *merd_snapshot_new(uint8_t *bytes, size_t size);

/* A new reference to `snap`. */
merd_snapshot *merd_snapshot_ref(merd_snapshot *snap);

/* Drops a reference; `snap` may be NULL. */
void merd_snapshot_release(merd_snapshot *snap);

const uint8_t *merd_snapshot_bytes(const merd_snapshot *snap, size_t *size);

/* The cache: all zero is empty. Not locked: the session's `work` lock guards it. */
typedef struct merd_snapshot_cache {
    struct {
        merd_snapshot *snap; /* NULL: a free slot */
        uint64_t revision;
        uint64_t used;       /* the cache's clock when last asked for */
        char key[MERD_ETAG_MAX];
    } slot[MERD_SNAPSHOT_VARIANTS];
    uint64_t clock;
} merd_snapshot_cache;

/* A new reference to the snapshot stored under `key`, or NULL. */
merd_snapshot *merd_snapshot_cache_get(merd_snapshot_cache *c, const char *key);

/* Stores a reference to `snap` under `key` for `revision`. Variants of other
 * revisions go first (they can never be asked for again), then the least
 * recently used one. */
void merd_snapshot_cache_put(merd_snapshot_cache *c, uint64_t revision, const char *key,
                             merd_snapshot *snap);

/* Drops every reference the cache holds. */
void merd_snapshot_cache_clear(merd_snapshot_cache *c);

#endif
