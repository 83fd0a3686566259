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
 * checkpoint and the journal: the engine is deterministic, so the rebuilt
 * scene is the one before.
 *
 * Loading. A session restored from the data folder starts unloaded (its
 * journal not read) and is loaded by its first request or by the background
 * loader (loader.h), so meristemd listens before reading any journal.
 */
#ifndef MERISTEMD_SESSION_H
#define MERISTEMD_SESSION_H

#include <stdatomic.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <jansson.h>

#include <meristem.h>

#include "server/cores.h"
#include "server/edits.h"
#include "server/journal.h"
#include "server/snapshot.h"

typedef struct merd_session merd_session;

typedef struct merd_session_config {
    const char *data_dir;
    merd_fsync_mode fsync;
    merd_edit_limits limits;      /* per request */
    uint32_t max_internodes;     /* per session: a batch stops growing past it */
    double max_seconds;          /* per request: a batch stops at the step that passes it */
    size_t max_obstacle_triangles;
    const atomic_int *stopping;  /* when set and non-zero: batches stop at the next whole step */
    uint32_t checkpoint_every;   /* revisions between checkpoints; 0: none */
    bool compact;                /* drop the journal records a checkpoint covers */
    uint32_t patch_threads;      /* threads one snapshot's junction patches take; 0: those
                                    `cores` lends it, or without it all the cores */
    merd_cores *cores;           /* the cores lent to the snapshots meshed at once, or NULL */
} merd_session_config;

/* Creates a session with id `id` (32 hex digits) from a create request `spec`
 * (borrowed): builds the scene and writes the journal's first record. NULL with
 * `why` filled on a refusal (as merd_scene_from_spec says, or 500 for the disk). */
merd_session *merd_session_create(const merd_session_config *cfg, const char *id, const json_t *spec,
                                  double expires_at, merd_refusal *why);

/* The Unix time after which the session should be removed (its creation's
 * ttl_seconds, kept in the journal), or 0 for never. */
double merd_session_expires(const merd_session *s);

/* A session known only by its id, whose journal <data-dir>/<id>.journal is
 * loaded later (merd_session_load): no I/O, O(1). Its summary says
 * {"id", "state": "not loaded"} until then. NULL when out of memory. */
merd_session *merd_session_unloaded(const merd_session_config *cfg, const char *id);

/* Called once, by the call that loaded (or failed to load) a session, while
 * it still holds the session: `error` is NULL when it loaded (`report` may
 * still say a torn tail was dropped), else why not, with `report->fault`. */
typedef void (*merd_session_loaded_fn)(void *ctx, merd_session *s, const merd_journal_report *report,
                                       const char *error);

/* Ensures the session is loaded: from its checkpoint and the journal records
 * after it, or, without a checkpoint that fits, by replaying the whole
 * journal. Concurrent callers load it once: the others wait for that load
 * (and for `done`, which only the loading call runs) and share its outcome.
 * 0 when loaded, -1 when it could not be (now or by an earlier call). A
 * loaded session returns at once. Cost: reading the journal and checkpoint,
 * and replaying at most --checkpoint-every records (all, without one). */
int merd_session_load(merd_session *s, merd_session_loaded_fn done, void *ctx);

/* Whether the session is loaded (never waits). */
bool merd_session_is_loaded(merd_session *s);

/* Reference counting: a session stays alive while a request uses it, even after
 * it is deleted from the registry. */
void merd_session_ref(merd_session *s);
void merd_session_unref(merd_session *s);

const char *merd_session_id(const merd_session *s);
uint64_t merd_session_revision(merd_session *s);

/* The summary (new reference). `full` adds params and schedule. Never waits for
 * a running step: it shows the state after the last accepted batch and the
 * progress of the running one. Of a session not loaded: {id, state: "not
 * loaded"}. */
json_t *merd_session_summary(merd_session *s, bool full);

/* The same summary as text (caller frees), from text cached when the batch was
 * accepted: the fast path of GET /v1/sessions/{id}. NULL when out of memory. */
char *merd_session_summary_text(merd_session *s, bool full, uint64_t *revision);

/* Applies a decoded batch to a loaded session (merd_session_load): all or
 * none (see above), stopping early on cancel, the time limit or the internode
 * limit, keeping whole steps. Returns 0 and the
 * outcome, or -1 with `why`. Blocks while another batch of this session runs. */
int merd_session_apply(merd_session *s, const merd_batch *batch, merd_batch_outcome *outcome,
                       merd_refusal *why);

/* Asks the running batch, if any, to stop at its next whole step. Returns
 * whether a batch was running. */
bool merd_session_cancel(merd_session *s);

typedef struct merd_snapshot_options {
    mer_mesh_options mesh;
    uint32_t unquantized;
    uint32_t compression; /* mer_gltf_compression */
    /* The tree at a fractional time (mer_scene_show_time), in millionths of a
     * step, when at_t: meshed from a copy, the session unchanged. */
    bool at_t;
    uint64_t t_micro;
} merd_snapshot_options;

/* The current tree of a loaded session as GLB for `options`, from the session's cache of variants
 * when one of this revision and these options is there (`*cached` says so).
 * `*out` is a new reference to shared, immutable bytes: release with
 * merd_snapshot_release. `etag` gets "\"r{revision}-{options}\""
 * (MERD_ETAG_MAX bytes). 0, or -1 with `why`. Blocks while a batch runs. */
int merd_session_snapshot(merd_session *s, const merd_snapshot_options *options,
                          merd_snapshot **out, char *etag, bool *cached, merd_refusal *why);

/* The ETag a snapshot of `options` would have now (for If-None-Match without meshing). */
void merd_session_etag(merd_session *s, const merd_snapshot_options *options, char *etag);

/* The ETag of a snapshot of `revision` with `options`. */
void merd_session_etag_at(uint64_t revision, const merd_snapshot_options *options, char *etag);

/* The tree at past `revision` as GLB for `options`: derived (revisions.h) and
 * meshed, or taken from the session's kept past snapshots (`*cached`). As
 * merd_session_snapshot otherwise; 422 naming "revision" for a revision the
 * session does not have. Blocks while a batch runs. */
int merd_session_snapshot_at(merd_session *s, uint64_t revision,
                             const merd_snapshot_options *options, merd_snapshot **out,
                             char *etag, bool *cached, merd_refusal *why);

/* {"revisions": [...], "next_after": N|null}: a page of the session's
 * revisions after `after` (from 0 when `from_start`), at most `limit`, oldest
 * first (see merd_revisions_page). New reference. Blocks while a batch runs. */
json_t *merd_session_revisions(merd_session *s, uint64_t after, bool from_start, size_t limit);

/* {"revision": R, "nodes": [...]}: the skeleton of the tree, one object per
 * internode ever issued (only the living ones when `alive_only`). New
 * reference, NULL when out of memory. Blocks while a batch runs. O(nodes). */
json_t *merd_session_skeleton(merd_session *s, bool alive_only);

/* The .fset text of an inverse-model session's functions (its definition from
 * the line "funcgalleryver" on), a malloc'd copy of `*len` bytes and a NUL;
 * NULL for a session of another model or out of memory (then *len is 0 or 1).
 * Blocks while a batch runs. O(text). */
char *merd_session_functions(merd_session *s, size_t *len);

/* The cpfg source of an L-system session, as merd_session_functions gives an
 * inverse session's functions (NULL for another model). O(text). */
char *merd_session_lsystem(merd_session *s, size_t *len);

/* Living internodes after the last accepted batch (for metrics). */
uint32_t merd_session_internodes(merd_session *s);

/* Flushes the journal if no batch holds the session right now (a busy one is
 * flushed on the next call). For --fsync=interval. */
void merd_session_sync(merd_session *s);

/* Marks the session deleted and removes its journal durably (unlinked, folder
 * synced) before returning, even while a batch runs: that batch is cancelled
 * and journals nothing more. 0, or -1 with `error` (MERD_JOURNAL_ERROR_MAX
 * bytes) when the file could not be removed. */
int merd_session_discard(merd_session *s, char *error);

#endif
