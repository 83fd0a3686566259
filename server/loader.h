/* meristemd — the background loader: after meristemd listens, one thread at
 * low priority loads the sessions not loaded yet, oldest first, so that a
 * restarted daemon warms up without making anyone wait for it. A request for a
 * session loads that one at once (merd_registry_get_loaded); the loader only
 * fills the time between requests: it waits while the workers have queued
 * jobs, and a session it is loading is loaded once, for both. */
#ifndef MERISTEMD_LOADER_H
#define MERISTEMD_LOADER_H

#include <stdio.h>

#include "server/jobs.h"
#include "server/registry.h"

typedef struct merd_loader merd_loader;

/* Starts loading the unloaded sessions of `registry` (borrowed until
 * merd_loader_stop), yielding to `jobs` (may be NULL); says on `log` how many
 * were restored and how long it took once done. NULL when no thread starts. */
merd_loader *merd_loader_start(merd_registry *registry, merd_jobs *jobs, FILE *log);

/* Stops the loader at the end of the session it is loading (it never stops
 * halfway through one) and joins it. NULL is fine. */
void merd_loader_stop(merd_loader *l);

#endif
