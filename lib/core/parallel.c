/* meristem — a parallel loop over independent items (parallel.h). */
#include "config.h"

#include <pthread.h>
#include <stdatomic.h>
#include <stdbool.h>

#include "core/alloc.h"
#include "core/parallel.h"

typedef struct loop {
    merp_item_fn fn;
    void *ctx;
    uint32_t n;
    atomic_uint next; /* the next item not yet taken */
} loop;

static void *run(void *arg)
{
    loop *l = arg;
    for (uint32_t i; (i = atomic_fetch_add(&l->next, 1u)) < l->n;)
        l->fn(l->ctx, i);
    return NULL;
}

/* A worker's stack, as glibc's threads have by default: a junction patch's
 * frames take some 110 KB (its prepared run of up to 64 forks, 39 KB, twice
 * over), more than some C libraries give a thread (musl: 128 KB). */
#define WORKER_STACK (8u << 20)

void merp_parallel_for(uint32_t n, uint32_t threads, merp_item_fn fn, void *ctx)
{
    loop l = {fn, ctx, n, 0};
    uint32_t extra = threads > n ? n : threads;
    extra = extra > 0 ? extra - 1 : 0;
    pthread_t *t = extra > 0 ? merp_malloc(extra * sizeof *t) : NULL;
    uint32_t started = 0;
    pthread_attr_t attr;
    bool sized = t != NULL && pthread_attr_init(&attr) == 0;
    if (sized && pthread_attr_setstacksize(&attr, WORKER_STACK) != 0) {
        pthread_attr_destroy(&attr);
        sized = false;
    }
    for (; t != NULL && started < extra; started++)
        if (pthread_create(&t[started], sized ? &attr : NULL, run, &l) != 0)
            break; /* the rest runs on the threads we have */
    if (sized)
        pthread_attr_destroy(&attr);
    run(&l);
    for (uint32_t k = 0; k < started; k++)
        pthread_join(t[k], NULL);
    merp_free(t);
}
