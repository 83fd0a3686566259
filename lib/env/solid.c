/* meristem — triangle meshes as solids: the inside test behind mesh obstacles and
 * mesh marker volumes (scene.h, mer_scene_add_mesh).
 *
 * Definition. A point is inside when it lies in the mesh's bounding box and at
 * least two of the three axis rays from it (+x, +y, +z) cross the triangles an odd
 * number of times. For a closed mesh every ray agrees, so this is the exact
 * interior; a small hole only misleads the rays that pass through it, and the vote
 * outweighs them. Parity ignores winding, so flipped or inconsistently wound
 * triangles give the same solid.
 *
 * Robustness. A ray is crossed by a triangle when the ray's point lies in the
 * triangle's projection along the ray axis. Projections are normalized to
 * counter-clockwise and tested with edge functions in double precision, each edge
 * evaluated in a canonical vertex order so that the two triangles sharing it see
 * exactly opposite values; a point exactly on an edge or a vertex is given to one
 * triangle only by the top-left rule of rasterizers. So a ray through a shared
 * edge or vertex of a watertight mesh counts one crossing, not zero or two.
 * Triangles seen edge-on (projected area 0) are never crossed.
 *
 * Speed. Built once: a grid of cubic cells over the bounding box (at most
 * MERP_SOLID_RES cells along its longest side, fewer for small meshes, and fewer
 * when huge triangles would touch too many cells). A cell that a triangle's plane
 * may pass through (within the triangle's box, conservatively) is SURFACE and
 * lists those triangles. Every cell keeps, per axis, the parity of the ray from
 * its centre, computed column by column from the top down, and the vote of the
 * three. A query in a cell that is not SURFACE is that cached vote: O(1). In a
 * SURFACE cell, each axis walks up its column to the first cell that is not
 * SURFACE and adds the crossings met on the way (each counted in the cell that
 * holds it) to that cell's cached parity: O(triangles listed in the few cells
 * walked). Off the surface the parity of a closed mesh cannot change, so these
 * answers are the exact ones; for an open mesh they are the rays' verdicts carried
 * from the nearest cell centre above, a close approximation of the definition.
 * Walks are long where cells are coarse next to faces; merp_solid_work sums
 * their cost over a region, so that callers can refuse a mesh that would cost
 * a scene too much (obstacles.c).
 */
#include "config.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "core/hash.h"
#include "env/env.h"

#define MERP_SOLID_RES 128      /* cells along the longest side, at most */
#define MERP_SOLID_RES_MIN 16   /* and at least, unless huge triangles force fewer */
#define MERP_SOLID_TOUCH_MAX (24u * 1024 * 1024) /* triangle-cell pairs examined (and at most listed) */

/* A cell's byte: bits 0..2 the ray parity along x, y, z at its centre; then: */
#define CELL_SURFACE 0x08u
#define CELL_IN 0x10u /* the vote at its centre */

struct merp_solid {
    size_t ntri;
    float *tri;        /* 9 floats per triangle, world space */
    float lo[3], hi[3];
    float org[3];      /* grid origin (= lo) */
    float h, inv_h;    /* cell edge */
    int dim[3];
    uint8_t *cell;     /* x fastest */
    uint32_t *start;   /* CSR: the triangles listed in each cell (SURFACE cells only) */
    uint32_t *listed;
    uint64_t digest;
};

static int col(const merp_solid *s, int a, float x)
{
    float f = (x - s->org[a]) * s->inv_h;
    if (!(f >= 0.0f))
        return 0;
    if (f >= (float)s->dim[a])
        return s->dim[a] - 1;
    return (int)f;
}

static float centre(const merp_solid *s, int a, int i)
{
    return s->org[a] + ((float)i + 0.5f) * s->h;
}

static size_t cell_index(const merp_solid *s, const int c[3])
{
    return ((size_t)c[2] * (size_t)s->dim[1] + (size_t)c[1]) * (size_t)s->dim[0] + (size_t)c[0];
}

/* Edge function of (a → b) at p in the (u, v) plane: > 0 when p is to the left.
 * Evaluated with the lexicographically smaller vertex first, so that the reversed
 * edge of a neighbouring triangle gets exactly the negated value. */
static double edge_fn(const double *a, const double *b, double pu, double pv)
{
    int swap = a[0] > b[0] || (a[0] == b[0] && a[1] > b[1]);
    const double *x = swap ? b : a, *y = swap ? a : b;
    double e = (y[0] - x[0]) * (pv - x[1]) - (y[1] - x[1]) * (pu - x[0]);
    return swap ? -e : e;
}

/* Top-left rule for a counter-clockwise triangle (u right, v up): a point on an
 * edge belongs to the triangle when the edge goes down, or left along a
 * horizontal. An edge and its reverse never both qualify. */
static int top_left(const double *a, const double *b)
{
    double du = b[0] - a[0], dv = b[1] - a[1];
    return dv < 0.0 || (dv == 0.0 && du < 0.0);
}

static int covers(double w, const double *a, const double *b)
{
    return w > 0.0 || (w == 0.0 && top_left(a, b));
}

/* Whether the line along axis A through (pu, pv) crosses triangle t; if so, the
 * A coordinate of the crossing (clamped to the triangle's extent) goes to *at. */
static int crossing(const float *t, int A, float pu, float pv, float *at)
{
    int U = (A + 1) % 3, V = (A + 2) % 3;
    double q[3][2];
    for (int k = 0; k < 3; k++) {
        q[k][0] = (double)t[3 * k + U];
        q[k][1] = (double)t[3 * k + V];
    }
    double area = (q[1][0] - q[0][0]) * (q[2][1] - q[0][1]) -
                  (q[1][1] - q[0][1]) * (q[2][0] - q[0][0]);
    if (area == 0.0)
        return 0;
    int i1 = 1, i2 = 2;
    if (area < 0.0) {
        i1 = 2;
        i2 = 1;
    }
    const double *p0 = q[0], *p1 = q[i1], *p2 = q[i2];
    double u = (double)pu, v = (double)pv;
    double w0 = edge_fn(p1, p2, u, v), w1 = edge_fn(p2, p0, u, v), w2 = edge_fn(p0, p1, u, v);
    if (!covers(w0, p1, p2) || !covers(w1, p2, p0) || !covers(w2, p0, p1))
        return 0;
    double sum = w0 + w1 + w2;
    if (!(sum > 0.0))
        return 0;
    float a0 = t[A], a1 = t[3 * i1 + A], a2 = t[3 * i2 + A];
    float x = (float)((w0 * (double)a0 + w1 * (double)a1 + w2 * (double)a2) / sum);
    float mn = fminf(a0, fminf(a1, a2)), mx = fmaxf(a0, fmaxf(a1, a2));
    *at = x < mn ? mn : x > mx ? mx : x;
    return 1;
}

/* Crossings of the line along A through (pu, pv) that lie in cell c (counted in
 * the cell that holds them, once): how many are above `above`, and how many not. */
static void cell_crossings(const merp_solid *s, const int c[3], int A, float pu, float pv,
                           float above, uint32_t *hi, uint32_t *lo)
{
    size_t ci = cell_index(s, c);
    uint32_t h = 0, l = 0;
    for (uint32_t e = s->start[ci]; e < s->start[ci + 1]; e++) {
        float at;
        if (!crossing(s->tri + 9 * (size_t)s->listed[e], A, pu, pv, &at) || col(s, A, at) != c[A])
            continue;
        if (at > above)
            h++;
        else
            l++;
    }
    *hi = h;
    *lo = l;
}

/* Parity of the crossings of the ray from p (in SURFACE cell c) along +A. */
static int ray_parity(const merp_solid *s, int A, const float p[3], const int c[3])
{
    int U = (A + 1) % 3, V = (A + 2) % 3;
    int k[3] = {c[0], c[1], c[2]};
    uint32_t odd = 0;
    for (; k[A] < s->dim[A]; k[A]++) {
        uint8_t st = s->cell[cell_index(s, k)];
        if (!(st & CELL_SURFACE))
            return (int)((odd + ((unsigned)st >> A)) & 1u);
        uint32_t hi, lo;
        cell_crossings(s, k, A, p[U], p[V], p[A], &hi, &lo);
        odd += hi;
    }
    return (int)(odd & 1u); /* past the grid the ray is past the mesh */
}

int merp_solid_inside(const merp_solid *s, const float p[3])
{
    for (int a = 0; a < 3; a++)
        if (!(p[a] >= s->lo[a] && p[a] <= s->hi[a]))
            return 0;
    int c[3] = {col(s, 0, p[0]), col(s, 1, p[1]), col(s, 2, p[2])};
    uint8_t st = s->cell[cell_index(s, c)];
    if (!(st & CELL_SURFACE))
        return (st & CELL_IN) != 0;
    int votes = 0;
    for (int A = 0; A < 3; A++)
        votes += ray_parity(s, A, p, c);
    return votes >= 2;
}

void merp_solid_bounds(const merp_solid *s, float lo[3], float hi[3])
{
    memcpy(lo, s->lo, sizeof s->lo);
    memcpy(hi, s->hi, sizeof s->hi);
}

uint64_t merp_solid_digest(const merp_solid *s) { return s->digest; }

void merp_solid_free(merp_solid *s)
{
    if (s == NULL)
        return;
    merp_free(s->start);
    merp_free(s->listed);
    merp_free(s->cell);
    merp_free(s->tri);
    merp_free(s);
}

static void tri_cols(const merp_solid *s, const float *t, int lo[3], int hi[3])
{
    for (int a = 0; a < 3; a++) {
        float mn = t[a], mx = t[a];
        for (int k = 1; k < 3; k++) {
            float x = t[3 * k + a];
            mn = x < mn ? x : mn;
            mx = x > mx ? x : mx;
        }
        lo[a] = col(s, a, mn);
        hi[a] = col(s, a, mx);
    }
}

/* Sets the grid for `n` cells along the longest side (h at least `hmin`). */
static void set_grid(merp_solid *s, int n, double hmin)
{
    double longest = 0.0;
    for (int a = 0; a < 3; a++) {
        double ext = (double)s->hi[a] - (double)s->lo[a];
        longest = ext > longest ? ext : longest;
    }
    double h = longest / (double)n;
    if (h < hmin)
        h = hmin;
    s->h = (float)h;
    s->inv_h = 1.0f / s->h;
    memcpy(s->org, s->lo, sizeof s->org);
    for (int a = 0; a < 3; a++) {
        /* At most n + 1 (rounding); never clamped, so every cell has edge h. */
        double d = ceil(((double)s->hi[a] - (double)s->lo[a]) / (double)s->h);
        s->dim[a] = d < 1.0 ? 1 : (int)d;
    }
}

/* Triangle-cell pairs to examine: the cells of each triangle's box. */
static uint64_t grid_cost(const merp_solid *s)
{
    uint64_t t = 0;
    for (size_t i = 0; i < s->ntri; i++) {
        int lo[3], hi[3];
        tri_cols(s, s->tri + 9 * i, lo, hi);
        t += (uint64_t)(hi[0] - lo[0] + 1) * (uint64_t)(hi[1] - lo[1] + 1) *
             (uint64_t)(hi[2] - lo[2] + 1);
    }
    return t;
}

/* Calls back for every cell that triangle t's plane may pass through, within the
 * triangle's box of cells (conservative: cells are inflated by h/16, far more
 * than the rounding of col()). Returns how many. */
static uint32_t plane_cells(merp_solid *s, uint32_t ti, uint32_t *counts, int fill)
{
    const float *t = s->tri + 9 * (size_t)ti;
    double e1[3], e2[3], nrm[3];
    for (int a = 0; a < 3; a++) {
        e1[a] = (double)t[3 + a] - (double)t[a];
        e2[a] = (double)t[6 + a] - (double)t[a];
    }
    nrm[0] = e1[1] * e2[2] - e1[2] * e2[1];
    nrm[1] = e1[2] * e2[0] - e1[0] * e2[2];
    nrm[2] = e1[0] * e2[1] - e1[1] * e2[0];
    if (nrm[0] == 0.0 && nrm[1] == 0.0 && nrm[2] == 0.0)
        return 0; /* no area in any projection: never crossed */
    double d = nrm[0] * (double)t[0] + nrm[1] * (double)t[1] + nrm[2] * (double)t[2];
    double half = 0.5 * (double)s->h * (1.0 + 1.0 / 8.0);
    double reach = half * (fabs(nrm[0]) + fabs(nrm[1]) + fabs(nrm[2]));
    int lo[3], hi[3];
    tri_cols(s, t, lo, hi);
    uint32_t n = 0;
    int c[3];
    for (c[2] = lo[2]; c[2] <= hi[2]; c[2]++)
        for (c[1] = lo[1]; c[1] <= hi[1]; c[1]++)
            for (c[0] = lo[0]; c[0] <= hi[0]; c[0]++) {
                double m = 0.0;
                for (int a = 0; a < 3; a++)
                    m += nrm[a] * ((double)s->org[a] + ((double)c[a] + 0.5) * (double)s->h);
                if (!(fabs(m - d) <= reach))
                    continue;
                size_t ci = cell_index(s, c);
                n++;
                if (fill)
                    s->listed[s->start[ci]++] = ti;
                else
                    counts[ci + 1]++;
            }
    return n;
}

/* Ray parities at the cell centres along +A, column by column from the top. */
static void parities(merp_solid *s, int A)
{
    int U = (A + 1) % 3, V = (A + 2) % 3;
    for (int iv = 0; iv < s->dim[V]; iv++)
        for (int iu = 0; iu < s->dim[U]; iu++) {
            float pu = centre(s, U, iu), pv = centre(s, V, iv);
            int k[3], c[3];
            k[U] = iu;
            k[V] = iv;
            c[U] = col(s, U, pu); /* = iu, as cells are wide enough (hmin) */
            c[V] = col(s, V, pv);
            uint32_t above = 0;
            for (int i = s->dim[A] - 1; i >= 0; i--) {
                k[A] = c[A] = i;
                uint32_t hi = 0, lo = 0;
                if (s->cell[cell_index(s, c)] & CELL_SURFACE)
                    cell_crossings(s, c, A, pu, pv, centre(s, A, i), &hi, &lo);
                s->cell[cell_index(s, k)] |= (uint8_t)(((above + hi) & 1u) << A);
                above += hi + lo;
            }
        }
}

mer_result merp_solid_new(const float *xyz, size_t triangles, merp_solid **out, mer_error *err)
{
    *out = NULL;
    merp_solid *s = merp_calloc(1, sizeof *s);
    if (s == NULL)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for a mesh");
    s->ntri = triangles;
    s->tri = merp_malloc(triangles * 9 * sizeof *s->tri);
    if (s->tri == NULL) {
        merp_free(s);
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for a mesh");
    }
    memcpy(s->tri, xyz, triangles * 9 * sizeof *xyz);
    /* Digest of the triangles (FNV-1a over 32-bit words), for mer_scene_hash. */
    uint64_t hsh = MERP_FNV_OFFSET;
    float amax = 0.0f;
    for (size_t i = 0; i < 9 * triangles; i++) {
        uint32_t w;
        memcpy(&w, &s->tri[i], sizeof w);
        hsh = merp_fnv_word(hsh, w);
        int a = (int)(i % 3);
        float x = s->tri[i];
        if (i < 3 || x < s->lo[a])
            s->lo[a] = x;
        if (i < 3 || x > s->hi[a])
            s->hi[a] = x;
        amax = fabsf(x) > amax ? fabsf(x) : amax;
    }
    s->digest = hsh;
    /* Cells no finer than 64 ulps of the largest coordinate, so that a cell
     * centre always falls in its own cell. */
    double hmin = (double)amax * ldexp(1.0, -17);
    if (hmin <= 0.0)
        hmin = 1e-30;
    double n0 = 16.0 * cbrt((double)triangles);
    int n = n0 < MERP_SOLID_RES_MIN ? MERP_SOLID_RES_MIN : n0 > MERP_SOLID_RES ? MERP_SOLID_RES : (int)n0;
    for (;;) {
        set_grid(s, n, hmin);
        if (grid_cost(s) <= MERP_SOLID_TOUCH_MAX || n == 1)
            break; /* at n = 1, one pair per triangle */
        n /= 2;
    }
    size_t ncell = (size_t)s->dim[0] * (size_t)s->dim[1] * (size_t)s->dim[2];
    s->cell = merp_calloc(ncell, 1);
    s->start = merp_calloc(ncell + 1, sizeof *s->start);
    if (s->cell == NULL || s->start == NULL) {
        merp_solid_free(s);
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for a mesh grid");
    }
    /* Count, allocate, fill (start[c] as a cursor), shift back. */
    for (size_t i = 0; i < triangles; i++)
        plane_cells(s, (uint32_t)i, s->start, 0);
    for (size_t c = 0; c < ncell; c++) {
        if (s->start[c + 1] > 0)
            s->cell[c] = CELL_SURFACE;
        s->start[c + 1] += s->start[c];
    }
    s->listed = merp_malloc((s->start[ncell] ? s->start[ncell] : 1) * sizeof *s->listed);
    if (s->listed == NULL) {
        merp_solid_free(s);
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for a mesh grid");
    }
    for (size_t i = 0; i < triangles; i++)
        plane_cells(s, (uint32_t)i, NULL, 1);
    for (size_t c = ncell; c > 0; c--)
        s->start[c] = s->start[c - 1];
    s->start[0] = 0;
    for (int A = 0; A < 3; A++)
        parities(s, A);
    for (size_t c = 0; c < ncell; c++) {
        unsigned b = s->cell[c];
        if ((b & 1u) + ((b >> 1) & 1u) + ((b >> 2) & 1u) >= 2)
            s->cell[c] = (uint8_t)(b | CELL_IN);
    }
    *out = s;
    return MER_OK;
}

/* The overlap of cell i along axis a with [lo, hi]. */
static double overlap(const merp_solid *s, int a, int i, float lo, float hi)
{
    double c0 = (double)s->org[a] + (double)i * (double)s->h, c1 = c0 + (double)s->h;
    double a0 = c0 > (double)lo ? c0 : (double)lo, a1 = c1 < (double)hi ? c1 : (double)hi;
    return a1 > a0 ? a1 - a0 : 0.0;
}

/* Σ over cells of (volume of the cell in [lo, hi]) × (the triangles a query in
 * it meets walking up axis A: ray_parity's cost). */
static double walk_work(const merp_solid *s, int A, const float lo[3], const float hi[3])
{
    int U = (A + 1) % 3, V = (A + 2) % 3;
    double total = 0.0;
    int k[3];
    for (k[V] = 0; k[V] < s->dim[V]; k[V]++)
        for (k[U] = 0; k[U] < s->dim[U]; k[U]++) {
            double area = overlap(s, U, k[U], lo[U], hi[U]) * overlap(s, V, k[V], lo[V], hi[V]);
            if (area == 0.0)
                continue;
            double run = 0.0; /* triangles listed from this cell up to the first not SURFACE */
            for (k[A] = s->dim[A] - 1; k[A] >= 0; k[A]--) {
                size_t ci = cell_index(s, k);
                run = s->cell[ci] & CELL_SURFACE ? run + (double)(s->start[ci + 1] - s->start[ci]) : 0.0;
                total += run * area * overlap(s, A, k[A], lo[A], hi[A]);
            }
        }
    return total;
}

double merp_solid_work(const merp_solid *s, const float lo[3], const float hi[3], double density)
{
    assert(s != NULL && lo != NULL && hi != NULL && density >= 0.0);
    double work = 0.0;
    for (int A = 0; A < 3; A++)
        work += walk_work(s, A, lo, hi);
    return work * density;
}

size_t merp_solid_candidates(const merp_solid *s, uint32_t *out)
{
    size_t ncell = (size_t)s->dim[0] * (size_t)s->dim[1] * (size_t)s->dim[2], k = 0;
    for (size_t c = 0; c < ncell; c++)
        if (s->cell[c] & (CELL_IN | CELL_SURFACE)) {
            if (out != NULL)
                out[k] = (uint32_t)c;
            k++;
        }
    return k;
}

double merp_solid_cell_volume(const merp_solid *s)
{
    return (double)s->h * (double)s->h * (double)s->h;
}

void merp_solid_cell_point(const merp_solid *s, uint32_t cell, const float f[3], float out[3])
{
    size_t c = cell;
    int i = (int)(c % (size_t)s->dim[0]);
    c /= (size_t)s->dim[0];
    int j = (int)(c % (size_t)s->dim[1]);
    int k = (int)(c / (size_t)s->dim[1]);
    int ijk[3] = {i, j, k};
    for (int a = 0; a < 3; a++)
        out[a] = s->org[a] + ((float)ijk[a] + f[a]) * s->h;
}

mer_result merp_solid_clone(const merp_solid *s, merp_solid **out, mer_error *err)
{
    /* Voxelizing again is deterministic: the same triangles give the same cells. */
    return merp_solid_new(s->tri, s->ntri, out, err);
}

const float *merp_solid_triangles(const merp_solid *s, size_t *count)
{
    *count = s->ntri;
    return s->tri;
}
