/* meristem — phyllotaxis of lateral branches (G04 §4.3): each metamer's lateral
 * 137.5° from the one before, and the rule that a shoot's two longest laterals
 * lie at least 40° from the longest lateral of the shoot before it.
 *
 * The longest laterals of a shoot are those nearest its tip (G04 §2.2; G_ss is
 * drawn so), its last two metamers; the spiral runs on from shoot to shoot, so
 * with m metamers they sit 137.5° · m and 137.5° · (m − 1) from the previous
 * shoot's last. A shoot of one metamer has one lateral to check. */
#include "config.h"

#include <assert.h>
#include <math.h>

#include "models/inverse/inverse.h"

float merp_inv_angle_apart(float a, float b)
{
    float d = fmodf(fabsf(a - b), 360.0f);
    return d > 180.0f ? 360.0f - d : d;
}

int merp_inv_count_ok(uint32_t m)
{
    assert(m >= 1);
    if (merp_inv_angle_apart(MERP_INV_DIVERGENCE * (float)m, 0.0f) < MERP_INV_APART)
        return 0;
    return m == 1 ||
           merp_inv_angle_apart(MERP_INV_DIVERGENCE * (float)(m - 1), 0.0f) >= MERP_INV_APART;
}

uint32_t merp_inv_phyllo_count(uint32_t m, uint32_t m_max)
{
    assert(m >= 1 && m_max >= 1);
    for (uint32_t k = 0; k <= m_max; k++) {
        if (m > k && m - k <= m_max && merp_inv_count_ok(m - k))
            return m - k;
        if (m + k <= m_max && merp_inv_count_ok(m + k))
            return m + k;
    }
    return m;
}
