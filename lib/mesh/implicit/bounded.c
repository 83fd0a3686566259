/* meristem — the bounding field F_b of generalized bounded blending (G04 §3.1);
 * eq. (4) itself is merp_gbb in implicit.h. */
#include "config.h"

#include <assert.h>
#include <math.h>
#include <stddef.h>

#include "mesh/implicit/implicit.h"

float merp_bound_field(const merp_bound *bnd, const float p[3])
{
    assert(bnd->r_in >= 0.0f && bnd->r_out > bnd->r_in);
    merp_seg s = {{bnd->a[0], bnd->a[1], bnd->a[2]}, {bnd->b[0], bnd->b[1], bnd->b[2]}, 1.0f, 1.0f};
    float t;
    float d2 = merp_seg_d2(&s, p, &t);
    if (d2 >= bnd->r_out * bnd->r_out)
        return 0.0f; /* beyond the support: most points, no square root */
    float sn = (sqrtf(d2) - bnd->r_in) / (bnd->r_out - bnd->r_in);
    if (sn <= 0.0f)
        return 1.0f;
    if (sn >= 1.0f)
        return 0.0f;
    float r = sn * sn;
    float u = (1.0f - r) * (1.0f - r);
    return u * u * u; /* ((1 − r)²)³ */
}
