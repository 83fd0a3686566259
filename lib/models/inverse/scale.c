/* meristem — the branch scale factor s_b (G04 §4.1 eq (10), §4.2 eq (13), §4.3
 * eq (15)): s_b = G_ss(x_s) · s_bp · G_bs(x_max). It scales the branch's length,
 * sets its lifespan (eq (11)) and passes on to its laterals; below s_min no
 * lateral is made (§4.2). */
#include "config.h"

#include <assert.h>

#include "models/inverse/inverse.h"

float merp_inv_scale(const merp_gfunc *gbs, float x_max, float s_bp, const merp_gfunc *gss,
                     float x_s)
{
    assert(gbs != NULL);
    float s = s_bp * merp_gfunc_eval(gbs, x_max);
    if (gss != NULL)
        s *= merp_gfunc_eval(gss, x_s);
    return s > 0.0f ? s : 0.0f;
}
