/* meristemd — the background loader (see loader.h). */
#include "config.h"

#include <pthread.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stdlib.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>
#ifdef __linux__
#include <sys/syscall.h>
#endif

#include "server/clock.h"
#include "server/loader.h"

struct merd_loader {
    pthread_t thread;
    merd_registry *registry;
    merd_jobs *jobs;
    FILE *log;
    atomic_int stop;
};

/* Waits while requests wait for a worker, or until asked to stop. */
static void yield_to_requests(merd_loader *l)
{
    const struct timespec pause = {0, 5 * 1000000L};
    while (!atomic_load(&l->stop) && l->jobs != NULL && merd_jobs_pending(l->jobs) > 0)
        nanosleep(&pause, NULL);
}

static void *run(void *arg)
{
    merd_loader *l = arg;
#ifdef __linux__
    // Linux gives each thread its own nice value: this one yields the CPU to
    // the threads that answer requests.
    setpriority(PRIO_PROCESS, (id_t)syscall(SYS_gettid), 10);
#endif
    double t0 = merd_now();
    size_t n = 0, restored = 0;
    merd_session **sessions = merd_registry_unloaded(l->registry, &n);
    for (size_t i = 0; i < n; i++) {
        yield_to_requests(l);
        merd_refusal why;
        if (!atomic_load(&l->stop))
            restored += merd_registry_load(l->registry, sessions[i], &why) == 0;
        merd_session_unref(sessions[i]);
    }
    free(sessions);
    if (!atomic_load(&l->stop) && n > 0)
        fprintf(l->log, "meristemd: restored %zu sessions in the background in %.2f s\n", restored,
                merd_now() - t0);
    return NULL;
}

merd_loader *merd_loader_start(merd_registry *registry, merd_jobs *jobs, FILE *log)
{
    merd_loader *l = calloc(1, sizeof *l);
    if (l == NULL)
        return NULL;
    l->registry = registry;
    l->jobs = jobs;
    l->log = log;
    atomic_init(&l->stop, 0);
    if (pthread_create(&l->thread, NULL, run, l) != 0) {
        free(l);
        return NULL;
    }
    return l;
}

void merd_loader_stop(merd_loader *l)
{
    if (l == NULL)
        return;
    atomic_store(&l->stop, 1);
    pthread_join(l->thread, NULL);
    free(l);
}
