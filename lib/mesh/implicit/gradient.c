/* meristem — ∇F_g of a junction in closed form (implicit.h): the normals of a
 * patch from one pass over the primitives, where central differences took six
 * evaluations of the field. Mirrors junction.c's terms operation for
 * operation, each value carried with its gradient (forward-mode
 * differentiation by hand). */
#include "config.h"

#include <assert.h>
#include <math.h>

#include "core/vec.h"
#include "mesh/implicit/implicit.h"

typedef struct dual {
    float v, g[3];
} dual;

static const dual ZERO = {0.0f, {0.0f, 0.0f, 0.0f}};

static inline dual d_lin(float a, dual x, float b, dual y) /* a·x + b·y */
{
    return (dual){a * x.v + b * y.v, {a * x.g[0] + b * y.g[0], a * x.g[1] + b * y.g[1], a * x.g[2] + b * y.g[2]}};
}

static inline dual d_max(dual a, dual b) /* b when b > a, as junction.c's maxima */
{
    return b.v > a.v ? b : a;
}

/* The closest point's offset q = p − s(t) and its parameter t. */
static inline float closest(const float a[3], const float b[3], const float p[3], float q[3])
{
    float ab[3], ap[3];
    for (int k = 0; k < 3; k++)
        ab[k] = b[k] - a[k], ap[k] = p[k] - a[k];
    float len2 = v3_dot(ab, ab), u = 0.0f;
    if (len2 > 0.0f) {
        u = v3_dot(ap, ab) / len2;
        u = u < 0.0f ? 0.0f : u > 1.0f ? 1.0f : u;
    }
    for (int k = 0; k < 3; k++)
        q[k] = ap[k] - u * ab[k];
    return u;
}

/* ∂t/∂p of closest's t: zero where t is clamped to an end. Asked only
 * inside a field's support, as most points of a patch lie outside most
 * primitives'. */
static inline void closest_dt(const float a[3], const float b[3], float t, float dt[3])
{
    float ab[3];
    for (int k = 0; k < 3; k++)
        ab[k] = b[k] - a[k], dt[k] = 0.0f;
    float len2 = v3_dot(ab, ab);
    if (len2 > 0.0f && t > 0.0f && t < 1.0f)
        for (int k = 0; k < 3; k++)
            dt[k] = ab[k] / len2;
}

/* merp_seg_field with its gradient: f = (1 − x²)³, x² = d² / R(t)². */
static inline dual seg(const merp_seg *s, const float p[3])
{
    float q[3], dt[3] = {0.0f, 0.0f, 0.0f};
    float t = closest(s->a, s->b, p, q), d2 = v3_dot(q, q);
    float R = ((1.0f - t) * s->ra + t * s->rb) / MERP_SEG_XC, R2 = R * R, x2 = d2 / R2;
    if (x2 >= 1.0f)
        return ZERO;
    float u = 1.0f - x2, dR = (s->rb - s->ra) / MERP_SEG_XC;
    if (dR != 0.0f) /* ∇R = dR ∇t: only a tapered segment's radius moves */
        closest_dt(s->a, s->b, t, dt);
    /* ∇f = −3u² ∇x², ∇x² = 2q / R² − 2d² ∇R / R³: two factors, a division each. */
    float cq = -6.0f * u * u / R2, ct = 6.0f * u * u * d2 * dR / (R2 * R);
    dual f = {u * u * u, {0, 0, 0}};
    for (int k = 0; k < 3; k++)
        f.g[k] = cq * q[k] + ct * dt[k];
    return f;
}

/* merp_bound_field with its gradient: ((1 − s²)²)³ of s = (d − r_in)/(r_out − r_in). */
static inline dual bound(const merp_bound *b, const float p[3])
{
    float q[3];
    closest(b->a, b->b, p, q);
    float d2 = v3_dot(q, q);
    if (d2 >= b->r_out * b->r_out)
        return ZERO;
    float d = sqrtf(d2), span = b->r_out - b->r_in, sn = (d - b->r_in) / span;
    if (sn <= 0.0f)
        return (dual){1.0f, {0, 0, 0}};
    if (sn >= 1.0f)
        return ZERO;
    float r = sn * sn, u = (1.0f - r) * (1.0f - r), w = 1.0f - r;
    /* dF/ds = −12 s (1 − s²)⁵, ∇s = q / (d · span) */
    float c = -12.0f * sn * w * w * w * w * w / (d * span);
    dual f = {u * u * u, {0, 0, 0}};
    for (int k = 0; k < 3; k++)
        f.g[k] = c * q[k];
    return f;
}

/* Δ(c − x) of PCM (merp_pcm_delta) with its gradient. */
static inline dual delta_of(dual x, float w)
{
    float y = MERP_ISO - x.v;
    if (y < 0.0f)
        return (dual){y, {-x.g[0], -x.g[1], -x.g[2]}};
    if (y > w)
        return ZERO;
    float u = 1.0f - y / w, slope = u * u - 2.0f * y * u / w;
    return (dual){y * u * u, {-slope * x.g[0], -slope * x.g[1], -slope * x.g[2]}};
}

/* F_b·b1 + (1 − F_b)·b2 with the product rule (eq. 4). */
static inline dual gbb(dual F, dual b1, dual b2)
{
    dual r = {merp_gbb(F.v, b1.v, b2.v), {0, 0, 0}};
    for (int k = 0; k < 3; k++)
        r.g[k] = F.g[k] * (b1.v - b2.v) + F.v * b1.g[k] + (1.0f - F.v) * b2.g[k];
    return r;
}

/* The parent's axis A = max(in, out), with the scar's bounded blend. */
static inline dual axis(const merp_junction *j, const float p[3])
{
    dual f_in = seg(&j->in, p), A = f_in, f_out = ZERO;
    if (j->out.ra > 0.0f) {
        f_out = seg(&j->out, p);
        A = d_max(A, f_out);
    }
    if (j->scar_weight > 0.0f && j->out.ra > 0.0f) {
        dual F_s = d_lin(j->scar_weight, bound(&j->scar, p), 0.0f, ZERO);
        if (F_s.v > 0.0f) {
            dual a = d_lin(1.0f, f_in, 1.0f, delta_of(f_out, MERP_ISO));
            dual b = d_lin(1.0f, f_out, 1.0f, delta_of(f_in, MERP_ISO));
            A = gbb(F_s, a.v > b.v ? a : b, A);
        }
    }
    return A;
}

float merp_junction_gradient(const merp_junction *j, const float p[3], float g[3])
{
    assert(j->laterals >= 1 && j->laterals <= MERP_JUNCTION_LATERALS);
    dual A = axis(j, p), L[MERP_JUNCTION_LATERALS];
    dual A_d = A, b1 = ZERO, b2 = A, F_b = ZERO;
    for (uint32_t k = 0; k < j->laterals; k++) {
        L[k] = seg(&j->lateral[k], p);
        b2 = d_lin(1.0f, b2, 1.0f, L[k]);
        A_d = d_lin(1.0f, A_d, 1.0f, delta_of(L[k], j->w));
    }
    for (uint32_t k = 0; k < j->laterals; k++)
        b1 = d_max(b1, d_lin(1.0f, L[k], 1.0f, delta_of(A, j->w)));
    b1 = d_max(b1, A_d);
    for (uint32_t k = 0; k < j->laterals; k++)
        if (j->bound[k].r_out > 1e-5f)
            F_b = d_max(F_b, bound(&j->bound[k], p));
    dual F = gbb(F_b, b1, b2);
    for (int k = 0; k < 3; k++)
        g[k] = F.g[k];
    return F.v;
}
