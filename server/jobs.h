/* meristemd — a small pool of worker threads for work that may take seconds
 * (stepping, meshing), so libmicrohttpd's threads never wait on a tree: the
 * connection is suspended, the job runs here, and it resumes the connection. */
#ifndef MERISTEMD_JOBS_H
#define MERISTEMD_JOBS_H

#include <stddef.h>

typedef struct merd_jobs merd_jobs;
typedef void (*merd_job_fn)(void *arg);

/* Starts `threads` workers. NULL on failure. */
merd_jobs *merd_jobs_start(size_t threads);

/* Queues fn(arg); runs in submission order across the workers. 0, or -1 when
 * out of memory or stopping. */
int merd_jobs_submit(merd_jobs *jobs, merd_job_fn fn, void *arg);

/* Jobs queued and not yet started. */
size_t merd_jobs_pending(merd_jobs *jobs);

/* Runs every queued job, then joins the workers and frees the pool. NULL is fine. */
void merd_jobs_stop(merd_jobs *jobs);

#endif
