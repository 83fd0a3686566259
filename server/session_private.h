/* meristemd — a session's state, shared by the files that implement
 * session.h: session.c (lifecycle, applying, journaling), session_summary.c
 * (the summary cache) and session_snapshot.c (snapshots). */
#ifndef MERISTEMD_SESSION_PRIVATE_H
#define MERISTEMD_SESSION_PRIVATE_H

#include <limits.h>
#include <pthread.h>
#include <stdatomic.h>

#include "server/revisions.h"
#include "server/session.h"
#include "server/snapshot.h"

struct merd_session {
    atomic_int refs;
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
