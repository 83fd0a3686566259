/* meristem — graphically defined functions (G04 §4): the clamped uniform cubic
 * B-spline of a control polygon, sampled at x found by bisection, and the plain
 * piecewise-linear kind. See gfunc.h for the definition. */
#include "config.h"

#include <assert.h>
#include <math.h>
#include <string.h>

#include "models/inverse/gfunc.h"

/* Bisection steps: 2^-40 of the parameter range is far below a float's
 * resolution, so more steps change nothing. */
#define BISECT_STEPS 40

/* The polygon with every point repeated by its multiplicity; returns the count. */
static uint32_t expand(const merp_gfunc *f, double *px, double *py)
{
    uint32_t n = 0;
    for (uint32_t i = 0; i < f->npts; i++)
        for (uint32_t k = 0; k < f->pts[i].m && n < MERP_GF_EXPANDED_MAX; k++) {
            px[n] = (double)f->pts[i].x;
            py[n] = (double)f->pts[i].y;
            n++;
        }
    return n;
}

/* The clamped uniform knot t_i for n control points of degree 3: four knots at
 * each end, unit spacing in between, so the curve ends at the end points. */
static double knot(int i, int n)
{
    if (i <= 3)
        return 0.0;
    if (i >= n)
        return (double)(n - 3);
    return (double)(i - 3);
}

/* De Boor's algorithm at parameter s ∈ [0, n - 3] for the n points (px, py). */
static void de_boor(const double *px, const double *py, int n, double s, double *x, double *y)
{
    int k = (int)s + 3; /* the span t_k <= s < t_{k+1} */
    if (k > n - 1)
        k = n - 1;
    double dx[4], dy[4];
    for (int j = 0; j < 4; j++) {
        dx[j] = px[k - 3 + j];
        dy[j] = py[k - 3 + j];
    }
    for (int r = 1; r <= 3; r++)
        for (int j = 3; j >= r; j--) {
            int i = k - 3 + j;
            double lo = knot(i, n), hi = knot(i + 4 - r, n);
            double a = hi > lo ? (s - lo) / (hi - lo) : 0.0;
            dx[j] = (1.0 - a) * dx[j - 1] + a * dx[j];
            dy[j] = (1.0 - a) * dy[j - 1] + a * dy[j];
        }
    *x = dx[3];
    *y = dy[3];
}

void merp_gfunc_curve(const merp_gfunc *f, float u, float *x, float *y)
{
    assert(f != NULL && x != NULL && y != NULL);
    double px[MERP_GF_EXPANDED_MAX], py[MERP_GF_EXPANDED_MAX];
    int n = (int)expand(f, px, py);
    assert(n >= 4);
    double s = (double)(u < 0.0f ? 0.0f : u > 1.0f ? 1.0f : u) * (double)(n - 3);
    double cx, cy;
    de_boor(px, py, n, s, &cx, &cy);
    *x = (float)cx;
    *y = (float)cy;
}

/* The samples: for x_i = i / (samples - 1), the parameter with x(u) = x_i by
 * bisection (x(u) is non-decreasing: a B-spline's coordinate is a convex
 * combination of the polygon's, which do not decrease), and the curve point
 * there. Keeping the point reached, not (x_i, y), makes a polygon on a line give
 * samples on that line, hence values on it exactly. */
static void sample(merp_gfunc *f)
{
    double px[MERP_GF_EXPANDED_MAX], py[MERP_GF_EXPANDED_MAX];
    int n = (int)expand(f, px, py);
    double top = (double)(n - 3);
    for (uint32_t i = 0; i < f->samples; i++) {
        double target = (double)i / (double)(f->samples - 1);
        double lo = 0.0, hi = top, x, y;
        for (int it = 0; it < BISECT_STEPS; it++) {
            double mid = 0.5 * (lo + hi);
            de_boor(px, py, n, mid, &x, &y);
            if (x < target)
                lo = mid;
            else
                hi = mid;
        }
        de_boor(px, py, n, 0.5 * (lo + hi), &x, &y);
        f->sx[i] = (float)x;
        f->sy[i] = (float)y;
    }
    f->sx[0] = 0.0f; /* the ends are exact: the clamped curve starts and ends there */
    f->sy[0] = (float)py[0];
    f->sx[f->samples - 1] = 1.0f;
    f->sy[f->samples - 1] = (float)py[n - 1];
}

static mer_result check(const merp_gfunc *f, mer_error *err)
{
    if (f->name[0] == '\0' || memchr(f->name, '\0', sizeof f->name) == NULL)
        return mer_error_set(err, MER_ERR_INVALID, "name", "a function needs a name");
    if (f->kind != MERP_GF_BSPLINE && f->kind != MERP_GF_LINEAR)
        return mer_error_set(err, MER_ERR_INVALID, "kind", "%s: unknown kind", f->name);
    if (f->samples < 2 || f->samples > MERP_GF_SAMPLES_MAX)
        return mer_error_set(err, MER_ERR_INVALID, "samples", "%s: samples must be in 2..%u",
                             f->name, MERP_GF_SAMPLES_MAX);
    if (f->npts < 2 || f->npts > MERP_GF_POINTS_MAX)
        return mer_error_set(err, MER_ERR_INVALID, "points", "%s: 2..%u points", f->name,
                             MERP_GF_POINTS_MAX);
    uint32_t counted = 0;
    for (uint32_t i = 0; i < f->npts; i++) {
        const merp_gf_point *p = &f->pts[i];
        if (!isfinite(p->x) || !isfinite(p->y) || p->x < 0.0f || p->x > 1.0f)
            return mer_error_set(err, MER_ERR_INVALID, "points",
                                 "%s: point %u: x must lie in [0, 1]", f->name, i + 1);
        if (i > 0 && p->x < f->pts[i - 1].x)
            return mer_error_set(err, MER_ERR_INVALID, "points",
                                 "%s: point %u: x decreases", f->name, i + 1);
        if (p->m < 1 || p->m > MERP_GF_EXPANDED_MAX)
            return mer_error_set(err, MER_ERR_INVALID, "points",
                                 "%s: point %u: multiplicity must be in 1..%u", f->name, i + 1,
                                 MERP_GF_EXPANDED_MAX);
        counted += p->m;
    }
    if (f->pts[0].x != 0.0f || f->pts[f->npts - 1].x != 1.0f)
        return mer_error_set(err, MER_ERR_INVALID, "points",
                             "%s: the first point must be at x = 0 and the last at x = 1",
                             f->name);
    if (counted > MERP_GF_EXPANDED_MAX)
        return mer_error_set(err, MER_ERR_INVALID, "points",
                             "%s: more than %u points counting multiplicities", f->name,
                             MERP_GF_EXPANDED_MAX);
    if (f->kind == MERP_GF_BSPLINE && counted < 4)
        return mer_error_set(err, MER_ERR_INVALID, "points",
                             "%s: a cubic B-spline needs 4 points counting multiplicities",
                             f->name);
    return MER_OK;
}

mer_result merp_gfunc_prepare(merp_gfunc *f, mer_error *err)
{
    assert(f != NULL);
    mer_result rc = check(f, err);
    if (rc != MER_OK)
        return rc;
    if (f->kind == MERP_GF_BSPLINE)
        sample(f);
    return MER_OK;
}

/* Linear interpolation in the table (xs, ys) of n points, xs non-decreasing; on a
 * vertical step (equal x) the later point wins. */
static float interpolate(const float *xs, const float *ys, uint32_t n, float x)
{
    uint32_t lo = 0, hi = n - 1;
    while (hi - lo > 1) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (xs[mid] <= x)
            lo = mid;
        else
            hi = mid;
    }
    float w = xs[hi] - xs[lo];
    if (!(w > 0.0f))
        return ys[hi];
    float a = (x - xs[lo]) / w;
    a = a < 0.0f ? 0.0f : a > 1.0f ? 1.0f : a;
    return ys[lo] + a * (ys[hi] - ys[lo]);
}

float merp_gfunc_eval(const merp_gfunc *f, float x)
{
    assert(f != NULL && f->npts >= 2);
    if (!(x > 0.0f))
        x = 0.0f;
    else if (x > 1.0f)
        x = 1.0f;
    if (f->kind == MERP_GF_BSPLINE)
        return interpolate(f->sx, f->sy, f->samples, x);
    float xs[MERP_GF_POINTS_MAX], ys[MERP_GF_POINTS_MAX];
    for (uint32_t i = 0; i < f->npts; i++) {
        xs[i] = f->pts[i].x;
        ys[i] = f->pts[i].y;
    }
    return interpolate(xs, ys, f->npts, x);
}

mer_result merp_gfunc_make(merp_gfunc *f, const char *name, merp_gf_kind kind,
                           uint32_t samples, const float (*xy)[2], uint32_t n,
                           mer_error *err)
{
    assert(f != NULL && name != NULL && xy != NULL);
    memset(f, 0, sizeof *f);
    size_t len = strlen(name);
    if (len >= sizeof f->name)
        return mer_error_set(err, MER_ERR_INVALID, "name", "a name has at most %u bytes",
                             MERP_GF_NAME_MAX - 1);
    memcpy(f->name, name, len);
    f->kind = kind;
    f->samples = samples;
    if (n > MERP_GF_POINTS_MAX)
        return mer_error_set(err, MER_ERR_INVALID, "points", "%s: 2..%u points", name,
                             MERP_GF_POINTS_MAX);
    f->npts = n;
    for (uint32_t i = 0; i < n; i++)
        f->pts[i] = (merp_gf_point){xy[i][0], xy[i][1], 1};
    return merp_gfunc_prepare(f, err);
}

int merp_gfunc_equal(const merp_gfunc *a, const merp_gfunc *b)
{
    if (strcmp(a->name, b->name) != 0 || a->kind != b->kind || a->samples != b->samples ||
        (a->flip != 0) != (b->flip != 0) || a->npts != b->npts)
        return 0;
    for (uint32_t i = 0; i < a->npts; i++)
        if (a->pts[i].x != b->pts[i].x || a->pts[i].y != b->pts[i].y ||
            a->pts[i].m != b->pts[i].m)
            return 0;
    return 1;
}
