/* meristem — the structure of a shoot (G04 §4.3): m = G_m(l_s / l_smax) metamers
 * of equal length l_s / m (eq (14)), a leaf on each sized by G_l(x_s).
 *
 * G04 leaves G_m's unit open; here G_m gives a fraction of m_max, rounded to the
 * nearest count, at least one metamer (a shoot of length l_min still has one). */
#include "config.h"

#include <assert.h>
#include <math.h>

#include "models/inverse/inverse.h"

uint32_t merp_inv_metamers(const merp_gfunc *gm, float l_s, float ls_max, uint32_t m_max)
{
    assert(gm != NULL && m_max >= 1);
    float q = ls_max > 0.0f ? l_s / ls_max : 1.0f;
    float m = roundf((float)m_max * merp_gfunc_eval(gm, q));
    if (!(m >= 1.0f))
        return 1;
    return m > (float)m_max ? m_max : (uint32_t)m;
}

float merp_inv_leaf_size(const merp_gfunc *gl, float x_s, float leaf_size)
{
    assert(gl != NULL);
    float s = leaf_size * merp_gfunc_eval(gl, x_s);
    return s > 0.0f ? s : 0.0f;
}

float merp_inv_x_s(uint32_t j, uint32_t m)
{
    assert(m >= 1 && j < m);
    return (float)(j + 1) / (float)m;
}
