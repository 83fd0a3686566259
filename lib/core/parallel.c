/* meristem — a parallel loop over independent items (parallel.h). */
#include "config.h"

#include <pthread.h>
#include <stdatomic.h>

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

void merp_parallel_for(uint32_t n, uint32_t threads, merp_item_fn fn, void *ctx)
{
    loop l = {fn, ctx, n, 0};
    uint32_t extra = threads > n ? n : threads;
    extra = extra > 0 ? extra - 1 : 0;
    pthread_t *t = extra > 0 ? merp_malloc(extra * sizeof *t) : NULL;
    uint32_t started = 0;
    for (; t != NULL && started < extra; started++)
        if (pthread_create(&t[started], NULL, run, &l) != 0)
            break; /* the rest runs on the threads we have */
    run(&l);
    for (uint32_t k = 0; k < started; k++)
        pthread_join(t[k], NULL);
    merp_free(t);
}
