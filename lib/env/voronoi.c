/* meristem — Voronoi cells of plant sites on the ground plane (meristem/sow.h):
 * a point belongs to the cell of its nearest site, so the cells partition the
 * plane and a plant's markers clipped to its cell are nobody else's. */
#include "config.h"

#include <assert.h>
#include <string.h>

#include <meristem/sow.h>

uint32_t mer_voronoi_cell(const float *sites, uint32_t n, const float p[2])
{
    assert(sites != NULL && n >= 1 && p != NULL);
    uint32_t best = 0;
    float bd = 0.0f;
    for (uint32_t i = 0; i < n; i++) {
        float dx = sites[2 * i] - p[0], dz = sites[2 * i + 1] - p[1];
        float d = dx * dx + dz * dz;
        if (i == 0 || d < bd) {
            best = i;
            bd = d;
        }
    }
    return best;
}

size_t mer_voronoi_clip(const float *sites, uint32_t n, uint32_t cell, float *xyz, size_t count)
{
    assert(sites != NULL && n >= 1 && cell < n && (count == 0 || xyz != NULL));
    size_t k = 0;
    for (size_t i = 0; i < count; i++) {
        const float p[2] = {xyz[3 * i], xyz[3 * i + 2]};
        if (mer_voronoi_cell(sites, n, p) != cell)
            continue;
        if (k != i)
            memmove(xyz + 3 * k, xyz + 3 * i, 3 * sizeof *xyz);
        k++;
    }
    return k;
}
