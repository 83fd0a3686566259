/* meristem — whether a junction's patch can close the bark (joints.c): the
 * check that keeps a fork as tubes when its patch is not a clean surface. */
#include "config.h"

#include <stdbool.h>
#include <string.h>

#include "core/alloc.h"
#include "mesh_private.h"

/* Positions are hashed by open addressing with linear probing over a
 * power-of-two table at most half full. */
static size_t table_size(size_t n)
{
    size_t s = 16;
    while (s < 2 * n)
        s *= 2;
    return s;
}

static size_t mix(uint64_t k, size_t mask)
{
    k ^= k >> 31;
    k *= UINT64_C(0x9e3779b97f4a7c15);
    return (size_t)(k >> 29) & mask;
}

/* Whether two vertices share a position (bit for bit, as the GLB would). */
static bool positions_repeat(const merp_trimesh *m, uint32_t *t, size_t mask)
{
    for (size_t i = 0; i <= mask; i++)
        t[i] = UINT32_MAX;
    for (uint32_t v = 0; v < m->vertex_count; v++) {
        const float *p = m->positions + 3 * (size_t)v;
        uint32_t w[3];
        memcpy(w, p, sizeof w);
        size_t i = mix(((uint64_t)w[0] << 32 | w[1]) ^ (uint64_t)w[2] * 0x85ebca6bu, mask);
        for (; t[i] != UINT32_MAX; i = (i + 1) & mask)
            if (memcmp(m->positions + 3 * (size_t)t[i], p, sizeof w) == 0)
                return true;
        t[i] = v;
    }
    return false;
}

bool merp_patch_closes(const merp_trimesh *m, uint32_t ring_first)
{
    /* Each triangle's corners by vertex (a counting sort): corner a of
     * triangle (p, a, n) gives a its edge out a→n and its edge in p→a.
     * With two stamps a vertex, a's edges out mark their ends (a second
     * mark is a directed edge twice) and its edges in their starts (an
     * edge out whose end is unmarked has no reverse): O(vertices +
     * triangles) in memory of the mesh's size, with no search, where a
     * hash table of every directed edge cost most of the check. */
    size_t e = 3 * (size_t)m->triangle_count, nv = m->vertex_count, vsize = table_size(nv);
    uint32_t *v = merp_malloc(vsize * sizeof *v), *first = merp_calloc(nv + 1, sizeof *first);
    uint32_t *next = merp_malloc((e + 1) * sizeof *next), *prev = merp_malloc((e + 1) * sizeof *prev);
    uint32_t *mark = merp_malloc((2 * nv + 1) * sizeof *mark);
    bool ok = v != NULL && first != NULL && next != NULL && prev != NULL && mark != NULL &&
              !positions_repeat(m, v, vsize - 1);
    if (ok) {
        const uint32_t *t = m->triangles;
        for (size_t k = 0; k < e; k++)
            first[t[k]]++;
        for (uint32_t a = 0, sum = 0; a <= nv; a++) { /* first[a]: the end of a's corners */
            sum += first[a];
            first[a] = sum;
        }
        for (size_t f = 0; f < e; f += 3)
            for (int k = 0; k < 3; k++) {
                uint32_t i = --first[t[f + k]];
                next[i] = t[f + (k == 2 ? 0 : k + 1)], prev[i] = t[f + (k == 0 ? 2 : k - 1)];
            }
        uint32_t *out_mark = mark, *in_mark = mark + nv;
        for (size_t i = 0; i < 2 * nv; i++)
            mark[i] = UINT32_MAX;
        for (uint32_t a = 0; a < nv && ok; a++) {
            for (uint32_t i = first[a]; i < first[a + 1]; i++)
                in_mark[prev[i]] = a;
            for (uint32_t i = first[a]; i < first[a + 1] && ok; i++) {
                uint32_t b = next[i];
                /* no degenerate edge, no directed edge twice, and a reverse but along the rings */
                ok = b != a && out_mark[b] != a && ((a >= ring_first && b >= ring_first) || in_mark[b] == a);
                out_mark[b] = a;
            }
        }
    }
    merp_free(v);
    merp_free(first);
    merp_free(next);
    merp_free(prev);
    merp_free(mark);
    return ok;
}
