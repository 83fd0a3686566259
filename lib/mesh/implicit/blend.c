/* meristem — summation blending, B2 of G04 §3.1 (implicit.h). */
#include "config.h"

#include "mesh/implicit/implicit.h"

float merp_blend_sum(const float *f, uint32_t n)
{
    float s = 0.0f;
    for (uint32_t i = 0; i < n; i++)
        s += f[i];
    return s;
}
