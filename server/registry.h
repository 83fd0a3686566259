/* meristemd — the live sessions by id, their creation, deletion and restore. */
#ifndef MERISTEMD_REGISTRY_H
#define MERISTEMD_REGISTRY_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include <jansson.h>

#include "server/session.h"

typedef struct merd_registry merd_registry;

/* `cfg` is borrowed for the registry's life. NULL when out of memory. */
merd_registry *merd_registry_new(const merd_session_config *cfg, uint32_t max_sessions);

/* Registers every *.journal in the data folder (creating the folder if need
 * be) as a session not loaded yet, oldest journal first, and lists the
 * quarantine, logging to `log`. Reads no journal: one lstat per file. Returns
 * the number registered, or -1 if the folder cannot be made or read (the
 * reason is logged). */
long merd_registry_scan(merd_registry *r, FILE *log);

/* Ensures `s` (a session of `r`) is loaded; see merd_session_load. A journal
 * that cannot be loaded is quarantined (see quarantine.h), one that is wholly
 * a torn creation removed, and either way the session leaves the registry.
 * 0, or -1 with `why`: 503 quarantined, or 404. */
int merd_registry_load(merd_registry *r, merd_session *s, merd_refusal *why);

/* Ensure session loaded: the session `id`, loaded (merd_registry_load), with a
 * reference the caller releases; NULL with `why` (404, or 503 quarantined).
 * What every request about one session calls first. */
merd_session *merd_registry_get_loaded(merd_registry *r, const char *id, merd_refusal *why);

/* The sessions not loaded yet, in list order, each with a reference the
 * caller releases, in an array the caller frees (NULL when out of memory). */
merd_session **merd_registry_unloaded(merd_registry *r, size_t *n);

/* A new session from a create request, with a fresh 128-bit id from the OS.
 * On success *out holds a reference the caller releases. 429 when full. */
int merd_registry_create(merd_registry *r, const json_t *spec, merd_session **out, merd_refusal *why);

/* The session `id` with a reference the caller releases, or NULL. It may not
 * be loaded yet: merd_registry_get_loaded is what requests want. */
merd_session *merd_registry_get(merd_registry *r, const char *id);

/* Removes `id`: a running batch is cancelled and the journal is durably
 * removed before this returns. 0, or -1 with `why`: 404 if unknown, 500 if the
 * journal could not be removed. */
int merd_registry_delete(merd_registry *r, const char *id, merd_refusal *why);

/* Whether `id` is quarantined; if so, `why` gets the 503 to answer with. */
bool merd_registry_quarantined(merd_registry *r, const char *id, merd_refusal *why);

/* What GET /v1/sessions asks for (all borrowed; NULL: no filter). */
typedef struct merd_list_query {
    const char *after;   /* the id the previous page ended with */
    size_t limit;        /* at most this many sessions */
    const char *preset;  /* only sessions of this preset */
    const char *state;   /* only "loaded", "not loaded", "running", "idle", "live"
                          * (any but quarantined) or "quarantined" */
} merd_list_query;

/* {"sessions": [...], "next_after": id|null}: the sessions in list order
 * (restored sessions oldest first, then new ones as created): a loaded
 * session's short summary with state "loaded", {id, state: "not loaded"} for
 * one not loaded yet (listing never loads it), then the quarantined ones as
 * {id, state: "quarantined", reason}; filtered and paged by `q`; next_after is the `after` of the next
 * page, null on the last. New reference. O(sessions). */
json_t *merd_registry_list(merd_registry *r, const merd_list_query *q);

/* Removes, as merd_registry_delete does, every session whose time to live
 * (ttl_seconds at creation) has passed at Unix time `now`, logging each to
 * `log`. Returns how many were removed. */
size_t merd_registry_expire(merd_registry *r, double now, FILE *log);

/* Counts for metrics. */
void merd_registry_totals(merd_registry *r, uint32_t *sessions, uint64_t *internodes);

/* Flushes every journal written since the last call (for --fsync=interval). */
void merd_registry_sync(merd_registry *r);

/* Frees every session (journals stay on disk) and the registry. */
void merd_registry_free(merd_registry *r);

#endif
