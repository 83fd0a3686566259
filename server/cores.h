/* meristemd — the machine's cores, lent to the snapshots being meshed at once.
 *
 * A snapshot with implicit junctions builds its patches on threads, and its
 * bytes are the same whatever their number (mer_mesh_options.threads). With
 * a fixed share (the cores divided by the workers) a lone user brushing with
 * junctions on got one thread of two idle cores. A lease instead gives a
 * snapshot every core the other snapshots being meshed have not taken, at
 * least one: alone it has them all; when several start at once, the later
 * ones take one each, so the cores are oversubscribed by at most a thread
 * per snapshot until the earlier ones finish. Threads that step trees are
 * not counted (a growth batch beside a snapshot shares its cores).
 *
 * Thread-safe: take and give are lock-free. */
#ifndef MERISTEMD_CORES_H
#define MERISTEMD_CORES_H

#include <stdatomic.h>
#include <stdint.h>

typedef struct merd_cores {
    uint32_t total;              /* the cores to lend, at least 1 */
    atomic_uint in_use;          /* lent and not yet given back */
    atomic_uint_fast64_t leases; /* merd_cores_take's calls so far (GET /v1/metrics) */
    atomic_uint_fast64_t lent;   /* the cores they lent, in all */
} merd_cores;

/* A pool of `total` cores (at least 1), none lent. */
void merd_cores_init(merd_cores *c, uint32_t total);

/* Lends the cores that are free, at least 1: returns their number, to give
 * back with merd_cores_give. */
uint32_t merd_cores_take(merd_cores *c);

/* Gives back `n` cores that merd_cores_take lent. */
void merd_cores_give(merd_cores *c, uint32_t n);

#endif
