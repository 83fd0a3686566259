/* meristemd — a session's state, shared by the files that implement
 * session.h: session.c (lifecycle, applying, journaling), session_summary.c
 * (the summary cache) and session_snapshot.c (snapshots). */
#ifndef MERISTEMD_SESSION_PRIVATE_H
#define MERISTEMD_SESSION_PRIVATE_H

#include <limits.h>
#include <pthread.h>
#include <stdatomic.h>

#include "server/session.h"
#include "server/snapshot.h"

struct merd_session {
    atomic_int refs;
    char id[33];
    char path[PATH_MAX];
    char checkpoint[PATH_MAX]; /* beside the journal: <id>.checkpoint */
    const merd_session_config *cfg;
    json_t *spec;            /* the create request, as journaled */

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
};

/* Caches the summary of the scene as it is (caller holds `work`) and makes
 * `revision` the session's. */
void merd_session_publish(merd_session *s, uint64_t revision);

#endif
