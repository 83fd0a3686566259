/* meristemd — the machine's cores, lent to the snapshots being meshed at once
 * (see cores.h). */
#include "config.h"

#include "server/cores.h"

#include <assert.h>

void merd_cores_init(merd_cores *c, uint32_t total)
{
    assert(total >= 1);
    c->total = total;
    atomic_init(&c->in_use, 0u);
    atomic_init(&c->leases, 0u);
    atomic_init(&c->lent, 0u);
}

uint32_t merd_cores_take(merd_cores *c)
{
    unsigned used = atomic_load(&c->in_use), n;
    do {
        n = used < c->total ? c->total - used : 1u;
    } while (!atomic_compare_exchange_weak(&c->in_use, &used, used + n));
    atomic_fetch_add(&c->leases, 1u);
    atomic_fetch_add(&c->lent, n);
    return n;
}

void merd_cores_give(merd_cores *c, uint32_t n)
{
    unsigned before = atomic_fetch_sub(&c->in_use, n);
    assert(before >= n);
    (void)before;
}
