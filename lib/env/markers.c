/* meristem — marker set on a uniform grid (P09 §4.1, §6). */
#include "config.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <meristem/markers.h>
#include <meristem/params.h>

#include "core/alloc.h"
#include "core/array.h"
#include "core/bytes.h"
#include "core/vec.h"
#include "env/env.h"
#include "env/markers_grid.h"

#define NONE UINT32_MAX

/* Marker indices fit in 31 bits. */
#define MARKERS_MAX UINT32_C(0x7fffffff)

mer_result mer_markers_new(const float bmin[3], const float bmax[3], float cell,
                           mer_markers **out, mer_error *err)
{
    *out = NULL;
    if (!(cell > 0.0f))
        return mer_error_set(err, MER_ERR_RANGE, "marker_cell", "marker_cell must be > 0");
    double cells = 1.0;
    int dim[3];
    for (int a = 0; a < 3; a++) {
        double ext = (double)bmax[a] - (double)bmin[a];
        if (!(ext > 0.0))
            return mer_error_set(err, MER_ERR_RANGE, "bounds_max",
                                 "bounds_max must exceed bounds_min on every axis");
        double d = ceil(ext / (double)cell);
        if (d < 1.0)
            d = 1.0;
        cells *= d;
        if (cells > (double)MER_GRID_CELLS_MAX)
            return mer_error_set(err, MER_ERR_LIMIT, "marker_cell",
                                 "the marker grid would exceed %u cells; raise marker_cell",
                                 (unsigned)MER_GRID_CELLS_MAX);
        dim[a] = (int)d;
    }
    mer_markers *m = merp_calloc(1, sizeof *m);
    if (m == NULL)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the marker set");
    memcpy(m->bmin, bmin, sizeof m->bmin);
    memcpy(m->dim, dim, sizeof m->dim);
    m->cell = cell;
    m->inv_cell = 1.0f / cell;
    m->ncells = (size_t)dim[0] * (size_t)dim[1] * (size_t)dim[2];
    m->start = merp_calloc(m->ncells + 1, sizeof *m->start);
    m->end = merp_calloc(m->ncells, sizeof *m->end);
    if (m->start == NULL || m->end == NULL) {
        merp_free(m->start);
        merp_free(m->end);
        merp_free(m);
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the marker grid");
    }
    m->dirty = 0;
    *out = m;
    return MER_OK;
}

void mer_markers_free(mer_markers *m)
{
    if (m == NULL)
        return;
    merp_free(m->p);
    merp_free(m->dead);
    merp_free(m->start);
    merp_free(m->end);
    merp_free(m->items);
    merp_free(m->best);
    merp_free(m->touched);
    merp_free(m->stamp);
    merp_free(m->bits);
    merp_free(m->near_cells);
    merp_free(m);
}

mer_result mer_markers_add(mer_markers *m, const float *xyz, size_t count, mer_error *err)
{
    if (count == 0)
        return MER_OK;
    if (m->n + count > (size_t)MARKERS_MAX)
        return mer_error_set(err, MER_ERR_LIMIT, "markers", "too many markers");
    if (m->n + count > m->cap) {
        size_t cap = m->cap ? m->cap : 1024;
        while (cap < m->n + count)
            cap *= 2;
        float *p = merp_realloc(m->p, cap * 3 * sizeof *p);
        if (p == NULL)
            return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for markers");
        m->p = p;
        uint8_t *d = merp_realloc(m->dead, cap);
        if (d == NULL)
            return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for markers");
        m->dead = d;
        m->cap = cap;
    }
    memcpy(m->p + 3 * m->n, xyz, count * 3 * sizeof *xyz);
    memset(m->dead + m->n, 0, count);
    m->n += count;
    m->alive += count;
    m->dirty = 1;
    return MER_OK;
}

size_t mer_markers_count(const mer_markers *m) { return m->alive; }

size_t mer_markers_positions(const mer_markers *m, float *out, size_t cap)
{
    size_t k = 0;
    for (size_t i = 0; i < m->n; i++) {
        if (m->dead[i])
            continue;
        if (k < cap)
            memcpy(out + 3 * k, m->p + 3 * i, 3 * sizeof *out);
        k++;
    }
    return k;
}

/* Counting sort of live markers into cells, in index order within a cell. */
static int rebuild(mer_markers *m)
{
    if (m->alive > m->items_cap) {
        size_t cap = m->alive + m->alive / 2 + 16;
        merp_marker_entry *it = merp_realloc(m->items, cap * sizeof *it);
        if (it == NULL)
            return 0;
        m->items = it;
        m->items_cap = cap;
    }
    memset(m->start, 0, (m->ncells + 1) * sizeof *m->start);
    for (size_t i = 0; i < m->n; i++)
        if (!m->dead[i])
            m->start[merp_markers_cell(m, m->p + 3 * i) + 1]++;
    for (size_t c = 0; c < m->ncells; c++)
        m->start[c + 1] += m->start[c];
    /* Fill using start[c] as a cursor, then shift back. */
    for (size_t i = 0; i < m->n; i++)
        if (!m->dead[i]) {
            merp_marker_entry *e = &m->items[m->start[merp_markers_cell(m, m->p + 3 * i)]++];
            memcpy(e->p, m->p + 3 * i, sizeof e->p);
            e->id = (uint32_t)i;
        }
    for (size_t c = m->ncells; c > 0; c--) {
        m->end[c - 1] = m->start[c - 1];
        m->start[c] = m->start[c - 1];
    }
    m->start[0] = 0;
    m->dirty = 0;
    return 1;
}

int merp_markers_ensure_grid(mer_markers *m)
{
    return m->dirty ? rebuild(m) : 1;
}

static float dist2(const float *a, const float *b)
{
    float dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
    return dx * dx + dy * dy + dz * dz;
}

/* Cell ranges covering the box center ± radius. */
static void range(const mer_markers *m, const float *c, float radius, int lo[3], int hi[3])
{
    for (int a = 0; a < 3; a++) {
        lo[a] = merp_markers_coord(m, c[a] - radius, a);
        hi[a] = merp_markers_coord(m, c[a] + radius, a);
    }
}

/* Drops the entries of cell c within r2 of center (flagging their markers dead),
 * compacting the cell in place in index order. Returns how many. Most cells lose
 * none: nothing is written before the first one goes. */
static size_t remove_in_cell(mer_markers *m, size_t c, const float *center, float r2)
{
    merp_marker_entry *items = m->items;
    uint32_t t = m->start[c], end = m->end[c];
    while (t < end && dist2(items[t].p, center) > r2)
        t++;
    if (t == end)
        return 0;
    uint32_t kept = t;
    for (; t < end; t++) {
        if (dist2(items[t].p, center) <= r2)
            m->dead[items[t].id] = 1;
        else
            items[kept++] = items[t];
    }
    m->end[c] = kept;
    return end - kept;
}

static size_t remove_sphere_grid(mer_markers *m, const float *center, float radius)
{
    int lo[3], hi[3];
    range(m, center, radius, lo, hi);
    float r2 = radius * radius;
    size_t removed = 0, row = (size_t)m->dim[0], plane = row * (size_t)m->dim[1];
    for (int z = lo[2]; z <= hi[2]; z++)
        for (int y = lo[1]; y <= hi[1]; y++)
            for (int x = lo[0]; x <= hi[0]; x++)
                removed += remove_in_cell(m, (size_t)z * plane + (size_t)y * row + (size_t)x,
                                          center, r2);
    m->alive -= removed;
    return removed;
}

size_t mer_markers_remove_sphere(mer_markers *m, const float center[3], float radius)
{
    if (!merp_markers_ensure_grid(m)) {
        /* No memory for the grid: fall back to a linear scan. */
        float r2 = radius * radius;
        size_t removed = 0;
        for (size_t i = 0; i < m->n; i++)
            if (!m->dead[i] && dist2(m->p + 3 * i, center) <= r2) {
                m->dead[i] = 1;
                removed++;
            }
        m->alive -= removed;
        m->dirty = 1;
        return removed;
    }
    return remove_sphere_grid(m, center, radius);
}

size_t mer_markers_remove_if(mer_markers *m, int (*inside)(const float p[3], void *ctx), void *ctx)
{
    size_t removed = 0;
    for (size_t i = 0; i < m->n; i++)
        if (!m->dead[i] && inside(m->p + 3 * i, ctx)) {
            m->dead[i] = 1;
            removed++;
        }
    m->alive -= removed;
    if (removed > 0)
        m->dirty = 1; /* the grid's copies do not know: rebuild before the next query */
    return removed;
}

static inline int in_cone(const float *apex, const float *dir, const float *p, float r2,
                          float cos_half, float cos2, float *d2_out)
{
    float d[3] = {p[0] - apex[0], p[1] - apex[1], p[2] - apex[2]};
    float d2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    *d2_out = d2;
    float dot = d[0] * dir[0] + d[1] * dir[1] + d[2] * dir[2];
    /* dot/|d| >= cos(θ/2), without a division; careful with the sign. The tests
     * are combined with & rather than short-circuited: few markers of a cell are
     * in a cone, and a branch on each test is mispredicted half the time. */
    int near = (d2 > 0.0f) & (d2 <= r2), ahead = dot >= 0.0f;
    if (cos_half >= 0.0f)
        return near & ahead & (dot * dot >= cos2 * d2);
    return near & (ahead | (dot * dot <= cos2 * d2));
}

int mer_in_cone(const float apex[3], const float dir[3], const float p[3], float r,
                float cos_half_theta)
{
    float d2;
    return in_cone(apex, dir, p, r * r, cos_half_theta, cos_half_theta * cos_half_theta, &d2);
}

/* Scratch for the competition, sized to the grid's entries: best bud and its
 * distance² per entry. */
static mer_result ensure_scratch(mer_markers *m, mer_error *err)
{
    size_t need = m->start[m->ncells];
    if (need <= m->scratch_cap)
        return MER_OK;
    merp_claim *best = merp_realloc(m->best, need * sizeof *best);
    if (best == NULL)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for colonization");
    m->best = best;
    for (size_t i = m->scratch_cap; i < need; i++)
        m->best[i].bud = NONE;
    m->scratch_cap = need;
    return MER_OK;
}

/* Grid entry t at distance² d2 is perceived by bud b: it goes to the closest bud.
 * The entries claimed so far are listed in m->touched[0..*nt), in first-touched
 * order. Entries stay in place during a competition (only removals move them). */
static mer_result claim(mer_markers *m, uint32_t t, uint32_t b, float d2, size_t *nt,
                        mer_error *err)
{
    merp_claim *c = &m->best[t];
    if (c->bud != NONE) {
        if (d2 < c->d2) {
            c->bud = b;
            c->d2 = d2;
        }
        return MER_OK;
    }
    if (*nt == m->touched_cap) {
        size_t cap = m->touched_cap ? 2 * m->touched_cap : 4096;
        uint32_t *tt = merp_realloc(m->touched, cap * sizeof *tt);
        if (tt == NULL) {
            for (size_t x = 0; x < *nt; x++)
                m->best[m->touched[x]].bud = NONE;
            return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for colonization");
        }
        m->touched = tt;
        m->touched_cap = cap;
    }
    m->touched[(*nt)++] = t;
    c->bud = b;
    c->d2 = d2;
    return MER_OK;
}

/* A bud's perception volume (P09 §4.1): the cone of half-angle θ/2 within r. */
typedef struct cone {
    float r, r2, cos_half, cos2, sin_half;
} cone;

/* How far along a unit axis e the perception volume reaches, in units of r, for
 * cos ψ = e·dir: 1 when e lies inside the cone, else cos(ψ − θ/2) (the rim's
 * nearest generator), and never below 0 (the apex). */
static float reach(float cos_psi, const cone *k)
{
    if (cos_psi >= k->cos_half)
        return 1.0f;
    float sin_psi = sqrtf(fmaxf(0.0f, 1.0f - cos_psi * cos_psi));
    return fmaxf(0.0f, cos_psi * k->cos_half + sin_psi * k->sin_half);
}

/* Cell ranges covering the perception volume's bounding box: a 90° cone of
 * length r fills about a fifth of the box of the ball of radius r, and the
 * markers in the other cells could only fail in_cone. The box is widened by a
 * thousandth of r against rounding; a `dir` too far from unit length for that
 * gets the whole ball. */
static void cone_range(const mer_markers *m, const float *a, const float *dir, const cone *k,
                       int lo[3], int hi[3])
{
    float n2 = dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2];
    int ball = !(fabsf(n2 - 1.0f) <= 1e-4f);
    for (int x = 0; x < 3; x++) {
        float up = ball ? 1.0f : reach(dir[x], k), down = ball ? 1.0f : reach(-dir[x], k);
        lo[x] = merp_markers_coord(m, a[x] - k->r * (down + 1e-3f), x);
        hi[x] = merp_markers_coord(m, a[x] + k->r * (up + 1e-3f), x);
    }
}

/* Competition for bud b: every live marker in its perception volume is claimed,
 * and makes it not quiet. Cells are visited in index order and a cell's markers
 * in index order, so the claims' first-touched order is fixed. */
static mer_result compete(mer_markers *m, uint32_t b, const float *a, const float *db,
                          const cone *k, size_t *nt, uint8_t *quiet, mer_error *err)
{
    int lo[3], hi[3];
    cone_range(m, a, db, k, lo, hi);
    /* Locals: claims write through m, which would otherwise make every entry
     * reload the apex, the direction and the cell's bounds. */
    const float apex[3] = {a[0], a[1], a[2]}, dir[3] = {db[0], db[1], db[2]};
    const merp_marker_entry *items = m->items;
    size_t row = (size_t)m->dim[0], plane = row * (size_t)m->dim[1];
    for (int z = lo[2]; z <= hi[2]; z++)
        for (int y = lo[1]; y <= hi[1]; y++)
            for (int x = lo[0]; x <= hi[0]; x++) {
                size_t c = (size_t)z * plane + (size_t)y * row + (size_t)x;
                uint32_t t = m->start[c], end = m->end[c];
                for (; t < end; t++) {
                    float d2;
                    if (!in_cone(apex, dir, items[t].p, k->r2, k->cos_half, k->cos2, &d2))
                        continue;
                    if (quiet != NULL)
                        quiet[b] = 0;
                    mer_result rc = claim(m, t, b, d2, nt, err);
                    if (rc != MER_OK)
                        return rc;
                }
            }
    return MER_OK;
}

/* Q and V per bud from the claimed markers, in first-touched order (a fixed order):
 * V is the normalized sum of the unit vectors towards its markers. */
static void sum_directions(mer_markers *m, size_t nt, size_t n, const float *pos, float *q,
                           float *v, uint32_t *count)
{
    for (size_t t = 0; t < nt; t++) {
        uint32_t slot = m->touched[t];
        uint32_t b = m->best[slot].bud;
        m->best[slot].bud = NONE;
        const float *p = m->items[slot].p, *a = pos + 3 * (size_t)b;
        float d[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
        float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        v[3 * b] += d[0] / len;
        v[3 * b + 1] += d[1] / len;
        v[3 * b + 2] += d[2] / len;
        q[b] = 1.0f;
        if (count != NULL)
            count[b]++;
    }
    for (size_t b = 0; b < n; b++) {
        float *vb = v + 3 * b;
        float len = sqrtf(vb[0] * vb[0] + vb[1] * vb[1] + vb[2] * vb[2]);
        if (len > 0.0f) {
            vb[0] /= len;
            vb[1] /= len;
            vb[2] /= len;
        }
    }
}

mer_result mer_markers_colonize(mer_markers *m, size_t n, const float *pos, const float *dir,
                                float rho, float r, float theta, float *q, float *v,
                                uint32_t *count, uint8_t *quiet, mer_error *err)
{
    assert(m != NULL && (n == 0 || (pos != NULL && dir != NULL && q != NULL && v != NULL)));
    for (size_t b = 0; b < n; b++) {
        q[b] = 0.0f;
        v[3 * b] = v[3 * b + 1] = v[3 * b + 2] = 0.0f;
        if (count != NULL)
            count[b] = 0;
        if (quiet != NULL)
            quiet[b] = 1;
    }
    if (!merp_markers_ensure_grid(m))
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the marker grid");
    /* 1. Occupancy zones: markers within ρ of any bud are deleted from S. */
    for (size_t b = 0; b < n && m->alive > 0; b++) {
        /* A node's buds share its end: the zone of the first has emptied it. */
        if (b > 0 && memcmp(pos + 3 * b, pos + 3 * (b - 1), 3 * sizeof *pos) == 0)
            continue;
        remove_sphere_grid(m, pos + 3 * b, rho);
    }
    if (m->alive == 0 || n == 0)
        return MER_OK; /* with no markers every bud is quiet */
    mer_result rc = ensure_scratch(m, err);
    if (rc != MER_OK)
        return rc;
    cone k = {.r = r, .r2 = r * r, .cos_half = cosf(theta * 0.5f * MER_DEG2RAD)};
    if (theta >= 360.0f)
        k.cos_half = -1.0f;
    k.cos2 = k.cos_half * k.cos_half;
    k.sin_half = sqrtf(fmaxf(0.0f, 1.0f - k.cos2));
    size_t nt = 0;
    /* 2. Competition: each perceived marker goes to the closest bud. */
    for (size_t b = 0; b < n; b++) {
        rc = compete(m, (uint32_t)b, pos + 3 * b, dir + 3 * b, &k, &nt, quiet, err);
        if (rc != MER_OK)
            return rc;
    }
    /* 3. Q and V per bud. */
    sum_directions(m, nt, n, pos, q, v, count);
    return MER_OK;
}

mer_result merp_markers_clone(const mer_markers *m, mer_markers **out, mer_error *err)
{
    assert(m != NULL && out != NULL);
    mer_markers *c = merp_calloc(1, sizeof *c);
    *out = NULL;
    if (c == NULL)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the marker set");
    *c = *m;
    c->p = NULL;
    c->dead = NULL;
    c->start = NULL;
    c->end = NULL;
    c->items = NULL;
    c->best = NULL;
    c->touched = NULL;
    /* markers_near.c's scratch starts afresh */
    c->stamp = NULL;
    c->epoch = 0;
    c->bits = NULL;
    c->bits_cap = 0;
    c->near_cells = NULL;
    c->near_cap = 0;
    /* The grid and the scratch too: what the next query sees stays exactly as it was. */
    int ok = MERP_DUP(c->p, m->p, 3 * m->cap) && MERP_DUP(c->dead, m->dead, m->cap) &&
             MERP_DUP(c->start, m->start, m->ncells + 1) &&
             MERP_DUP(c->end, m->end, m->ncells) &&
             MERP_DUP(c->items, m->items, m->items_cap) &&
             MERP_DUP(c->best, m->best, m->scratch_cap) &&
             MERP_DUP(c->touched, m->touched, m->touched_cap);
    if (!ok) {
        mer_markers_free(c);
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for a copy of the markers");
    }
    *out = c;
    return MER_OK;
}

void merp_markers_save(const mer_markers *m, merp_bytes_out *out)
{
    /* Positions and deaths by index; the grid is rebuilt from them on the first
     * query, in index order within a cell, as it always is. */
    merp_put_u64(out, m->n);
    merp_put(out, m->p, 3 * m->n * sizeof *m->p);
    merp_put(out, m->dead, m->n);
}

mer_result merp_markers_load(mer_markers *m, merp_bytes_in *in, mer_error *err)
{
    assert(m != NULL && m->n == 0);
    uint64_t n = merp_get_u64(in);
    if (n > MARKERS_MAX)
        in->bad = 1;
    float *p = NULL;
    uint8_t *dead = NULL;
    if (MERP_GET_ARRAY(in, p, 3 * (size_t)n))
        MERP_GET_ARRAY(in, dead, (size_t)n);
    size_t alive = 0;
    for (size_t i = 0; !in->bad && i < n; i++) {
        if (dead[i] > 1)
            in->bad = 1;
        alive += !dead[i];
    }
    if (in->bad) {
        merp_free(p);
        merp_free(dead);
        return in->bad == 2 ? mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for markers")
                            : mer_error_set(err, MER_ERR_FORMAT, "markers", "damaged markers");
    }
    m->p = p;
    m->dead = dead;
    m->n = m->cap = (size_t)n;
    m->alive = alive;
    m->dirty = 1;
    return MER_OK;
}
