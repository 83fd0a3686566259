/* meristemd — counters for GET /v1/metrics (Prometheus text format 0.0.4). */
#ifndef MERISTEMD_METRICS_H
#define MERISTEMD_METRICS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

struct merd_cores;

typedef struct merd_metrics merd_metrics;

merd_metrics *merd_metrics_new(void);
void merd_metrics_free(merd_metrics *m);

/* Counts one request on route `route` (a static label such as
 * "/v1/sessions/{id}") answered with `status`. Lock-free. */
void merd_metrics_request(merd_metrics *m, const char *route, unsigned status);

/* Records one edit batch that stepped, and how long it took. */
void merd_metrics_step(merd_metrics *m, double seconds, uint32_t steps);

/* Records one snapshot sent: `cached` when the session's cache held it. */
void merd_metrics_snapshot(merd_metrics *m, bool cached);

/* The exposition text (caller frees), with the gauges given and the leases
 * of `cores` (may be NULL: none). */
char *merd_metrics_render(merd_metrics *m, uint32_t sessions, uint64_t internodes, size_t jobs_pending,
                          const struct merd_cores *cores);

#endif
