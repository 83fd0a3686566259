/* meristem — guiding vectors and edge costs after Xu & Mould 2015 (guiding.h):
 * a node's guiding vector is its parent's turned by the increment δ(h) about the
 * axis perpendicular to up and to the edge it was reached by, and an edge costs
 * little when it follows the guiding vector of the node it leaves. */
#include "config.h"

#include <assert.h>
#include <math.h>

#include "core/vec.h"
#include "models/guiding/guiding.h"

merp_gv_guide merp_gv_guide_of(const mer_params *p)
{
    assert(p != NULL);
    return (merp_gv_guide){.on = 1,
                           .rotation = p->gv_rotation * MER_DEG2RAD,
                           .falloff = p->gv_rotation_falloff,
                           .eps = p->gv_epsilon,
                           .p = p->gv_p};
}

void merp_gv_turn(const merp_gv_guide *gd, const float parent[3], const float e[3], uint32_t hop,
                  float out[3])
{
    assert(gd != NULL && parent != NULL && e != NULL && out != NULL && hop >= 1);
    static const float up[3] = {0.0f, 1.0f, 0.0f};
    float axis[3];
    v3_cross(up, e, axis);
    float delta = gd->rotation * powf(gd->falloff, (float)(hop - 1));
    /* Rotating by +δ about up × e turns up towards e: the field leans outwards
     * along the way the path went. An edge along up leaves it as it is. */
    if (!v3_normalize(axis) || delta == 0.0f) {
        out[0] = parent[0];
        out[1] = parent[1];
        out[2] = parent[2];
        return;
    }
    v3_rotate(parent, axis, delta, out);
    v3_normalize(out);
}

double merp_gv_cost(const merp_gv_guide *gd, const float g[3], const float e[3])
{
    assert(gd != NULL && g != NULL && e != NULL);
    double ex = (double)e[0], ey = (double)e[1], ez = (double)e[2];
    double len = sqrt(ex * ex + ey * ey + ez * ez);
    if (!gd->on)
        return len;
    double c = ((double)g[0] * ex + (double)g[1] * ey + (double)g[2] * ez) / len;
    double base = (double)gd->eps + (1.0 - c) / 2.0;
    return len * pow(base, (double)gd->p);
}
