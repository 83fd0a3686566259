/* meristem — Poisson-disk sampling in a rectangle after Bridson 2007
 * (meristem/sow.h): a background grid of cells of edge r/√2 holds at most one
 * point each, so a candidate is checked against the 5 × 5 cells around it. */
#include "config.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <meristem/rng.h>
#include <meristem/sow.h>

#include "core/alloc.h"
#include "core/array.h"

#define K 30 /* Bridson's candidates per active point */
#define TWO_PI 6.28318530717958647692f

typedef struct sampler {
    float lo[2], hi[2], r, inv;
    int gw, gh;
    int32_t *grid; /* point index per cell, -1 when empty */
    float *pts;    /* 2 per point */
    uint32_t *active;
    size_t n, cap;
} sampler;

static int cell_x(const sampler *s, float x) { return (int)((x - s->lo[0]) * s->inv); }
static int cell_z(const sampler *s, float z) { return (int)((z - s->lo[1]) * s->inv); }

/* 1 if p is in the rectangle and no point lies closer than r. */
static int fits(const sampler *s, const float p[2])
{
    if (!(p[0] >= s->lo[0] && p[0] <= s->hi[0] && p[1] >= s->lo[1] && p[1] <= s->hi[1]))
        return 0;
    int cx = cell_x(s, p[0]), cz = cell_z(s, p[1]);
    for (int z = cz - 2; z <= cz + 2; z++)
        for (int x = cx - 2; x <= cx + 2; x++) {
            if (x < 0 || z < 0 || x >= s->gw || z >= s->gh)
                continue;
            int32_t q = s->grid[(size_t)z * (size_t)s->gw + (size_t)x];
            if (q < 0)
                continue;
            float dx = s->pts[2 * q] - p[0], dz = s->pts[2 * q + 1] - p[1];
            if (dx * dx + dz * dz < s->r * s->r)
                return 0;
        }
    return 1;
}

static int add(sampler *s, const float p[2], size_t *nactive)
{
    if (s->n == s->cap) {
        size_t cap = s->cap * 2 + 64;
        if (!MERP_RESIZE(s->pts, 2 * cap) || !MERP_RESIZE(s->active, cap))
            return 0;
        s->cap = cap;
    }
    int cx = cell_x(s, p[0]), cz = cell_z(s, p[1]);
    cx = cx < s->gw ? cx : s->gw - 1;
    cz = cz < s->gh ? cz : s->gh - 1;
    s->grid[(size_t)cz * (size_t)s->gw + (size_t)cx] = (int32_t)s->n;
    memcpy(s->pts + 2 * s->n, p, 2 * sizeof *p);
    s->active[(*nactive)++] = (uint32_t)s->n;
    s->n++;
    return 1;
}

/* Bridson's loop: a maximal set of points at least r apart. */
static int fill(sampler *s, mer_rng *rng)
{
    size_t nactive = 0;
    float p[2] = {mer_rng_range(rng, s->lo[0], s->hi[0]), mer_rng_range(rng, s->lo[1], s->hi[1])};
    if (!add(s, p, &nactive))
        return 0;
    while (nactive > 0) {
        uint32_t a = mer_rng_below(rng, (uint32_t)nactive);
        const float *c = s->pts + 2 * s->active[a];
        int found = 0;
        for (int k = 0; k < K && !found; k++) {
            float angle = TWO_PI * mer_rng_float(rng);
            float d = s->r * (1.0f + mer_rng_float(rng));
            float q[2] = {c[0] + d * cosf(angle), c[1] + d * sinf(angle)};
            if (fits(s, q)) {
                if (!add(s, q, &nactive))
                    return 0;
                found = 1;
            }
        }
        if (!found)
            s->active[a] = s->active[--nactive];
    }
    return 1;
}

/* `count` of the n points, chosen uniformly (a partial Fisher-Yates shuffle of
 * the indices), written in the order they were made. */
static int choose(sampler *s, mer_rng *rng, uint32_t count, float *out)
{
    uint32_t *idx = s->active; /* free again once fill is done */
    uint8_t *keep = merp_calloc(s->n, 1);
    if (keep == NULL)
        return 0;
    for (size_t i = 0; i < s->n; i++)
        idx[i] = (uint32_t)i;
    for (uint32_t i = 0; i < count; i++) {
        uint32_t j = i + mer_rng_below(rng, (uint32_t)s->n - i);
        uint32_t t = idx[i];
        idx[i] = idx[j];
        idx[j] = t;
        keep[idx[i]] = 1;
    }
    size_t k = 0;
    for (size_t i = 0; i < s->n; i++)
        if (keep[i]) {
            memcpy(out + 2 * k, s->pts + 2 * i, 2 * sizeof *out);
            k++;
        }
    merp_free(keep);
    return 1;
}

static mer_result check(const float lo[2], const float hi[2], float r, double *cells,
                        mer_error *err)
{
    if (!(r > 0.0f) || !isfinite(r))
        return mer_error_set(err, MER_ERR_RANGE, "min_distance", "min_distance must be > 0, got %g",
                             (double)r);
    for (int a = 0; a < 2; a++)
        if (!isfinite(lo[a]) || !isfinite(hi[a]) || !(hi[a] > lo[a]))
            return mer_error_set(err, MER_ERR_RANGE, "area",
                                 "the area must be a rectangle [[x0, z0], [x1, z1]] with x1 > x0 and z1 > z0");
    double cell = (double)r / sqrt(2.0);
    *cells = ceil(((double)hi[0] - (double)lo[0]) / cell) * ceil(((double)hi[1] - (double)lo[1]) / cell);
    if (*cells > (double)MER_SOW_CELLS_MAX)
        return mer_error_set(err, MER_ERR_RANGE, "min_distance",
                             "the area is %.0f cells of min_distance/sqrt(2), more than %u: raise "
                             "min_distance or shrink the area", *cells, (unsigned)MER_SOW_CELLS_MAX);
    return MER_OK;
}

mer_result mer_poisson_disk(const float lo[2], const float hi[2], float r, uint32_t count,
                            uint64_t seed, float *out, uint32_t *placed, mer_error *err)
{
    assert(lo != NULL && hi != NULL && placed != NULL && (count == 0 || out != NULL));
    *placed = 0;
    double cells;
    mer_result rc = check(lo, hi, r, &cells, err);
    if (rc != MER_OK || count == 0)
        return rc;
    sampler s = {.lo = {lo[0], lo[1]}, .hi = {hi[0], hi[1]}, .r = r};
    s.inv = (float)(sqrt(2.0) / (double)r);
    s.gw = (int)ceil(((double)hi[0] - (double)lo[0]) * (double)s.inv);
    s.gh = (int)ceil(((double)hi[1] - (double)lo[1]) * (double)s.inv);
    s.gw = s.gw > 0 ? s.gw : 1;
    s.gh = s.gh > 0 ? s.gh : 1;
    s.grid = merp_malloc((size_t)s.gw * (size_t)s.gh * sizeof *s.grid);
    mer_rng rng;
    mer_rng_seed(&rng, seed);
    int ok = s.grid != NULL;
    if (ok) {
        memset(s.grid, 0xff, (size_t)s.gw * (size_t)s.gh * sizeof *s.grid);
        ok = fill(&s, &rng);
    }
    if (ok && s.n >= count) {
        ok = choose(&s, &rng, count, out);
        *placed = count;
    } else if (ok) {
        memcpy(out, s.pts, 2 * s.n * sizeof *out);
        *placed = (uint32_t)s.n;
        rc = mer_error_set(err, MER_ERR_LIMIT, "count",
                           "the area holds only %u plants at least %g apart, not %u",
                           (unsigned)s.n, (double)r, (unsigned)count);
    }
    merp_free(s.grid);
    merp_free(s.pts);
    merp_free(s.active);
    if (!ok) {
        *placed = 0;
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for Poisson-disk sampling");
    }
    return rc;
}
