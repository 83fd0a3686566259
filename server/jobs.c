/* meristemd — worker pool. */
#include "config.h"

#include <pthread.h>
#include <stdbool.h>
#include <stdlib.h>

#include "server/jobs.h"

typedef struct job {
    merd_job_fn fn;
    void *arg;
    struct job *next;
} job;

struct merd_jobs {
    pthread_mutex_t lock;
    pthread_cond_t ready;
    job *head, *tail;
    size_t pending, max_pending;
    bool stopping, drained;
    size_t threads;
    pthread_t *workers;
};

static void *worker(void *arg)
{
    merd_jobs *jobs = arg;
    for (;;) {
        pthread_mutex_lock(&jobs->lock);
        while (jobs->head == NULL && !jobs->stopping)
            pthread_cond_wait(&jobs->ready, &jobs->lock);
        job *j = jobs->head;
        if (j == NULL) {  // stopping, and nothing left to run
            pthread_mutex_unlock(&jobs->lock);
            return NULL;
        }
        jobs->head = j->next;
        if (jobs->head == NULL)
            jobs->tail = NULL;
        jobs->pending--;
        pthread_mutex_unlock(&jobs->lock);
        j->fn(j->arg);
        free(j);
    }
}

merd_jobs *merd_jobs_start(size_t threads, size_t max_queued)
{
    merd_jobs *jobs = calloc(1, sizeof *jobs);
    if (jobs == NULL)
        return NULL;
    jobs->max_pending = max_queued;
    pthread_mutex_init(&jobs->lock, NULL);
    pthread_cond_init(&jobs->ready, NULL);
    jobs->workers = calloc(threads, sizeof *jobs->workers);
    if (jobs->workers == NULL) {
        free(jobs);
        return NULL;
    }
    for (; jobs->threads < threads; jobs->threads++)
        if (pthread_create(&jobs->workers[jobs->threads], NULL, worker, jobs) != 0)
            break;
    if (jobs->threads == 0) {
        merd_jobs_stop(jobs);
        return NULL;
    }
    return jobs;
}

int merd_jobs_submit(merd_jobs *jobs, merd_job_fn fn, void *arg)
{
    job *j = malloc(sizeof *j);
    if (j == NULL)
        return MERD_JOBS_STOPPING;
    *j = (job){fn, arg, NULL};
    pthread_mutex_lock(&jobs->lock);
    if (jobs->stopping || jobs->pending >= jobs->max_pending) {
        int rc = jobs->stopping ? MERD_JOBS_STOPPING : MERD_JOBS_FULL;
        pthread_mutex_unlock(&jobs->lock);
        free(j);
        return rc;
    }
    if (jobs->tail != NULL)
        jobs->tail->next = j;
    else
        jobs->head = j;
    jobs->tail = j;
    jobs->pending++;
    pthread_cond_signal(&jobs->ready);
    pthread_mutex_unlock(&jobs->lock);
    return 0;
}

size_t merd_jobs_pending(merd_jobs *jobs)
{
    pthread_mutex_lock(&jobs->lock);
    size_t n = jobs->pending;
    pthread_mutex_unlock(&jobs->lock);
    return n;
}

void merd_jobs_drain(merd_jobs *jobs)
{
    pthread_mutex_lock(&jobs->lock);
    jobs->stopping = true;
    bool drained = jobs->drained;
    jobs->drained = true;
    pthread_cond_broadcast(&jobs->ready);
    pthread_mutex_unlock(&jobs->lock);
    if (!drained)
        for (size_t i = 0; i < jobs->threads; i++)
            pthread_join(jobs->workers[i], NULL);
}

void merd_jobs_stop(merd_jobs *jobs)
{
    if (jobs == NULL)
        return;
    merd_jobs_drain(jobs);
    free(jobs->workers);
    pthread_mutex_destroy(&jobs->lock);
    pthread_cond_destroy(&jobs->ready);
    free(jobs);
}
