/* meristem — a row of skeletal segments as a structure of arrays
 * (implicit.h): one point's closest points on four segments, and their
 * capsules' or bounds' fields and gradients, in 4-wide loops that GCC
 * vectorizes (SSE2 at -O2). Each lane does the scalar code's arithmetic in
 * its order (merp_seg_d2, merp_seg_field, merp_bound_field, gradient.c's
 * closed form), so a lane's value is the scalar one to the bit
 * (test_implicit's row_lanes_match_scalar). */
#include "config.h"

#include <assert.h>
#include <math.h>
#include <stddef.h>

#include "mesh/implicit/implicit.h"

/* The loops below are 4-wide on purpose: ask GCC's vectorizer here, where
 * it pays, with no traps assumed from floating point (which changes no
 * value), so that the selects of a lane can be if-converted. Clang has no
 * such attribute and vectorizes these loops at -O2 by itself. */
#if defined(__GNUC__) && !defined(__clang__)
#define VECTORIZE __attribute__((optimize("tree-vectorize", "no-trapping-math")))
#else
#define VECTORIZE
#endif

/* The closest points and bound_lanes forced into each row function (GCC
 * and clang): the lanes stay in registers from one step to the next, and
 * the bound field alone drops the gradient's factor, and its division, as
 * dead code. */
#if defined(__GNUC__)
#define INLINE __attribute__((always_inline)) inline
#else
#define INLINE inline
#endif

/* A lane no segment fills: a ball so far away that every field of it is 0
 * (x² ≥ 1, d² ≥ r_out²), with radii 1/2, 1 that divide nothing by zero. */
#define FAR 1e18f

void merp_row_clear(merp_row *r)
{
    for (int l = 0; l < MERP_ROW; l++)
        merp_row_set(r, l, (const float[3]){FAR, FAR, FAR}, (const float[3]){FAR, FAR, FAR}, 0.5f, 1.0f);
}

void merp_row_set(merp_row *r, int l, const float a[3], const float b[3], float ra, float rb)
{
    assert(l >= 0 && l < MERP_ROW);
    float ab[3];
    for (int k = 0; k < 3; k++)
        r->a[k][l] = a[k], ab[k] = r->ab[k][l] = b[k] - a[k];
    float len2 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
    r->len2[l] = len2;
    r->den[l] = len2 > 0.0f ? len2 : 1.0f;
    for (int k = 0; k < 3; k++)
        r->dt[k][l] = ab[k] / r->den[l];
    r->ra[l] = ra, r->rb[l] = rb, r->rb2[l] = rb * rb;
    r->span[l] = rb - ra, r->dR[l] = r->span[l] / MERP_SEG_XC;
}

/* merp_row_closest, inlined into the row's fields: their lanes then
 * continue in registers from the closest points' arithmetic. */
VECTORIZE INLINE static void closest(const merp_row *restrict r, const float p[3], merp_row_point *restrict c)
{
    const float px = p[0], py = p[1], pz = p[2]; /* loaded once: c may not alias p */
    for (int l = 0; l < MERP_ROW; l++) {
        float apx = px - r->a[0][l], apy = py - r->a[1][l], apz = pz - r->a[2][l];
        float abx = r->ab[0][l], aby = r->ab[1][l], abz = r->ab[2][l];
        float u = (apx * abx + apy * aby + apz * abz) / r->den[l];
        u = u < 0.0f ? 0.0f : u;
        u = u > 1.0f ? 1.0f : u;
        u = r->len2[l] > 0.0f ? u : 0.0f;
        float qx = apx - u * abx, qy = apy - u * aby, qz = apz - u * abz;
        c->t[l] = u;
        c->q[0][l] = qx, c->q[1][l] = qy, c->q[2][l] = qz;
        c->d2[l] = qx * qx + qy * qy + qz * qz;
    }
}

VECTORIZE void merp_row_closest(const merp_row *restrict r, const float p[3], merp_row_point *restrict c)
{
    closest(r, p, c);
}

VECTORIZE void merp_row_seg_field(const merp_row *r, const float p[3], float f[MERP_ROW])
{
    merp_row_point c;
    closest(r, p, &c);
    for (int l = 0; l < MERP_ROW; l++) {
        float t = c.t[l], R = ((1.0f - t) * r->ra[l] + t * r->rb[l]) / MERP_SEG_XC;
        float x2 = c.d2[l] / (R * R), u = 1.0f - x2;
        f[l] = x2 < 1.0f ? u * u * u : 0.0f;
    }
}

VECTORIZE void merp_row_seg_gradient(const merp_row *r, const float p[3], merp_row_grad *out)
{
    merp_row_point c;
    closest(r, p, &c);
    /* Two loops, the selects apart from the arithmetic: as one, GCC's
     * partial redundancy elimination turns the selects into branches and
     * the loop no longer vectorizes. */
    float R[MERP_ROW], R2[MERP_ROW], u[MERP_ROW], m[MERP_ROW];
    const float *dR = r->dR;
    for (int l = 0; l < MERP_ROW; l++) {
        float t = c.t[l];
        R[l] = ((1.0f - t) * r->ra[l] + t * r->rb[l]) / MERP_SEG_XC, R2[l] = R[l] * R[l];
        float x2 = c.d2[l] / R2[l];
        /* Outside the support x² ≥ 1: taken as 1 there, u = 0 makes f and
         * ∇f 0 (and finite) without a branch. */
        u[l] = 1.0f - (x2 < 1.0f ? x2 : 1.0f);
        /* ∇R = dR ∇t where t moves with p (m = 1), not where it is clamped. */
        float moves = dR[l] != 0.0f ? 1.0f : 0.0f;
        moves = r->len2[l] > 0.0f ? moves : 0.0f;
        moves = t > 0.0f ? moves : 0.0f;
        m[l] = t < 1.0f ? moves : 0.0f;
    }
    for (int l = 0; l < MERP_ROW; l++) {
        /* ∇f = −3u² ∇x², ∇x² = 2q / R² − 2d² ∇R / R³. */
        float uu = u[l], cq = -6.0f * uu * uu / R2[l], ct = 6.0f * uu * uu * c.d2[l] * dR[l] / (R2[l] * R[l]);
        out->f[l] = uu * uu * uu;
        /* + 0: where u = 0 or m = 0 the products are ±0; a zero sum is +0,
         * as the scalar code's early return gives (adding +0 leaves any
         * other value as it is). */
        out->g[0][l] = cq * c.q[0][l] + ct * (m[l] * r->dt[0][l]) + 0.0f;
        out->g[1][l] = cq * c.q[1][l] + ct * (m[l] * r->dt[1][l]) + 0.0f;
        out->g[2][l] = cq * c.q[2][l] + ct * (m[l] * r->dt[2][l]) + 0.0f;
    }
}

/* F_b of each lane from its closest point into F, and the factor cg of
 * its gradient ∇F_b = cg·q into cg. The scalar code's branches (beyond
 * r_out: 0; s ≤ 0: 1; s ≥ 1: 0) as selects and a clamp of s to [0, 1],
 * which gives the same values there. */
VECTORIZE INLINE static void bound_lanes(const merp_row *r, const merp_row_point *c, float F[MERP_ROW],
                                         float cg[MERP_ROW])
{
    /* Most samples of a patch lie beyond every bound's support: then F_b is
     * 0 in each lane, and neither square roots nor the rest are needed. */
    int any = 0;
    for (int l = 0; l < MERP_ROW; l++)
        any |= c->d2[l] < r->rb2[l];
    if (!any) {
        for (int l = 0; l < MERP_ROW; l++)
            F[l] = cg[l] = 0.0f;
        return;
    }
    float s[MERP_ROW], den[MERP_ROW], in[MERP_ROW], dist[MERP_ROW];
    /* Scalar: sqrtf sets errno, so GCC keeps a branch per call (an
     * optimize attribute does not lift that) and the loop would not
     * vectorize. */
    for (int l = 0; l < MERP_ROW; l++)
        dist[l] = c->d2[l] < r->rb2[l] ? sqrtf(c->d2[l]) : 0.0f;
    for (int l = 0; l < MERP_ROW; l++) {
        float r_in = r->ra[l], d2 = c->d2[l];
        float d = dist[l], span = r->span[l], sn = (d - r_in) / span;
        sn = sn > 0.0f ? sn : 0.0f;
        s[l] = sn < 1.0f ? sn : 1.0f;
        in[l] = d2 < r->rb2[l] ? 1.0f : 0.0f;
        den[l] = d > 0.0f ? d * span : 1.0f; /* d = 0 only where s = 0 or out */
    }
    /* Apart from the loop above: as one, the selects become branches. */
    for (int l = 0; l < MERP_ROW; l++) {
        float w = 1.0f - s[l] * s[l], u = w * w;
        F[l] = in[l] != 0.0f ? u * u * u : 0.0f; /* ((1 − r)²)³ with r = s² */
        /* dF/ds = −12 s (1 − s²)⁵, ∇s = q / (d · span) */
        cg[l] = in[l] != 0.0f ? -12.0f * s[l] * w * w * w * w * w / den[l] : 0.0f;
    }
}

VECTORIZE void merp_row_bound_field(const merp_row *r, const float p[3], float F[MERP_ROW])
{
    merp_row_point c;
    float cg[MERP_ROW];
    closest(r, p, &c);
    bound_lanes(r, &c, F, cg);
}

VECTORIZE void merp_row_bound_gradient(const merp_row *r, const float p[3], merp_row_grad *out)
{
    merp_row_point c;
    float cg[MERP_ROW];
    closest(r, p, &c);
    bound_lanes(r, &c, out->f, cg);
    for (int l = 0; l < MERP_ROW; l++) {
        /* + 0: a zero gradient is +0, as the scalar code's returns give. */
        out->g[0][l] = cg[l] * c.q[0][l] + 0.0f;
        out->g[1][l] = cg[l] * c.q[1][l] + 0.0f;
        out->g[2][l] = cg[l] * c.q[2][l] + 0.0f;
    }
}
