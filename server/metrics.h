/* meristemd — counters for GET /v1/metrics (Prometheus text format 0.0.4). */
#ifndef MERISTEMD_METRICS_H
#define MERISTEMD_METRICS_H

#include <stddef.h>
#include <stdint.h>

typedef struct mer_metrics mer_metrics;

mer_metrics *mer_metrics_new(void);
void mer_metrics_free(mer_metrics *m);

/* Counts one request on route `route` (a static label such as
 * "/v1/sessions/{id}") answered with `status`. Lock-free. */
void mer_metrics_request(mer_metrics *m, const char *route, unsigned status);

/* Records one edit batch that stepped, and how long it took. */
void mer_metrics_step(mer_metrics *m, double seconds, uint32_t steps);

/* The exposition text (caller frees), with the gauges given. */
char *mer_metrics_render(mer_metrics *m, uint32_t sessions, uint64_t internodes, size_t jobs_pending);

#endif
