/* meristem — whether a junction's patch can close the bark (joints.c): the
 * check that keeps a fork as tubes when its patch is not a clean surface. */
#include "config.h"

#include <stdbool.h>
#include <string.h>

#include "core/alloc.h"
#include "mesh_private.h"

/* Open addressing with linear probing over a power-of-two table at most half
 * full: the check is O(vertices + triangles), where sorting the directed
 * edges cost most of a patch. */
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

/* Slot of directed edge a→b (key + 1, so 0 is empty): the key's or an empty one. */
static size_t edge_slot(const uint64_t *t, size_t mask, uint64_t key)
{
    size_t i = mix(key, mask);
    while (t[i] != 0 && t[i] != key + 1)
        i = (i + 1) & mask;
    return i;
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
    size_t e = 3 * (size_t)m->triangle_count, vsize = table_size(m->vertex_count), size = table_size(e);
    uint32_t *v = merp_malloc(vsize * sizeof *v);
    uint64_t *t = merp_calloc(size, sizeof *t);
    bool ok = v != NULL && t != NULL && !positions_repeat(m, v, vsize - 1);
    for (size_t f = 0; f < m->triangle_count && ok; f++) {
        const uint32_t *c = m->triangles + 3 * f;
        for (int k = 0; k < 3 && ok; k++) {
            uint32_t a = c[k], b = c[(k + 1) % 3];
            size_t i = edge_slot(t, size - 1, (uint64_t)a << 32 | b);
            ok = a != b && t[i] == 0; /* no directed edge twice */
            t[i] = ((uint64_t)a << 32 | b) + 1;
        }
    }
    /* Every edge has its reverse, except along the rings. */
    for (size_t f = 0; f < m->triangle_count && ok; f++) {
        const uint32_t *c = m->triangles + 3 * f;
        for (int k = 0; k < 3 && ok; k++) {
            uint32_t a = c[k], b = c[(k + 1) % 3];
            ok = (a >= ring_first && b >= ring_first) ||
                 t[edge_slot(t, size - 1, (uint64_t)b << 32 | a)] != 0;
        }
    }
    merp_free(v);
    merp_free(t);
    return ok;
}
