/* meristem — the heading of each growth increment (G04 §4.1, eqs (8)–(9)), and
 * the branching angle.
 *
 * G04 measures θ from the branch's original heading but does not give that
 * heading itself; its §2.2 observes branching angles of about 80° for short
 * shoots and 35° for long ones. The original heading here leaves the parent at
 * the angle interpolated between the two by eq (8)'s s_θ, as eq (9) interpolates
 * G_o1 and G_o2: a branch's angle narrows as it lengthens. */
#include "config.h"

#include <assert.h>
#include <math.h>

#include "core/vec.h"
#include "models/inverse/inverse.h"

float merp_inv_s_theta(float l_y, float l_max)
{
    if (!(l_max > 0.0f) || !(l_y > 0.0f))
        return 0.0f;
    float s = l_y / l_max;
    return s > 1.0f ? 1.0f : s;
}

float merp_inv_heading(const merp_gfunc *go1, const merp_gfunc *go2, float s_theta, float x_y,
                       float theta_max)
{
    assert(go1 != NULL && go2 != NULL);
    return theta_max *
           ((1.0f - s_theta) * merp_gfunc_eval(go1, x_y) + s_theta * merp_gfunc_eval(go2, x_y));
}

float merp_inv_branch_angle(const merp_inv_def *d, float s_theta)
{
    assert(d != NULL);
    return (1.0f - s_theta) * d->beta_short + s_theta * d->beta_long;
}

void merp_inv_orient(const float h0[3], const float dp[3], float theta, float out[3])
{
    assert(h0 != NULL && dp != NULL && out != NULL);
    /* u: the unit direction towards dp in the plane of h0 and dp; rotating h0
     * by θ in that plane is cos θ · h0 + sin θ · u. */
    float c = v3_dot(h0, dp), u[3];
    for (int a = 0; a < 3; a++)
        u[a] = dp[a] - c * h0[a];
    if (!v3_normalize(u)) {
        for (int a = 0; a < 3; a++)
            out[a] = h0[a];
        return;
    }
    float to_dp = acosf(c < -1.0f ? -1.0f : c > 1.0f ? 1.0f : c) / MER_DEG2RAD;
    if (theta > to_dp)
        theta = to_dp;
    if (theta < to_dp - 180.0f)
        theta = to_dp - 180.0f;
    float r = theta * MER_DEG2RAD, cs = cosf(r), sn = sinf(r);
    for (int a = 0; a < 3; a++)
        out[a] = cs * h0[a] + sn * u[a];
    v3_normalize(out);
}
