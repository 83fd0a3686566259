/* meristem — how long a branch lives (G04 §4.1 eq (11)): a = G_a(s_b). By the
 * scale factor rather than the length, so that short branches of high order may
 * outlive longer ones of lower order, as G04 observes. s_b is clamped to G_a's
 * domain [0, 1]. */
#include "config.h"

#include <assert.h>

#include "models/inverse/inverse.h"

float merp_inv_lifespan(const merp_gfunc *ga, float s_b, float a_max)
{
    assert(ga != NULL);
    float a = a_max * merp_gfunc_eval(ga, s_b);
    return a > 0.0f ? a : 0.0f;
}

int merp_inv_alive_at(float a, uint32_t born, double t)
{
    return t - (double)born < (double)a;
}
