/* meristem — branch length by year (G04 §4.1, eqs (5)–(7)): the trunk after G_h,
 * order-1 and higher branches between the young and the mature silhouette. */
#include "config.h"

#include <assert.h>

#include "models/inverse/inverse.h"

float merp_inv_time(uint32_t y, uint32_t y_max)
{
    assert(y_max > 0);
    return (float)y / (float)y_max;
}

float merp_inv_silhouette(const merp_gfunc *gs1, const merp_gfunc *gs2, float t_y, float x_y,
                          float l_py)
{
    assert(gs1 != NULL && gs2 != NULL);
    return l_py * ((1.0f - t_y) * merp_gfunc_eval(gs1, x_y) + t_y * merp_gfunc_eval(gs2, x_y));
}

float merp_inv_enforce_min(float l_dy, float l_prev, float l_min)
{
    float least = l_prev + l_min;
    return l_dy > least ? l_dy : least;
}

void merp_inv_trunk_lengths(const merp_inv_def *d, float *l)
{
    assert(d != NULL && l != NULL);
    float prev = 0.0f;
    for (uint32_t y = 0; y <= d->y_max; y++) {
        float t = merp_inv_time(y, d->y_max);
        prev = l[y] = merp_inv_enforce_min(d->h_max * merp_gfunc_eval(&d->g[MERP_G_H], t), prev,
                                           d->l_min);
    }
}

/* Eq (7) runs on the lengths before s_b and eq (12) scale them: eq (12) divides
 * the whole max(l_dy, l_{y−1} + l_min), which only keeps lengths growing when
 * l_{y−1} there is the unscaled length of the year before. */
void merp_inv_branch_lengths(const merp_inv_def *d, const float *lp, float x, uint32_t y_c,
                             uint32_t order, float s_b, float *l)
{
    assert(d != NULL && lp != NULL && l != NULL && order >= 1);
    float k = s_b * merp_inv_order_scale(order), u = 0.0f;
    for (uint32_t y = 0; y <= d->y_max; y++) {
        if (y < y_c) {
            l[y] = 0.0f;
            continue;
        }
        float x_y = lp[y] > 0.0f ? x / lp[y] : 1.0f;
        float l_dy = merp_inv_silhouette(&d->g[MERP_G_S1], &d->g[MERP_G_S2],
                                         merp_inv_time(y, d->y_max), x_y, lp[y]);
        u = merp_inv_enforce_min(l_dy, u, d->l_min);
        l[y] = k * u;
    }
}
