/* meristem — Perlin's improved noise (K. Perlin, "Improving Noise", SIGGRAPH
 * 2002) in 3-D, and fractional Brownian motion (fBm) of it. Not installed.
 *
 * The permutation is Perlin's 256 entries shuffled (Fisher-Yates) from a seed,
 * so every session has its own noise field and the same seed gives the same one
 * on every machine. The noise is 0 at every integer lattice point, continuous
 * with continuous first and second derivatives (the quintic fade 6t⁵ − 15t⁴ +
 * 10t³), and in [-1, 1]. */
#ifndef MERISTEM_CORE_PERLIN_H
#define MERISTEM_CORE_PERLIN_H

#include <stdint.h>

typedef struct merp_perlin {
    uint8_t perm[512]; /* the shuffled permutation, twice, so that p[p[x] + y] needs no wrap */
} merp_perlin;

/* The permutation of `seed`. O(256). */
void merp_perlin_init(merp_perlin *n, uint64_t seed);

/* Improved noise at (x, y, z). O(1). */
float merp_perlin3(const merp_perlin *n, float x, float y, float z);

/* `octaves` octaves (at least 1) of noise, each at twice the frequency and half
 * the amplitude of the one before, divided by the sum of the amplitudes: in
 * [-1, 1], 0 at lattice points. O(octaves). */
float merp_perlin_fbm(const merp_perlin *n, const float p[3], uint32_t octaves);

#endif
