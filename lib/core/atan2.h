/* meristem — a fast two-argument arctangent for angles that need not be
 * exact to the last bit (not installed).
 *
 * A patch vertex's texture coordinate u is its angle about the shaft
 * (lib/mesh/joints.c), and libm's atan2f, about 40 ns a call, was about 3 %
 * of meshing a tree's implicit junctions. This one is a polynomial, inline,
 * with no call and no branch on the quadrant but selects.
 *
 * The polynomial is Hastings' approximation as tabled by Abramowitz & Stegun,
 * Handbook of Mathematical Functions, formula 4.4.49: on 0 ≤ a ≤ 1,
 * atan a = a (1 + Σ c_2k a^2k, k = 1..8) with an error under 2·10⁻⁸ rad;
 * evaluated in float, within 4·10⁻⁷ rad of atan2 (a float ulp of π is
 * 2.4·10⁻⁷; tests/unit/test_atan2.c). */
#ifndef MERISTEM_CORE_ATAN2_H
#define MERISTEM_CORE_ATAN2_H

#include <math.h>

/* The angle of (x, y) in (−π, π], as atan2f(y, x) within 4·10⁻⁷ rad, for
 * finite x and y. Where atan2f tells zeros' signs apart it may not: on the
 * negative x axis it is +π for y = −0 too (atan2f: −π), and at the origin
 * it is 0 (atan2f: ±0 or ±π), angles a texture's u wraps to the same place. */
static inline float merp_atan2f(float y, float x)
{
    static const float pi = 3.14159265358979f, half_pi = 1.57079632679490f;
    float ax = fabsf(x), ay = fabsf(y);
    float hi = ax > ay ? ax : ay, lo = ax > ay ? ay : ax;
    if (hi == 0.0f)
        return 0.0f;
    float a = lo / hi, s = a * a;
    float p = 0.0028662257f;
    p = p * s - 0.0161657367f;
    p = p * s + 0.0429096138f;
    p = p * s - 0.0752896400f;
    p = p * s + 0.1065626393f;
    p = p * s - 0.1420889944f;
    p = p * s + 0.1999355085f;
    p = p * s - 0.3333314528f;
    float r = a + a * s * p; /* atan(lo / hi), in [0, π/4] */
    r = ay > ax ? half_pi - r : r;
    r = x < 0.0f ? pi - r : r;
    return y < 0.0f ? -r : r;
}

#endif
