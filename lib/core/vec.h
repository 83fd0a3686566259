/* meristem — small 3-vector helpers and angle constants shared inside lib/ (not
 * installed). */
#ifndef MERISTEM_CORE_VEC_H
#define MERISTEM_CORE_VEC_H

#include <math.h>

#define MER_DEG2RAD 0.017453292519943295f /* degrees to radians */
#define MERP_TWO_PI 6.2831853071795865f  /* one full turn in radians */

static inline float v3_dot(const float *a, const float *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static inline void v3_cross(const float *a, const float *b, float *out)
{
    float x = a[1] * b[2] - a[2] * b[1];
    float y = a[2] * b[0] - a[0] * b[2];
    float z = a[0] * b[1] - a[1] * b[0];
    out[0] = x;
    out[1] = y;
    out[2] = z;
}

static inline float v3_len(const float *a) { return sqrtf(v3_dot(a, a)); }

/* Normalizes in place; returns 0 (and leaves `a`) when its length is 0. */
static inline int v3_normalize(float *a)
{
    float l = v3_len(a);
    if (!(l > 0.0f))
        return 0;
    a[0] /= l;
    a[1] /= l;
    a[2] /= l;
    return 1;
}

/* Some unit vector perpendicular to the unit vector `d`. */
static inline void v3_any_perp(const float *d, float *out)
{
    const float x[3] = {1.0f, 0.0f, 0.0f}, z[3] = {0.0f, 0.0f, 1.0f};
    v3_cross(fabsf(d[0]) < 0.9f ? x : z, d, out);
    v3_normalize(out);
}

/* Rodrigues: rotates `v` about the unit `axis` by `angle` radians. */
static inline void v3_rotate(const float *v, const float *axis, float angle, float *out)
{
    float c = cosf(angle), s = sinf(angle);
    float k[3];
    v3_cross(axis, v, k);
    float d = v3_dot(axis, v) * (1.0f - c);
    float r[3];
    for (int i = 0; i < 3; i++)
        r[i] = v[i] * c + k[i] * s + axis[i] * d;
    out[0] = r[0];
    out[1] = r[1];
    out[2] = r[2];
}

#endif
