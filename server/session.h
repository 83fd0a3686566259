/* meristemd — one live tree session: its scene, revision, journal and caches.
 *
 * Locking. `work` (held while the scene changes or is meshed) serializes edits
 * and snapshots of one session; sessions are independent, so they step in
 * parallel. `state` guards the small things readers want while a step runs:
 * the cached summary, the revision and the progress. A summary never waits for
 * a running step.
 *
 * Durability. An edit batch is applied, then journaled (and fsync'ed), and only
 * then made visible (revision + 1) and acknowledged. A batch refused halfway, or
 * one whose journal write fails, is undone by rebuilding the scene from the
 * journal: the engine is deterministic, so the rebuilt scene is the one before.
 */
#ifndef MERISTEMD_SESSION_H
#define MERISTEMD_SESSION_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <jansson.h>

#include <meristem.h>

#include "server/edits.h"
#include "server/journal.h"

typedef struct mer_session mer_session;

typedef struct mer_session_config {
    const char *data_dir;
    mer_fsync_mode fsync;
    mer_edit_limits limits;      /* per request */
    uint32_t max_internodes;     /* per session: a batch stops growing past it */
    double max_seconds;          /* per request: a batch stops at the step that passes it */
    size_t max_obstacle_triangles;
} mer_session_config;

/* Creates a session with id `id` (32 hex digits) from a create request `spec`
 * (borrowed): builds the scene and writes the journal's first record. NULL with
 * `why` filled on a refusal (400/422 for the spec, 500 for the disk). */
mer_session *mer_session_create(const mer_session_config *cfg, const char *id, const json_t *spec,
                                mer_refusal *why);

/* Restores the session journaled at `path` by replaying it. NULL with a reason
 * in `error` (MER_JOURNAL_ERROR_MAX bytes). `*dropped` gets a torn tail's bytes. */
mer_session *mer_session_restore(const mer_session_config *cfg, const char *path,
                                 size_t *dropped, char *error);

/* Reference counting: a session stays alive while a request uses it, even after
 * it is deleted from the registry. */
void mer_session_ref(mer_session *s);
void mer_session_unref(mer_session *s);

const char *mer_session_id(const mer_session *s);
uint64_t mer_session_revision(mer_session *s);

/* The summary (new reference). `full` adds params and schedule. Never waits for
 * a running step: it shows the state after the last accepted batch and the
 * progress of the running one. */
json_t *mer_session_summary(mer_session *s, bool full);

/* The same summary as text (caller frees), from text cached when the batch was
 * accepted: the fast path of GET /v1/sessions/{id}. NULL when out of memory. */
char *mer_session_summary_text(mer_session *s, bool full, uint64_t *revision);

/* Applies a decoded batch: all or none (see above), stopping early on cancel,
 * the time limit or the internode limit, keeping whole steps. Returns 0 and the
 * outcome, or -1 with `why`. Blocks while another batch of this session runs. */
int mer_session_apply(mer_session *s, const mer_batch *batch, mer_batch_outcome *outcome,
                      mer_refusal *why);

/* Asks the running batch, if any, to stop at its next whole step. Returns
 * whether a batch was running. */
bool mer_session_cancel(mer_session *s);

typedef struct mer_snapshot_options {
    mer_mesh_options mesh;
    uint32_t unquantized;
    uint32_t compression; /* mer_gltf_compression */
} mer_snapshot_options;

/* The current tree as GLB for `options`, from the per-session cache when the
 * revision and options are those of the last snapshot. `*bytes` is a new
 * reference to shared, immutable bytes: release with mer_snapshot_release.
 * `etag` gets "\"r{revision}-{options}\"" (64 bytes). 0, or -1 with `why`. */
typedef struct mer_snapshot mer_snapshot;
int mer_session_snapshot(mer_session *s, const mer_snapshot_options *options,
                         mer_snapshot **out, char *etag, mer_refusal *why);
const uint8_t *mer_snapshot_bytes(const mer_snapshot *snap, size_t *size);
void mer_snapshot_release(mer_snapshot *snap);

/* The ETag a snapshot of `options` would have now (for If-None-Match without meshing). */
void mer_session_etag(mer_session *s, const mer_snapshot_options *options, char *etag);

/* Living internodes after the last accepted batch (for metrics). */
uint32_t mer_session_internodes(mer_session *s);

/* Flushes the journal if no batch holds the session right now (a busy one is
 * flushed on the next call). For --fsync=interval. */
void mer_session_sync(mer_session *s);

/* Marks the session deleted: its journal is removed when the last reference goes. */
void mer_session_discard(mer_session *s);

#endif
