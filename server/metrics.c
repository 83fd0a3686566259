/* meristemd — metrics. Requests are counted in a fixed table of route × status
 * slots with atomic counters: no lock on the request path. */
#include "config.h"

#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "server/metrics.h"

#include "server/cores.h"

#define ROUTES 16
#define STATUSES 24

static const double buckets[] = {0.005, 0.01, 0.025, 0.05, 0.1, 0.25, 0.5, 1, 2.5, 5, 10, 30, 60};
#define BUCKETS (sizeof buckets / sizeof buckets[0])

struct merd_metrics {
    _Atomic(const char *) routes[ROUTES]; /* labels, filled once, first come first served */
    atomic_uint statuses[STATUSES];
    atomic_uint_fast64_t count[ROUTES][STATUSES];
    atomic_int claim;                   /* guards the label tables' growth */
    atomic_uint_fast64_t step_bucket[BUCKETS + 1];
    atomic_uint_fast64_t step_count, steps;
    _Atomic double step_sum;
    atomic_uint_fast64_t snapshot_hits, snapshot_misses;
};

merd_metrics *merd_metrics_new(void)
{
    return calloc(1, sizeof(merd_metrics));
}

void merd_metrics_free(merd_metrics *m)
{
    free(m);
}

static void lock(merd_metrics *m)
{
    int expected = 0;
    while (!atomic_compare_exchange_weak(&m->claim, &expected, 1))
        expected = 0;
}

/* The slot of a route label or a status, claiming a free one on first sight.
 * Slots are only ever filled, never emptied, so readers need no lock. */
static int route_slot(merd_metrics *m, const char *route)
{
    for (int i = 0; i < ROUTES; i++) {
        const char *have = atomic_load(&m->routes[i]);
        if (have == route)
            return i;
        if (have == NULL) {
            lock(m);
            if (atomic_load(&m->routes[i]) == NULL)
                atomic_store(&m->routes[i], route);
            atomic_store(&m->claim, 0);
            if (atomic_load(&m->routes[i]) == route)
                return i;
        }
    }
    return -1;
}

static int status_slot(merd_metrics *m, unsigned status)
{
    for (int i = 0; i < STATUSES; i++) {
        unsigned have = atomic_load(&m->statuses[i]);
        if (have == status)
            return i;
        if (have == 0) {
            lock(m);
            if (atomic_load(&m->statuses[i]) == 0)
                atomic_store(&m->statuses[i], status);
            atomic_store(&m->claim, 0);
            if (atomic_load(&m->statuses[i]) == status)
                return i;
        }
    }
    return -1;
}

void merd_metrics_request(merd_metrics *m, const char *route, unsigned status)
{
    int r = route_slot(m, route), s = status_slot(m, status);
    if (r >= 0 && s >= 0)
        atomic_fetch_add(&m->count[r][s], 1);
}

void merd_metrics_step(merd_metrics *m, double seconds, uint32_t steps)
{
    size_t b = 0;
    while (b < BUCKETS && seconds > buckets[b])
        b++;
    atomic_fetch_add(&m->step_bucket[b], 1);
    atomic_fetch_add(&m->step_count, 1);
    atomic_fetch_add(&m->steps, steps);
    double old = atomic_load(&m->step_sum);
    while (!atomic_compare_exchange_weak(&m->step_sum, &old, old + seconds))
        ;
}

void merd_metrics_snapshot(merd_metrics *m, bool cached)
{
    atomic_fetch_add(cached ? &m->snapshot_hits : &m->snapshot_misses, 1);
}

char *merd_metrics_render(merd_metrics *m, uint32_t sessions, uint64_t internodes, size_t jobs_pending,
                          const struct merd_cores *cores)
{
    char *text = NULL;
    size_t size = 0;
    FILE *f = open_memstream(&text, &size);
    if (f == NULL)
        return NULL;
    fprintf(f, "# HELP meristem_requests_total HTTP requests by route and status.\n"
               "# TYPE meristem_requests_total counter\n");
    for (size_t r = 0; r < ROUTES && atomic_load(&m->routes[r]); r++)
        for (size_t s = 0; s < STATUSES && atomic_load(&m->statuses[s]); s++) {
            uint64_t n = atomic_load(&m->count[r][s]);
            if (n)
                fprintf(f, "meristem_requests_total{route=\"%s\",status=\"%u\"} %llu\n",
                        atomic_load(&m->routes[r]), atomic_load(&m->statuses[s]),
                        (unsigned long long)n);
        }
    fprintf(f, "# HELP meristem_step_seconds Time to apply an edit batch that stepped.\n"
               "# TYPE meristem_step_seconds histogram\n");
    uint64_t cumulative = 0;
    for (size_t b = 0; b < BUCKETS; b++) {
        cumulative += atomic_load(&m->step_bucket[b]);
        fprintf(f, "meristem_step_seconds_bucket{le=\"%g\"} %llu\n", buckets[b],
                (unsigned long long)cumulative);
    }
    cumulative += atomic_load(&m->step_bucket[BUCKETS]);
    fprintf(f, "meristem_step_seconds_bucket{le=\"+Inf\"} %llu\n", (unsigned long long)cumulative);
    fprintf(f, "meristem_step_seconds_sum %.6f\nmeristem_step_seconds_count %llu\n",
            atomic_load(&m->step_sum), (unsigned long long)atomic_load(&m->step_count));
    fprintf(f, "# HELP meristem_steps_total Simulation steps run.\n# TYPE meristem_steps_total counter\n"
               "meristem_steps_total %llu\n", (unsigned long long)atomic_load(&m->steps));
    fprintf(f, "# HELP meristem_snapshot_cache_total Snapshots sent, by whether the session's "
               "cache of variants held them.\n# TYPE meristem_snapshot_cache_total counter\n"
               "meristem_snapshot_cache_total{result=\"hit\"} %llu\n"
               "meristem_snapshot_cache_total{result=\"miss\"} %llu\n",
            (unsigned long long)atomic_load(&m->snapshot_hits),
            (unsigned long long)atomic_load(&m->snapshot_misses));
    fprintf(f, "# HELP meristem_sessions Live sessions.\n# TYPE meristem_sessions gauge\n"
               "meristem_sessions %u\n", sessions);
    fprintf(f, "# HELP meristem_internodes Living internodes in all sessions.\n"
               "# TYPE meristem_internodes gauge\nmeristem_internodes %llu\n",
            (unsigned long long)internodes);
    fprintf(f, "# HELP meristem_jobs_pending Edit and snapshot jobs waiting for a worker.\n"
               "# TYPE meristem_jobs_pending gauge\nmeristem_jobs_pending %zu\n", jobs_pending);
    if (cores != NULL)
        fprintf(f, "# HELP meristem_patch_leases_total Snapshots with implicit junctions whose patches "
                   "were built on lent cores.\n# TYPE meristem_patch_leases_total counter\n"
                   "meristem_patch_leases_total %llu\n"
                   "# HELP meristem_patch_threads_total Threads those snapshots' patches were lent, "
                   "in all.\n# TYPE meristem_patch_threads_total counter\n"
                   "meristem_patch_threads_total %llu\n",
                (unsigned long long)atomic_load(&cores->leases), (unsigned long long)atomic_load(&cores->lent));
    fclose(f);
    return text;
}
