/* meristem — the field of a branch junction: blend, PCM and generalized
 * bounded blending combined as G04 §3.2 does for the branch bark ridge
 * (implicit.h). */
#include "config.h"

#include <assert.h>
#include <math.h>

#include "core/vec.h"
#include "mesh/implicit/implicit.h"

void merp_junction_bound(merp_junction *j, uint32_t k, const float up[3], float ridge)
{
    assert(k < j->laterals);
    const merp_seg *l = &j->lateral[k];
    float d[3], e[3];
    for (int a = 0; a < 3; a++)
        d[a] = l->b[a] - l->a[a];
    v3_normalize(d);
    /* e: the side the lateral leaves towards, across the parent's axis. */
    float cos_t = v3_dot(d, up);
    for (int a = 0; a < 3; a++)
        e[a] = d[a] - cos_t * up[a];
    if (!v3_normalize(e))
        v3_any_perp(up, e);
    /* The crotch C, in the plane (e, up): where the parent's surface x = r_P
     * meets the lateral's upper line J + t·d + r_L·n, n = (−cos θ, sin θ):
     * t = (r_P + r_L cos θ) / sin θ, θ ≥ 10° (a lateral along its parent has
     * no crotch to speak of). */
    float sin_t = sqrtf(fmaxf(0.0f, 1.0f - cos_t * cos_t));
    cos_t = fminf(cos_t, 0.985f), sin_t = fmaxf(sin_t, 0.17f);
    float r_P = j->in.rb, r_L = l->ra, t = (r_P + r_L * cos_t) / sin_t;
    float x = t * sin_t - r_L * cos_t, y = t * cos_t + r_L * sin_t;
    float g = ridge < 0.0f ? 0.0f : ridge > 1.0f ? 1.0f : ridge;
    merp_bound *b = &j->bound[k];
    for (int a = 0; a < 3; a++) {
        b->a[a] = l->a[a] + x * e[a] + y * up[a];
        b->b[a] = b->a[a] + 0.5f * r_L * g * d[a];
    }
    b->r_in = 0.4f * r_L * g;
    b->r_out = b->r_in + 0.8f * r_L * g + 1e-6f;
}

float merp_junction_ridge(const merp_junction *j, const float p[3])
{
    float F_b = 0.0f;
    for (uint32_t k = 0; k < j->laterals; k++) {
        if (j->bound[k].r_out <= 1e-5f)
            continue;
        float v = merp_bound_field(&j->bound[k], p);
        F_b = v > F_b ? v : F_b;
    }
    return F_b;
}

float merp_junction_field(const float p[3], const void *data)
{
    const merp_junction *j = data;
    assert(j->laterals >= 1 && j->laterals <= MERP_JUNCTION_LATERALS);
    float A = merp_seg_field(&j->in, p);
    if (j->out.ra > 0.0f) {
        float f_out = merp_seg_field(&j->out, p);
        A = f_out > A ? f_out : A;
    }
    float L[MERP_JUNCTION_LATERALS], f[1 + MERP_JUNCTION_LATERALS] = {A};
    float A_d = A, b1 = 0.0f;
    for (uint32_t k = 0; k < j->laterals; k++) {
        L[k] = merp_seg_field(&j->lateral[k], p);
        f[1 + k] = L[k];
        A_d += merp_pcm_delta(MERP_ISO - L[k], j->w);
    }
    for (uint32_t k = 0; k < j->laterals; k++) {
        float L_d = L[k] + merp_pcm_delta(MERP_ISO - A, j->w);
        b1 = L_d > b1 ? L_d : b1;
    }
    b1 = A_d > b1 ? A_d : b1;
    float b2 = merp_blend_sum(f, 1 + j->laterals);
    return merp_gbb(merp_junction_ridge(j, p), b1, b2);
}
