/* meristem — the radius of a branch as a function of position along it (G04
 * §4.1: "the radius of a branch is defined as a function of position along the
 * branch"). G04 gives no unit for it; here a branch's base radius grows with its
 * current length, r_b = r_max · L / h_max (the trunk has r_max at the base once
 * it is h_max long), and is no more than its parent's radius where it leaves it,
 * so that a branch never outgrows its support; G_r(x) then shapes it from base
 * (x = 0) to tip (x = 1). */
#include "config.h"

#include <assert.h>

#include "models/inverse/inverse.h"

float merp_inv_base_radius(const merp_inv_def *d, float length, float cap)
{
    assert(d != NULL && length >= 0.0f);
    float r = d->r_max * length / d->h_max;
    return cap >= 0.0f && r > cap ? cap : r;
}

float merp_inv_radius(const merp_gfunc *gr, float x, float r_base)
{
    assert(gr != NULL);
    float g = merp_gfunc_eval(gr, x);
    return g > 0.0f ? r_base * g : 0.0f;
}

mer_result merp_inv_radius_default(merp_gfunc *gr, mer_error *err)
{
    /* A taper that thins a little faster near the tip, as a pipe model would. */
    static const float taper[4][2] = {{0.0f, 1.0f}, {0.4f, 0.7f}, {0.8f, 0.35f}, {1.0f, 0.1f}};
    return merp_gfunc_make(gr, "G_r", MERP_GF_BSPLINE, 64, taper, 4, err);
}
