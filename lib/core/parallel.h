/* meristem — a parallel loop over independent items, on threads started and
 * joined within the call (lib/ keeps no thread pool: meristem/scene.h, no
 * global state). Not installed. */
#ifndef MERISTEM_CORE_PARALLEL_H
#define MERISTEM_CORE_PARALLEL_H

#include <stdint.h>

/* Item i's work; it must write only what is item i's own, so that the
 * results do not depend on which thread ran which item, or in what order. */
typedef void (*merp_item_fn)(void *ctx, uint32_t i);

/* Calls fn(ctx, i) once for every i in [0, n), on the caller's thread and up
 * to threads − 1 more (threads 0 or 1: all on the caller's), each taking the
 * next item not yet taken. When a thread cannot be started its share runs on
 * the others. Returns when every item is done. Cost: the items', plus
 * starting min(threads, n) − 1 threads. */
void merp_parallel_for(uint32_t n, uint32_t threads, merp_item_fn fn, void *ctx);

#endif
