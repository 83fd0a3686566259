/* meristem — the tapered-capsule primitive of an internode (implicit.h). */
#include "config.h"

#include <assert.h>
#include <math.h>
#include <stddef.h>

#include "core/vec.h"
#include "mesh/implicit/implicit.h"

float merp_seg_xc(void)
{
    return MERP_SEG_XC;
}

float merp_seg_distance2(const merp_seg *s, const float p[3], float *t)
{
    float u;
    float d2 = merp_seg_d2(s, p, &u);
    if (t != NULL)
        *t = u;
    return d2;
}

float merp_seg_distance(const merp_seg *s, const float p[3], float *t)
{
    return sqrtf(merp_seg_distance2(s, p, t));
}

float merp_seg_support(const merp_seg *s)
{
    return (s->ra > s->rb ? s->ra : s->rb) / MERP_SEG_XC;
}
