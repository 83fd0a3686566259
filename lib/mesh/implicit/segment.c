/* meristem — the tapered-capsule primitive of an internode (implicit.h). */
#include "config.h"

#include <assert.h>
#include <math.h>
#include <stddef.h>

#include "core/vec.h"
#include "mesh/implicit/implicit.h"

/* x_c = sqrt(1 − c^(1/3)) for c = 1/2: g(x_c) = (1 − x_c²)³ = c. A constant,
 * since every field evaluation divides by it (test_implicit checks the iso). */
#define XC 0.45420201894740647f

float merp_seg_xc(void)
{
    return XC;
}

/* The squared distance from p to s and the parameter of the closest point:
 * the fields need d² only, so no square root. */
static float seg_distance2(const merp_seg *s, const float p[3], float *t)
{
    float ab[3], ap[3];
    for (int k = 0; k < 3; k++) {
        ab[k] = s->b[k] - s->a[k];
        ap[k] = p[k] - s->a[k];
    }
    float len2 = v3_dot(ab, ab), u = 0.0f;
    if (len2 > 0.0f) {
        u = v3_dot(ap, ab) / len2;
        u = u < 0.0f ? 0.0f : u > 1.0f ? 1.0f : u;
    }
    float q[3];
    for (int k = 0; k < 3; k++)
        q[k] = ap[k] - u * ab[k];
    *t = u;
    return v3_dot(q, q);
}

float merp_seg_distance2(const merp_seg *s, const float p[3], float *t)
{
    float u;
    float d2 = seg_distance2(s, p, &u);
    if (t != NULL)
        *t = u;
    return d2;
}

float merp_seg_distance(const merp_seg *s, const float p[3], float *t)
{
    return sqrtf(merp_seg_distance2(s, p, t));
}

float merp_seg_field(const merp_seg *s, const float p[3])
{
    assert(s->ra > 0.0f && s->rb > 0.0f);
    float t;
    float d2 = seg_distance2(s, p, &t);
    float R = ((1.0f - t) * s->ra + t * s->rb) / XC;
    float x2 = d2 / (R * R);
    if (x2 >= 1.0f)
        return 0.0f;
    float u = 1.0f - x2;
    return u * u * u;
}

float merp_seg_support(const merp_seg *s)
{
    return (s->ra > s->rb ? s->ra : s->rb) / XC;
}
