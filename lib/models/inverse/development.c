/* meristem — continuous development within a year (G04 §4.3 after Mündermann's
 * thesis, Figs. 12–13): every metamer of a shoot follows the same growth curves
 * (internode elongation G_e, leaf growth G_lg, bud growth G_bg), each offset in
 * time from the one below it, so a shoot unfolds from its base to its tip.
 *
 * G04 does not give the offsets. Here the j-th of m metamers starts at
 * span · j / m of the year and grows for 1 − span of it, so the shoot is whole
 * at the year's end and the tree at year y + 1 follows the tree at year y with
 * no jump. */
#include "config.h"

#include <assert.h>

#include "models/inverse/inverse.h"

float merp_inv_metamer_start(uint32_t j, uint32_t m, float span)
{
    assert(m >= 1 && j < m && span >= 0.0f && span < 1.0f);
    return span * (float)j / (float)m;
}

float merp_inv_growth(const merp_gfunc *g, float f, uint32_t j, uint32_t m, float span)
{
    assert(g != NULL);
    float start = merp_inv_metamer_start(j, m, span);
    float u = (f - start) / (1.0f - span);
    if (!(u > 0.0f))
        return 0.0f;
    if (u >= 1.0f)
        return 1.0f;
    float v = merp_gfunc_eval(g, u);
    return v < 0.0f ? 0.0f : v > 1.0f ? 1.0f : v;
}
