/* meristem — the live markers near a set of points, in index order, from the
 * marker grid (markers.h): what a model that scans every marker each step (R07's
 * association) needs to look at, without copying the markers far from the tree. */
#include "config.h"

#include <assert.h>
#include <string.h>

#include "core/alloc.h"
#include "core/array.h"
#include "env/markers_grid.h"
#include "env/markers_near.h"

/* The index of b's lowest set bit (b ≠ 0): one instruction where the
 * compiler has a builtin for it (GCC, Clang), else a shift loop. */
static inline size_t lowest_bit(uint64_t b)
{
    assert(b != 0);
#if defined(__GNUC__)
    return (size_t)__builtin_ctzll(b); /* unsigned long long holds at least 64 bits */
#else
    size_t i = 0;
    for (; (b & 1u) == 0; b >>= 1)
        i++;
    return i;
#endif
}

/* A fresh stamp for m->stamp (cells): the cells stamped earlier read as unstamped. */
static uint32_t next_stamp(mer_markers *m)
{
    if (++m->epoch == 0) {
        memset(m->stamp, 0, m->ncells * sizeof *m->stamp);
        m->epoch = 1;
    }
    return m->epoch;
}

/* The distinct cells of the `n` points into m->near_cells; returns how many, or
 * SIZE_MAX when out of memory. */
static size_t point_cells(mer_markers *m, const float *pts, size_t n)
{
    uint32_t s = next_stamp(m);
    size_t k = 0;
    for (size_t i = 0; i < n; i++) {
        const float *p = pts + 3 * i;
        size_t c = merp_markers_cell(m, p);
        if (m->stamp[c] == s)
            continue;
        m->stamp[c] = s;
        if (k == m->near_cap) {
            size_t cap = m->near_cap ? 2 * m->near_cap : 256;
            if (!MERP_RESIZE(m->near_cells, cap))
                return SIZE_MAX;
            m->near_cap = cap;
        }
        m->near_cells[k++] = (uint32_t)c;
    }
    return k;
}

/* Sets the bit of every live marker in the cells within `reach` cells (per axis)
 * of the `k` cells listed; returns how many bits. */
static size_t mark_around(mer_markers *m, size_t k, int reach)
{
    uint32_t s = next_stamp(m);
    size_t row = (size_t)m->dim[0], plane = row * (size_t)m->dim[1], total = 0;
    for (size_t i = 0; i < k; i++) {
        size_t c = m->near_cells[i];
        int at[3] = {(int)(c % row), (int)(c / row % (size_t)m->dim[1]), (int)(c / plane)};
        int lo[3], hi[3];
        for (int a = 0; a < 3; a++) {
            lo[a] = at[a] - reach < 0 ? 0 : at[a] - reach;
            hi[a] = at[a] + reach >= m->dim[a] ? m->dim[a] - 1 : at[a] + reach;
        }
        for (int z = lo[2]; z <= hi[2]; z++)
            for (int y = lo[1]; y <= hi[1]; y++)
                for (int x = lo[0]; x <= hi[0]; x++) {
                    size_t d = (size_t)z * plane + (size_t)y * row + (size_t)x;
                    if (m->stamp[d] == s)
                        continue;
                    m->stamp[d] = s;
                    for (uint32_t t = m->start[d]; t < m->end[d]; t++) {
                        uint32_t id = m->items[t].id;
                        m->bits[id >> 6] |= UINT64_C(1) << (id & 63);
                    }
                    total += m->end[d] - m->start[d];
                }
    }
    return total;
}

mer_result merp_markers_near(mer_markers *m, const float *pts, size_t n, float radius,
                             float **xyz, size_t *cap, size_t *count, mer_error *err)
{
    assert(m != NULL && (n == 0 || pts != NULL) && radius >= 0.0f);
    assert(xyz != NULL && cap != NULL && count != NULL);
    *count = 0;
    size_t words = (m->n + 63) / 64;
    if (!merp_markers_ensure_grid(m))
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the marker grid");
    if (m->stamp == NULL && (m->stamp = merp_calloc(m->ncells, sizeof *m->stamp)) == NULL)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the marker grid");
    if (words > m->bits_cap) {
        if (!MERP_RESIZE(m->bits, words))
            return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the marker grid");
        memset(m->bits + m->bits_cap, 0, (words - m->bits_cap) * sizeof *m->bits);
        m->bits_cap = words;
    }
    size_t k = point_cells(m, pts, n);
    if (k == SIZE_MAX)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the marker grid");
    /* Two points r apart lie at most ⌊r / cell⌋ + 1 cells apart on an axis,
     * whether or not the grid clamps them to its border. */
    int widest = m->dim[0] > m->dim[1] ? m->dim[0] : m->dim[1];
    widest = widest > m->dim[2] ? widest : m->dim[2];
    float cells = radius * m->inv_cell;
    int reach = cells < (float)widest ? (int)cells + 1 : widest;
    size_t total = mark_around(m, k, reach);
    if (total > *cap && !merp_array_resize(xyz, 3 * total, sizeof **xyz)) {
        memset(m->bits, 0, words * sizeof *m->bits);
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for markers");
    }
    if (total > *cap)
        *cap = total;
    /* Index order; the bits are cleared on the way, ready for the next call. */
    size_t j = 0;
    for (size_t w = 0; w < words && j < total; w++)
        for (uint64_t b = m->bits[w]; b != 0; b &= b - 1) {
            size_t id = 64 * w + lowest_bit(b);
            memcpy(*xyz + 3 * j++, m->p + 3 * id, 3 * sizeof **xyz);
            m->bits[w] = 0;
        }
    *count = j;
    return MER_OK;
}
