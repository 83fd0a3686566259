/* meristem — precise contact modeling, B1 of the branch bark ridge (G04 §3,
 * after Gascuel 1993 and Desbrun & Cani-Gascuel 1998); the formulation is in
 * implicit.h. */
#include "config.h"

#include <assert.h>

#include "mesh/implicit/implicit.h"

void merp_pcm_pair(float f1, float f2, float w, float *f1d, float *f2d)
{
    *f1d = f1 + merp_pcm_delta(MERP_ISO - f2, w);
    *f2d = f2 + merp_pcm_delta(MERP_ISO - f1, w);
}

float merp_pcm_union(float f1, float f2, float w)
{
    float a, b;
    merp_pcm_pair(f1, f2, w, &a, &b);
    return a > b ? a : b;
}
