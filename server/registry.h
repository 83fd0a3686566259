/* meristemd — the live sessions by id, their creation, deletion and restore. */
#ifndef MERISTEMD_REGISTRY_H
#define MERISTEMD_REGISTRY_H

#include <stdint.h>
#include <stdio.h>

#include <jansson.h>

#include "server/session.h"

typedef struct mer_registry mer_registry;

/* `cfg` is borrowed for the registry's life. NULL when out of memory. */
mer_registry *mer_registry_new(const mer_session_config *cfg, uint32_t max_sessions);

/* Restores every *.journal in the data folder (creating the folder if need be),
 * logging each to `log`. Returns the number restored, or -1 if the folder cannot
 * be made or read (the reason is logged). */
long mer_registry_restore(mer_registry *r, FILE *log);

/* A new session from a create request, with a fresh 128-bit id from the OS.
 * On success *out holds a reference the caller releases. 429 when full. */
int mer_registry_create(mer_registry *r, const json_t *spec, mer_session **out, mer_refusal *why);

/* The session `id` with a reference the caller releases, or NULL. */
mer_session *mer_registry_get(mer_registry *r, const char *id);

/* Removes `id`: it stops, and its journal goes with its last reference. 0, or -1 if unknown. */
int mer_registry_delete(mer_registry *r, const char *id);

/* {"sessions": [short summaries]} in creation order (new reference). */
json_t *mer_registry_list(mer_registry *r);

/* Counts for metrics. */
void mer_registry_totals(mer_registry *r, uint32_t *sessions, uint64_t *internodes);

/* Flushes every journal written since the last call (for --fsync=interval). */
void mer_registry_sync(mer_registry *r);

/* Frees every session (journals stay on disk) and the registry. */
void mer_registry_free(mer_registry *r);

#endif
