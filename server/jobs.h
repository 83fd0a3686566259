/* meristemd — a small pool of worker threads for work that may take seconds
 * (stepping, meshing), so libmicrohttpd's threads never wait on a tree: the
 * connection is suspended, the job runs here, and it resumes the connection. */
#ifndef MERISTEMD_JOBS_H
#define MERISTEMD_JOBS_H

#include <stddef.h>

typedef struct merd_jobs merd_jobs;
typedef void (*merd_job_fn)(void *arg);

/* Starts `threads` workers and a queue of at most `max_queued` jobs waiting
 * for one. NULL on failure. */
merd_jobs *merd_jobs_start(size_t threads, size_t max_queued);

enum { MERD_JOBS_STOPPING = -1, MERD_JOBS_FULL = -2 };

/* Queues fn(arg); runs in submission order across the workers. 0;
 * MERD_JOBS_FULL when `max_queued` jobs already wait (answer 503 and let the
 * client retry rather than let requests wait for seconds); MERD_JOBS_STOPPING
 * when out of memory or stopping. O(1). */
int merd_jobs_submit(merd_jobs *jobs, merd_job_fn fn, void *arg);

/* Jobs queued and not yet started. */
size_t merd_jobs_pending(merd_jobs *jobs);

/* Refuses new jobs, runs every queued one and joins the workers; the pool
 * stays valid (submit answers MERD_JOBS_STOPPING) until merd_jobs_stop. */
void merd_jobs_drain(merd_jobs *jobs);

/* Drains (if not done yet) and frees the pool. NULL is fine. */
void merd_jobs_stop(merd_jobs *jobs);

#endif
