/* meristem — bud shadows cast in batches (P09 §4.1). A step's new shoots add and
 * lift thousands of shadow pyramids, each a few hundred voxels in ~50 rows of a
 * grid far larger than the cache. Held back and sorted by voxel, the pyramids
 * of one step are cast layer by layer: each layer of the grid takes the squares
 * of every pyramid that reaches it while it is in the cache. Buds on the same
 * voxel (a shoot's tip and its last lateral, a bud gone where another appeared)
 * are cast once, with their net count. The sums wrap modulo 2³², so any order and any grouping gives the
 * very same grid. */
#include "config.h"

#include <assert.h>
#include <stdint.h>
#include <string.h>

#include "core/array.h"
#include "env/env.h"

/* The widest digit of the radix sort: its 2¹² 32-bit counts (16 KB) leave room
 * in a 32 KB L1 data cache for the keys streaming through, and a grid of up to
 * 2²⁴ voxels (256³) is sorted in two passes. */
#define RADIX_BITS_MAX 12
/* The casts held back at most: the sort's counts are 32-bit. */
#define PENDING_MAX UINT32_MAX

void merp_env_batch_begin(merp_env *e)
{
    assert(e != NULL && !e->batching);
    e->batching = e->shadow != NULL;
    e->npend = 0;
}

/* Holds a cast back; without memory or count to hold it, casts it now (same sum). */
void merp_env_batch_cast(merp_env *e, const float p[3], int sign)
{
    if (e->npend == PENDING_MAX) {
        mer_shadow_cast_at(e->shadow, p, sign);
        return;
    }
    if (e->npend == e->pend_cap) {
        size_t cap = e->pend_cap ? 2 * e->pend_cap : 4096;
        if (!MERP_RESIZE(e->pend, cap) || !MERP_RESIZE(e->pend_tmp, cap)) {
            mer_shadow_cast_at(e->shadow, p, sign);
            return;
        }
        e->pend_cap = cap;
    }
    /* key: the voxel, then one bit for the sign */
    e->pend[e->npend++] = (uint64_t)merp_shadow_cell(e->shadow, p) << 1 | (sign < 0);
}

/* LSD radix sort of the keys by voxel (the sign bit is left unsorted), in as
 * few passes of digits as wide as the grid's voxel count needs. */
static uint64_t *sort_keys(uint64_t *a, uint64_t *tmp, size_t n, size_t cells)
{
    assert(n <= PENDING_MAX);
    unsigned bits = 0;
    while (bits < 64 && ((uint64_t)(cells - 1) >> bits) != 0)
        bits++;
    unsigned passes = (bits + RADIX_BITS_MAX - 1) / RADIX_BITS_MAX;
    unsigned width = passes ? (bits + passes - 1) / passes : 0;
    const uint64_t mask = ((uint64_t)1 << width) - 1;
    uint32_t count[(1u << RADIX_BITS_MAX) + 1];
    for (unsigned p = 0, shift = 1; p < passes; p++, shift += width) {
        memset(count, 0, ((mask + 2) * sizeof *count));
        for (size_t t = 0; t < n; t++)
            count[(a[t] >> shift & mask) + 1]++;
        for (uint64_t d = 0; d < mask; d++)
            count[d + 1] += count[d];
        for (size_t t = 0; t < n; t++)
            tmp[count[a[t] >> shift & mask]++] = a[t];
        uint64_t *x = a;
        a = tmp;
        tmp = x;
    }
    return a;
}

void merp_env_batch_end(merp_env *e)
{
    assert(e != NULL);
    if (!e->batching)
        return;
    e->batching = 0;
    size_t n = e->npend;
    e->npend = 0;
    if (n == 0)
        return;
    uint64_t *k = sort_keys(e->pend, e->pend_tmp, n, merp_shadow_cells(e->shadow));
    /* The casts merged by voxel, by voxel: by layer j first (x fastest, then z). */
    int merged = e->casts_cap >= n || MERP_RESIZE(e->casts, n);
    if (merged && e->casts_cap < n)
        e->casts_cap = n;
    size_t m = 0;
    for (size_t t = 0; t < n;) {
        uint64_t cell = k[t] >> 1;
        int32_t count = 0;
        for (; t < n && k[t] >> 1 == cell; t++)
            count += (k[t] & 1) ? -1 : 1;
        if (count == 0)
            continue;
        if (merged)
            e->casts[m++] = merp_shadow_cast_of(e->shadow, (uint32_t)cell, count);
        else /* without memory for the list: one pyramid at a time, the same sum */
            merp_shadow_cast_cell(e->shadow, (uint32_t)cell, count);
    }
    merp_shadow_cast_layers(e->shadow, e->casts, m);
}
