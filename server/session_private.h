/* meristemd — a session's state, shared by the files that implement
 * session.h: session.c (lifecycle, applying, journaling), session_load.c
 * (loading from checkpoint and journal, compaction), session_summary.c (the
 * summary cache) and session_snapshot.c (snapshots). */
#ifndef MERISTEMD_SESSION_PRIVATE_H
#define MERISTEMD_SESSION_PRIVATE_H

#include <limits.h>
#include <pthread.h>
#include <stdatomic.h>

#include "server/revisions.h"
#include "server/session.h"
#include "server/snapshot.h"

/* Where a session is in its loading (see merd_session_load). */
enum { MERD_NOT_LOADED = 0, MERD_LOADED = 1, MERD_LOAD_FAILED = 2 };

struct merd_session {
    atomic_int refs;
    atomic_int loaded;       /* MERD_NOT_LOADED etc.; changes only while `work` is held */
    char id[33];
    char path[PATH_MAX];
    char checkpoint[PATH_MAX]; /* beside the journal: <id>.checkpoint */
    const merd_session_config *cfg;
    json_t *spec;            /* the create request, as journaled */
    double expires_at;       /* Unix time after which the session goes; 0: never */

    pthread_mutex_t work;    /* held while the scene changes or is meshed */
    mer_scene *scene;
    merd_journal *journal;

    pthread_mutex_t state;   /* guards what follows */
    uint64_t revision;
    json_t *summary;         /* after the last accepted batch */
    char *summary_text;      /* the same, full, serialized, without its closing brace */
    char *short_text;        /* without params and schedule, likewise */
    uint32_t internodes;
    bool running;
    uint32_t done, total;    /* progress of the running batch */
    atomic_int cancel;
    bool discarded;
    merd_snapshot_cache snaps; /* guarded by `work` */
    merd_revisions *revs;      /* guarded by `work` */
};

/* A session of id `id` with nothing loaded (scene, journal and spec NULL). */
merd_session *merd_session_new(const merd_session_config *cfg, const char *id);

/* Builds the session's scene again from its checkpoint and journal (caller
 * holds `work`; the session is loaded): how a refused batch is undone when no
 * copy was taken. 0, or -1 with a reason in `error` (MERD_JOURNAL_ERROR_MAX). */
int merd_session_rebuild(merd_session *s, char *error);

/* After a checkpoint at `revision`, the last record's (caller holds `work`):
 * with --compact, drops the journal records it covers (see session_load.c). */
void merd_session_compact(merd_session *s, uint64_t revision);

/* Caches the summary of the scene as it is (caller holds `work`) and makes
 * `revision` the session's. */
void merd_session_publish(merd_session *s, uint64_t revision);

/* Where a revert of `s` finds past revisions (session_history.c). */
merd_past merd_session_past(merd_session *s);

/* Records revision `revision` of `s` with its `edits` (borrowed) and the step
 * and internodes of `record` (a journal record holding them) or, when it has
 * none, of the scene as it is (caller holds `work`). */
void merd_session_record(merd_session *s, uint64_t revision, const json_t *edits,
                         const json_t *record);

/* The tree of `scene` at `revision` as GLB for `options` (caller holds `work`). */
int merd_session_build(merd_session *s, const mer_scene *scene, uint64_t revision,
                       const merd_snapshot_options *options, merd_snapshot **out,
                       merd_refusal *why);

#endif
