/* meristem — ∇F_g of a junction in closed form (implicit.h): the normals of a
 * patch from one pass over the primitives, where central differences took six
 * evaluations of the field. Mirrors junction.c's terms operation for
 * operation, each value carried with its gradient (forward-mode
 * differentiation by hand); the primitives' own gradients come 4-wide from
 * row.c. */
#include "config.h"

#include <assert.h>

#include "mesh/implicit/implicit.h"

/* Every term's function forced inline into field_with (see junction.c). */
#if defined(__GNUC__)
#define INLINE __attribute__((always_inline)) inline
#else
#define INLINE inline
#endif

typedef struct dual {
    float v, g[3];
} dual;

static const dual ZERO = {0.0f, {0.0f, 0.0f, 0.0f}};

static inline dual d_lin(float a, dual x, float b, dual y) /* a·x + b·y */
{
    return (dual){a * x.v + b * y.v,
                  {a * x.g[0] + b * y.g[0], a * x.g[1] + b * y.g[1], a * x.g[2] + b * y.g[2]}};
}

static inline dual d_max(dual a, dual b) /* b when b > a, as junction.c's maxima */
{
    return b.v > a.v ? b : a;
}

/* Lane l of a row's values and gradients as a dual number. */
static inline dual lane(const merp_row_grad *r, int l)
{
    return (dual){r->f[l], {r->g[0][l], r->g[1][l], r->g[2][l]}};
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

/* Lane l of rows r as a dual number. */
static inline dual lane_of(const merp_row_grad *r, uint32_t l)
{
    return lane(r + l / MERP_ROW, (int)(l % MERP_ROW));
}

/* Group g's axis A folded up its forks (junction.c's axis_terms), with
 * each fork's scar's bounded blend, from the segments' and bounds' lanes. */
static INLINE dual axis(const merp_jprep *jp, const merp_jlanes *L, uint32_t g, const merp_row_grad *seg,
                        const merp_row_grad *bnd)
{
    uint32_t first = L->group_first[g], end = L->group_first[g + 1];
    dual A = lane_of(seg, L->in_lane[first]);
    for (uint32_t i = first; i < end; i++) {
        const merp_junction *j = &jp->j[i];
        if (!(j->out.ra > 0.0f))
            continue; /* a fork with no continuation: its lane is 0 */
        dual f_in = A, f_out = lane_of(seg, L->out_lane[i]);
        A = d_max(f_in, f_out);
        if (j->scar_weight > 0.0f) {
            dual F_s = d_lin(j->scar_weight, lane_of(bnd, i), 0.0f, ZERO);
            if (F_s.v > 0.0f) {
                dual a = d_lin(1.0f, f_in, 1.0f, delta_of(f_out, MERP_ISO));
                dual b = d_lin(1.0f, f_out, 1.0f, delta_of(f_in, MERP_ISO));
                A = gbb(F_s, a.v > b.v ? a : b, A);
            }
        }
    }
    return A;
}

/* Lateral k of fork i: its segment's lane, or the group's up it (Fg). */
static INLINE dual lateral_of(const merp_jlanes *L, uint32_t i, uint32_t k, const merp_row_grad *seg,
                              const dual *Fg)
{
    uint32_t c = L->child[i][k];
    return c != 0 ? Fg[c] : lane_of(seg, L->lat_lane[i][k]);
}

/* Group g's field and gradient (junction.c's group_field). */
static INLINE dual group_field(const merp_jprep *jp, const merp_jlanes *L, uint32_t g, const merp_row_grad *seg,
                               const merp_row_grad *bnd, const dual *Fg)
{
    uint32_t first = L->group_first[g], end = L->group_first[g + 1];
    dual A = axis(jp, L, g, seg, bnd), A_d = A, b1 = ZERO, b2 = A, F_b = ZERO;
    for (uint32_t i = first; i < end; i++)
        for (uint32_t k = 0; k < jp->j[i].laterals; k++) {
            b2 = d_lin(1.0f, b2, 1.0f, lateral_of(L, i, k, seg, Fg));
            if (jp->j[i].bound[k].r_out > 1e-5f)
                F_b = d_max(F_b, lane_of(bnd, L->bnd_lane[i][k]));
        }
    /* Beyond the ridge (most samples) F_b and ∇F_b are 0 and eq. (4) is B2:
     * exactly, as no component of B2's gradient is −0 (each lane's is +0
     * where it is zero), so 0·x + 1·B2 is B2 to the bit. */
    if (F_b.v == 0.0f)
        return b2;
    for (uint32_t i = first; i < end; i++)
        for (uint32_t k = 0; k < jp->j[i].laterals; k++)
            A_d = d_lin(1.0f, A_d, 1.0f, delta_of(lateral_of(L, i, k, seg, Fg), jp->j[i].w));
    for (uint32_t i = first; i < end; i++)
        for (uint32_t k = 0; k < jp->j[i].laterals; k++)
            b1 = d_max(b1, d_lin(1.0f, lateral_of(L, i, k, seg, Fg), 1.0f, delta_of(A, jp->j[i].w)));
    b1 = d_max(b1, A_d);
    return gbb(F_b, b1, b2);
}

/* The run's field and gradient from its lanes where L says (jp's own, or
 * a single fork's constants, whose lookups the compiler folds away). */
static INLINE dual field_with(const merp_jprep *jp, const merp_jlanes *L, const merp_row_grad *seg,
                              const merp_row_grad *bnd)
{
    dual Fg[MERP_RUN_FORKS] = {{0}}; /* each group's written before it is read */
    for (uint32_t k = L->groups; k-- > 1;)
        Fg[k] = group_field(jp, L, k, seg, bnd, Fg);
    return group_field(jp, L, 0, seg, bnd, Fg);
}

float merp_jprep_gradient(const merp_jprep *jp, const float p[3], float g[3])
{
    float F[MERP_JROWS * MERP_ROW];
    return merp_jprep_gradient_bounds(jp, p, g, F);
}

float merp_jprep_gradient_bounds(const merp_jprep *jp, const float p[3], float g[3], float *bounds)
{
    merp_row_grad seg[MERP_JROWS], bnd[MERP_JROWS];
    for (uint32_t r = 0; r < jp->rows; r++) {
        if (merp_jprep_beyond_row(jp, r, p))
            memset(&seg[r], 0, sizeof seg[r]); /* +0, as the lanes give */
        else
            merp_row_seg_gradient(&jp->seg[r], p, &seg[r]);
    }
    merp_jprep_bound_gradient(jp, p, bnd);
    for (uint32_t r = 0; r < jp->rows; r++)
        memcpy(bounds + MERP_ROW * r, bnd[r].f, sizeof bnd[r].f);
    dual F = jp->forks == 1 ? field_with(jp, &MERP_JLANES_SINGLE, seg, bnd) : field_with(jp, &jp->lanes, seg, bnd);
    for (int k = 0; k < 3; k++)
        g[k] = F.g[k];
    return F.v;
}

float merp_junction_gradient(const merp_junction *j, const float p[3], float g[3])
{
    merp_jprep jp;
    merp_jprep_init(&jp, j);
    return merp_jprep_gradient(&jp, p, g);
}
