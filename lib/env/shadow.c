/* meristem — shadow propagation grid (P09 §4.1). */
#include "config.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <meristem/params.h>
#include <meristem/shadow.h>

#include "core/alloc.h"
#include "core/array.h"
#include "core/bytes.h"
#include "core/hash.h"
#include "env/env.h"

#define FIX 4096.0f   /* fixed-point units per a */
#define QMAX_LIMIT 32

struct mer_shadow {
    float bmin[3];
    float voxel, inv_voxel;
    int dim[3];
    size_t nvox;
    float a, b;
    uint32_t q_max;
    uint32_t delta[QMAX_LIMIT + 1]; /* round(4096·b^(−q)): Δs in units of a/4096 */
    uint32_t *s;
    /* scratch of merp_shadow_cast_layers, made on first use: a layer's 2-D
     * difference, (dim[2] + 1) rows of dim[0] + 1, then one row of column sums */
    uint32_t *diff;
};

mer_result mer_shadow_new(const float bmin[3], const float bmax[3], float voxel, float a,
                          float b, uint32_t q_max, mer_shadow **out, mer_error *err)
{
    *out = NULL;
    if (!(voxel > 0.0f))
        return mer_error_set(err, MER_ERR_RANGE, "voxel", "voxel must be > 0");
    if (!(a > 0.0f))
        return mer_error_set(err, MER_ERR_RANGE, "shadow_a", "shadow_a must be > 0");
    if (!(b > 1.0f))
        return mer_error_set(err, MER_ERR_RANGE, "shadow_b", "shadow_b must be > 1");
    if (q_max > QMAX_LIMIT)
        return mer_error_set(err, MER_ERR_RANGE, "q_max", "q_max must be from 0 to %d", QMAX_LIMIT);
    double cells = 1.0;
    int dim[3];
    for (int i = 0; i < 3; i++) {
        double ext = (double)bmax[i] - (double)bmin[i];
        if (!(ext > 0.0))
            return mer_error_set(err, MER_ERR_RANGE, "bounds_max",
                                 "bounds_max must exceed bounds_min on every axis");
        double d = ceil(ext / (double)voxel);
        cells *= d;
        if (cells > (double)MER_GRID_CELLS_MAX)
            return mer_error_set(err, MER_ERR_LIMIT, "voxel",
                                 "the shadow grid would exceed %u voxels; raise voxel",
                                 (unsigned)MER_GRID_CELLS_MAX);
        dim[i] = (int)d;
    }
    mer_shadow *sh = merp_calloc(1, sizeof *sh);
    if (sh == NULL)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the shadow grid");
    memcpy(sh->bmin, bmin, sizeof sh->bmin);
    memcpy(sh->dim, dim, sizeof sh->dim);
    sh->voxel = voxel;
    sh->inv_voxel = 1.0f / voxel;
    sh->nvox = (size_t)dim[0] * (size_t)dim[1] * (size_t)dim[2];
    sh->a = a;
    sh->b = b;
    sh->q_max = q_max;
    for (uint32_t q = 0; q <= q_max; q++)
        sh->delta[q] = (uint32_t)lround((double)FIX * pow((double)b, -(double)q)); /* a·b^(−q) */
    sh->s = merp_calloc(sh->nvox, sizeof *sh->s);
    if (sh->s == NULL) {
        merp_free(sh);
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the shadow grid");
    }
    *out = sh;
    return MER_OK;
}

void mer_shadow_free(mer_shadow *sh)
{
    if (sh == NULL)
        return;
    merp_free(sh->s);
    merp_free(sh->diff);
    merp_free(sh);
}

void mer_shadow_clear(mer_shadow *sh) { memset(sh->s, 0, sh->nvox * sizeof *sh->s); }

void mer_shadow_dims(const mer_shadow *sh, int dim[3]) { memcpy(dim, sh->dim, sizeof sh->dim); }

int mer_shadow_voxel_of(const mer_shadow *sh, const float p[3], int ijk[3])
{
    int inside = 1;
    for (int a = 0; a < 3; a++) {
        float f = (p[a] - sh->bmin[a]) * sh->inv_voxel;
        if (!(f >= 0.0f)) {
            ijk[a] = 0;
            inside = 0;
        } else if (f >= (float)sh->dim[a]) {
            ijk[a] = sh->dim[a] - 1;
            inside = 0;
        } else {
            ijk[a] = (int)f;
        }
    }
    return inside;
}

static size_t idx(const mer_shadow *sh, int i, int j, int k)
{
    /* x fastest, so each pyramid row is contiguous. */
    return ((size_t)j * (size_t)sh->dim[2] + (size_t)k) * (size_t)sh->dim[0] + (size_t)i;
}

/* Voxels [i0, i1] × [k0, k1] of one layer. */
typedef struct rect {
    int i0, i1, k0, k1;
} rect;

/* The square of half-width q about (I, K), clipped to a layer of dx × dz. */
static rect square(int dx, int dz, int I, int K, int q)
{
    rect r = {I - q, I + q, K - q, K + q};
    if (r.i0 < 0) r.i0 = 0;
    if (r.k0 < 0) r.k0 = 0;
    if (r.i1 >= dx) r.i1 = dx - 1;
    if (r.k1 >= dz) r.k1 = dz - 1;
    return r;
}

/* Adds d to rectangle r of one layer (x fastest). */
static void add_rect(uint32_t *layer, int dx, rect r, uint32_t d)
{
    uint32_t *row = layer + (size_t)r.k0 * (size_t)dx;
    for (int k = r.k0; k <= r.k1; k++, row += dx)
        for (int i = r.i0; i <= r.i1; i++)
            row[i] += d;
}

/* Adds d to the square of half-width q about (I, K) in one layer. */
static void add_square(uint32_t *layer, int dx, int dz, int I, int K, int q, uint32_t d)
{
    add_rect(layer, dx, square(dx, dz, I, K, q), d);
}

void mer_shadow_cast(mer_shadow *sh, const int ijk[3], int sign, float weight)
{
    const int I = ijk[0], J = ijk[1], K = ijk[2];
    for (uint32_t q = 0; q <= sh->q_max; q++) {
        int j = J - (int)q;
        if (j < 0)
            break;
        uint32_t d = weight == 1.0f ? sh->delta[q] : (uint32_t)lroundf((float)sh->delta[q] * weight);
        if (sign < 0)
            d = (uint32_t)0 - d; /* unsigned wrap: exact inverse of the addition */
        add_square(sh->s + idx(sh, 0, j, 0), sh->dim[0], sh->dim[2], I, K, (int)q, d);
    }
}

uint32_t merp_shadow_cell(const mer_shadow *sh, const float p[3])
{
    int ijk[3];
    mer_shadow_voxel_of(sh, p, ijk);
    return (uint32_t)idx(sh, ijk[0], ijk[1], ijk[2]);
}

size_t merp_shadow_cells(const mer_shadow *sh) { return sh->nvox; }

void merp_shadow_cast_cell(mer_shadow *sh, uint32_t cell, int32_t count)
{
    merp_shadow_cast c = merp_shadow_cast_of(sh, cell, count);
    merp_shadow_cast_layers(sh, &c, 1);
}

merp_shadow_cast merp_shadow_cast_of(const mer_shadow *sh, uint32_t cell, int32_t count)
{
    assert(cell < sh->nvox);
    const uint32_t dx = (uint32_t)sh->dim[0], dz = (uint32_t)sh->dim[2];
    merp_shadow_cast c = {(int32_t)(cell % dx), (int32_t)(cell / (dx * dz)),
                          (int32_t)(cell / dx % dz), count};
    return c;
}

/* The squares of c[a, b) in layer L (cast from layer c[t].j, so of half-width
 * c[t].j − L): their bounding box, and how many voxels they cover in all. */
static size_t layer_squares(const mer_shadow *sh, const merp_shadow_cast *c, size_t a,
                            size_t b, int L, rect *box)
{
    rect bb = {sh->dim[0], -1, sh->dim[2], -1};
    size_t area = 0;
    for (size_t t = a; t < b; t++) {
        rect r = square(sh->dim[0], sh->dim[2], c[t].i, c[t].k, c[t].j - L);
        area += (size_t)(r.i1 - r.i0 + 1) * (size_t)(r.k1 - r.k0 + 1);
        bb.i0 = r.i0 < bb.i0 ? r.i0 : bb.i0;
        bb.i1 = r.i1 > bb.i1 ? r.i1 : bb.i1;
        bb.k0 = r.k0 < bb.k0 ? r.k0 : bb.k0;
        bb.k1 = r.k1 > bb.k1 ? r.k1 : bb.k1;
    }
    *box = bb;
    return area;
}

/* Adds the squares of c[a, b) to layer L through a 2-D difference: four
 * corners a square, then one running sum over their bounding box `bb`, which
 * leaves the scratch zero again. Many squares overlap in a crown: this costs
 * the box's voxels rather than the squares' (the same sums modulo 2³²). */
static void add_by_difference(mer_shadow *sh, uint32_t *layer, const merp_shadow_cast *c,
                              size_t a, size_t b, int L, rect bb)
{
    const int dx = sh->dim[0], dz = sh->dim[2];
    const size_t w = (size_t)dx + 1;
    uint32_t *D = sh->diff, *col = sh->diff + ((size_t)dz + 1) * w;
    for (size_t t = a; t < b; t++) {
        rect r = square(dx, dz, c[t].i, c[t].k, c[t].j - L);
        uint32_t d = sh->delta[c[t].j - L] * (uint32_t)c[t].count;
        uint32_t *top = D + (size_t)r.k0 * w, *end = D + (size_t)(r.k1 + 1) * w;
        top[r.i0] += d;
        top[r.i1 + 1] -= d;
        end[r.i0] -= d;
        end[r.i1 + 1] += d;
    }
    memset(col + bb.i0, 0, (size_t)(bb.i1 - bb.i0 + 1) * sizeof *col);
    for (int k = bb.k0; k <= bb.k1; k++) {
        uint32_t *Dk = D + (size_t)k * w, *row = layer + (size_t)k * (size_t)dx, acc = 0;
        for (int i = bb.i0; i <= bb.i1; i++) {
            col[i] += Dk[i];
            Dk[i] = 0;
            acc += col[i];
            row[i] += acc;
        }
        Dk[bb.i1 + 1] = 0;
    }
    memset(D + (size_t)(bb.k1 + 1) * w + bb.i0, 0, (size_t)(bb.i1 - bb.i0 + 2) * sizeof *D);
}

void merp_shadow_cast_layers(mer_shadow *sh, const merp_shadow_cast *c, size_t n)
{
    if (n == 0)
        return;
    const int dx = sh->dim[0], dz = sh->dim[2], qmax = (int)sh->q_max;
    const size_t layer_size = (size_t)dx * (size_t)dz;
    int top = c[n - 1].j, bottom = c[0].j - qmax;
    if (bottom < 0)
        bottom = 0;
    /* A pyramid at layer J covers layers J − q_max .. J: layer L takes the casts
     * with L <= J <= L + q_max, c[a, b). */
    size_t a = 0, b = 0;
    for (int L = bottom; L <= top; L++) {
        while (a < n && c[a].j < L)
            a++;
        while (b < n && c[b].j <= L + qmax)
            b++;
        uint32_t *layer = sh->s + (size_t)L * layer_size;
        rect bb;
        size_t area = layer_squares(sh, c, a, b, L, &bb);
        /* the running sum costs about two adds a voxel of the box */
        if (area > 2 * (size_t)(bb.i1 - bb.i0 + 1) * (size_t)(bb.k1 - bb.k0 + 1) &&
            (sh->diff != NULL || (sh->diff = merp_calloc(((size_t)dz + 2) * ((size_t)dx + 1),
                                                         sizeof *sh->diff)) != NULL)) {
            add_by_difference(sh, layer, c, a, b, L, bb);
            continue;
        }
        for (size_t t = a; t < b; t++) {
            assert(t == a || c[t].j >= c[t - 1].j);
            /* count casts at once: the same sum as count single ones, wrapping alike */
            uint32_t d = sh->delta[c[t].j - L] * (uint32_t)c[t].count;
            add_square(layer, dx, dz, c[t].i, c[t].k, c[t].j - L, d);
        }
    }
}

void mer_shadow_cast_at(mer_shadow *sh, const float p[3], int sign)
{
    int ijk[3];
    mer_shadow_voxel_of(sh, p, ijk);
    mer_shadow_cast(sh, ijk, sign, 1.0f);
}

void mer_shadow_add_voxel(mer_shadow *sh, const int ijk[3], float amount)
{
    for (int a = 0; a < 3; a++)
        if (ijk[a] < 0 || ijk[a] >= sh->dim[a])
            return;
    long v = lroundf(amount / sh->a * FIX);
    sh->s[idx(sh, ijk[0], ijk[1], ijk[2])] += (uint32_t)v; /* wraps for negative v */
}

static float value_raw(const mer_shadow *sh, int i, int j, int k)
{
    if (i < 0 || j < 0 || k < 0 || i >= sh->dim[0] || j >= sh->dim[1] || k >= sh->dim[2])
        return 0.0f;
    return (float)(int32_t)sh->s[idx(sh, i, j, k)] * (sh->a / FIX);
}

float mer_shadow_value(const mer_shadow *sh, const int ijk[3])
{
    return value_raw(sh, ijk[0], ijk[1], ijk[2]);
}

merp_light merp_shadow_light_view(const mer_shadow *sh, float c)
{
    merp_light l = {sh->s, sh->nvox, sh->a / FIX, c, sh->a};
    return l;
}

float merp_shadow_light_cell(const mer_shadow *sh, uint32_t cell, float c)
{
    merp_light l = merp_shadow_light_view(sh, c);
    return merp_light_at(&l, cell);
}

/* How many voxels ahead merp_shadow_light_cells asks the memory for: enough reads
 * in flight to hide a miss, few enough to stay in the cache until used. */
#define READ_AHEAD 16

void merp_shadow_light_cells(const mer_shadow *sh, const uint32_t *cells, size_t n, float c,
                             float *q)
{
    merp_light l = merp_shadow_light_view(sh, c);
    for (size_t t = 0; t < n; t++) {
        if (t + READ_AHEAD < n)
            merp_light_prefetch(&l, cells[t + READ_AHEAD]);
        q[t] = merp_light_at(&l, cells[t]);
    }
}

float mer_shadow_light(const mer_shadow *sh, const float p[3], float c)
{
    return merp_shadow_light_cell(sh, merp_shadow_cell(sh, p), c);
}

/* The 26 neighbour offsets in (dk, dj, di) order and their unit directions
 * (components 0, ±1, ±1/√2, ±1/√3), a constant table: no initialisation race
 * between sessions stepping in parallel. */
typedef struct nb {
    int di, dj, dk;
    float u[3];
} nb;

static const nb neighbours[26] = {
    {-1, -1, -1, {-0.577350269f, -0.577350269f, -0.577350269f}},
    {0, -1, -1, {0.0f, -0.707106781f, -0.707106781f}},
    {1, -1, -1, {0.577350269f, -0.577350269f, -0.577350269f}},
    {-1, 0, -1, {-0.707106781f, 0.0f, -0.707106781f}},
    {0, 0, -1, {0.0f, 0.0f, -1.000000000f}},
    {1, 0, -1, {0.707106781f, 0.0f, -0.707106781f}},
    {-1, 1, -1, {-0.577350269f, 0.577350269f, -0.577350269f}},
    {0, 1, -1, {0.0f, 0.707106781f, -0.707106781f}},
    {1, 1, -1, {0.577350269f, 0.577350269f, -0.577350269f}},
    {-1, -1, 0, {-0.707106781f, -0.707106781f, 0.0f}},
    {0, -1, 0, {0.0f, -1.000000000f, 0.0f}},
    {1, -1, 0, {0.707106781f, -0.707106781f, 0.0f}},
    {-1, 0, 0, {-1.000000000f, 0.0f, 0.0f}},
    {1, 0, 0, {1.000000000f, 0.0f, 0.0f}},
    {-1, 1, 0, {-0.707106781f, 0.707106781f, 0.0f}},
    {0, 1, 0, {0.0f, 1.000000000f, 0.0f}},
    {1, 1, 0, {0.707106781f, 0.707106781f, 0.0f}},
    {-1, -1, 1, {-0.577350269f, -0.577350269f, 0.577350269f}},
    {0, -1, 1, {0.0f, -0.707106781f, 0.707106781f}},
    {1, -1, 1, {0.577350269f, -0.577350269f, 0.577350269f}},
    {-1, 0, 1, {-0.707106781f, 0.0f, 0.707106781f}},
    {0, 0, 1, {0.0f, 0.0f, 1.000000000f}},
    {1, 0, 1, {0.707106781f, 0.0f, 0.707106781f}},
    {-1, 1, 1, {-0.577350269f, 0.577350269f, 0.577350269f}},
    {0, 1, 1, {0.0f, 0.707106781f, 0.707106781f}},
    {1, 1, 1, {0.577350269f, 0.577350269f, 0.577350269f}},
};

float merp_shadow_cone(float theta)
{
    return theta >= 360.0f ? -1.0f : cosf(theta * 0.5f * 0.017453292519943295f);
}

/* V of a bud in voxel c (mer_shadow_direction), the cone's cos(θ/2) given. */
static void direction_at(const mer_shadow *sh, const int c[3], const float dir[3],
                         float cos_half, uint32_t mode, float out[3])
{
    out[0] = out[1] = out[2] = 0.0f;
    if (mode == MER_SHADOW_DIR_GRADIENT) {
        float g[3] = {
            0.5f * (value_raw(sh, c[0] + 1, c[1], c[2]) - value_raw(sh, c[0] - 1, c[1], c[2])),
            0.5f * (value_raw(sh, c[0], c[1] + 1, c[2]) - value_raw(sh, c[0], c[1] - 1, c[2])),
            0.5f * (value_raw(sh, c[0], c[1], c[2] + 1) - value_raw(sh, c[0], c[1], c[2] - 1)),
        };
        float len = sqrtf(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
        if (len > 0.0f)
            for (int a = 0; a < 3; a++)
                out[a] = -g[a] / len;
        return;
    }
    int interior = c[0] > 0 && c[1] > 0 && c[2] > 0 && c[0] < sh->dim[0] - 1 &&
                   c[1] < sh->dim[1] - 1 && c[2] < sh->dim[2] - 1;
    const uint32_t *centre = sh->s + idx(sh, c[0], c[1], c[2]);
    const ptrdiff_t sx = 1, sz = sh->dim[0], sy = (ptrdiff_t)sh->dim[0] * sh->dim[2];
    int32_t best = 0;
    float best_dot = 0.0f;
    int found = -1;
    for (int n = 0; n < 26; n++) {
        const nb *x = &neighbours[n];
        float dot = x->u[0] * dir[0] + x->u[1] * dir[1] + x->u[2] * dir[2];
        if (dot < cos_half)
            continue;
        int32_t sv;
        if (interior) {
            sv = (int32_t)centre[x->di * sx + x->dj * sy + x->dk * sz];
        } else {
            int i = c[0] + x->di, j = c[1] + x->dj, k = c[2] + x->dk;
            int in = i >= 0 && j >= 0 && k >= 0 && i < sh->dim[0] && j < sh->dim[1] && k < sh->dim[2];
            sv = in ? (int32_t)sh->s[idx(sh, i, j, k)] : 0;
        }
        if (found < 0 || sv < best || (sv == best && dot > best_dot)) {
            found = n;
            best = sv;
            best_dot = dot;
        }
    }
    if (found >= 0)
        memcpy(out, neighbours[found].u, 3 * sizeof *out);
}

void mer_shadow_direction(const mer_shadow *sh, const float p[3], const float dir[3],
                          float theta, uint32_t mode, float out[3])
{
    int c[3];
    mer_shadow_voxel_of(sh, p, c);
    direction_at(sh, c, dir, merp_shadow_cone(theta), mode, out);
}

void merp_shadow_direction_cell(const mer_shadow *sh, uint32_t cell, const float dir[3],
                                float cos_half, uint32_t mode, float out[3])
{
    merp_shadow_cast v = merp_shadow_cast_of(sh, cell, 0);
    int c[3] = {v.i, v.j, v.k};
    direction_at(sh, c, dir, cos_half, mode, out);
}

void merp_shadow_prefetch_around(const mer_shadow *sh, uint32_t cell)
{
#if defined(__GNUC__)
    const ptrdiff_t sz = sh->dim[0], sy = (ptrdiff_t)sh->dim[0] * sh->dim[2];
    for (int dj = -1; dj <= 1; dj++)
        for (int dk = -1; dk <= 1; dk++) {
            ptrdiff_t o = (ptrdiff_t)cell + dj * sy + dk * sz;
            if (o >= 0 && (size_t)o < sh->nvox)
                __builtin_prefetch(sh->s + o);
        }
#else
    (void)sh;
    (void)cell;
#endif
}

uint64_t mer_shadow_hash(const mer_shadow *sh)
{
    uint64_t h = MERP_FNV_OFFSET;
    for (size_t i = 0; i < sh->nvox; i++)
        h = merp_fnv_u32le(h, sh->s[i]);
    return h;
}

mer_result merp_shadow_clone(const mer_shadow *sh, mer_shadow **out, mer_error *err)
{
    assert(sh != NULL && out != NULL);
    mer_shadow *c = merp_malloc(sizeof *c);
    *out = NULL;
    if (c == NULL)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the shadow grid");
    *c = *sh;
    c->diff = NULL;
    if (!MERP_DUP(c->s, sh->s, sh->nvox)) {
        merp_free(c);
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the shadow grid");
    }
    *out = c;
    return MER_OK;
}

void merp_shadow_save(const mer_shadow *sh, merp_bytes_out *out)
{
    merp_put_u64(out, sh->nvox);
    merp_put(out, sh->s, sh->nvox * sizeof *sh->s);
}

mer_result merp_shadow_load(mer_shadow *sh, merp_bytes_in *in, mer_error *err)
{
    if (merp_get_u64(in) != sh->nvox)
        in->bad = 1;
    if (!in->bad && sh->nvox > (in->n - in->at) / sizeof *sh->s)
        in->bad = 1;
    if (in->bad)
        return mer_error_set(err, MER_ERR_FORMAT, "shadow", "a damaged shadow grid");
    /* Any value is a shade: the grid holds sums that wrap (mer_shadow_cast_at). */
    merp_get(in, sh->s, sh->nvox * sizeof *sh->s);
    return MER_OK;
}
