/* meristem — Perlin's improved noise, 3-D, and its fBm (perlin.h). */
#include "config.h"

#include <assert.h>
#include <math.h>
#include <stddef.h>

#include <meristem/rng.h>

#include "core/perlin.h"

void merp_perlin_init(merp_perlin *n, uint64_t seed)
{
    assert(n != NULL);
    /* A stream of its own: the scene's stream is not drawn from. */
    mer_rng rng;
    mer_rng_seed(&rng, seed ^ UINT64_C(0x5045524c494e3344)); /* "PERLIN3D" */
    for (int i = 0; i < 256; i++)
        n->perm[i] = (uint8_t)i;
    for (uint32_t i = 255; i > 0; i--) {
        uint32_t j = mer_rng_below(&rng, i + 1);
        uint8_t t = n->perm[i];
        n->perm[i] = n->perm[j];
        n->perm[j] = t;
    }
    for (int i = 0; i < 256; i++)
        n->perm[256 + i] = n->perm[i];
}

static float fade(float t) { return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f); }

static float lerp(float t, float a, float b) { return a + t * (b - a); }

/* The dot product of (x, y, z) with one of the 12 edge directions of a cube
 * (4 of them twice, to make 16), picked by the low 4 bits of the hash. */
static float grad(int hash, float x, float y, float z)
{
    int h = hash & 15;
    float u = h < 8 ? x : y;
    float v = h < 4 ? y : (h == 12 || h == 14 ? x : z);
    return ((h & 1) == 0 ? u : -u) + ((h & 2) == 0 ? v : -v);
}

float merp_perlin3(const merp_perlin *n, float x, float y, float z)
{
    assert(n != NULL);
    float fx = floorf(x), fy = floorf(y), fz = floorf(z);
    /* The lattice cell, wrapped to 0..255 (two's complement keeps negatives periodic). */
    int X = (int)(int64_t)fx & 255, Y = (int)(int64_t)fy & 255, Z = (int)(int64_t)fz & 255;
    x -= fx;
    y -= fy;
    z -= fz;
    float u = fade(x), v = fade(y), w = fade(z);
    const uint8_t *p = n->perm;
    int A = p[X] + Y, AA = p[A] + Z, AB = p[A + 1] + Z;
    int B = p[X + 1] + Y, BA = p[B] + Z, BB = p[B + 1] + Z;
    float r = lerp(w,
                   lerp(v, lerp(u, grad(p[AA], x, y, z), grad(p[BA], x - 1, y, z)),
                        lerp(u, grad(p[AB], x, y - 1, z), grad(p[BB], x - 1, y - 1, z))),
                   lerp(v, lerp(u, grad(p[AA + 1], x, y, z - 1), grad(p[BA + 1], x - 1, y, z - 1)),
                        lerp(u, grad(p[AB + 1], x, y - 1, z - 1),
                             grad(p[BB + 1], x - 1, y - 1, z - 1))));
    /* The gradients have length √2: |r| stays within about 1.04; clamp to [-1, 1]. */
    return fminf(1.0f, fmaxf(-1.0f, r));
}

float merp_perlin_fbm(const merp_perlin *n, const float p[3], uint32_t octaves)
{
    assert(n != NULL && p != NULL && octaves >= 1);
    float sum = 0.0f, amp = 1.0f, norm = 0.0f, f = 1.0f;
    for (uint32_t o = 0; o < octaves; o++) {
        sum += amp * merp_perlin3(n, p[0] * f, p[1] * f, p[2] * f);
        norm += amp;
        amp *= 0.5f;
        f *= 2.0f;
    }
    return sum / norm;
}
