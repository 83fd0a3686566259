/* meristem — xoshiro256** seeded by splitmix64. */
#include "config.h"

#include <meristem/rng.h>

uint64_t mer_splitmix64(uint64_t *state)
{
    uint64_t z = (*state += UINT64_C(0x9E3779B97F4A7C15));
    z = (z ^ (z >> 30)) * UINT64_C(0xBF58476D1CE4E5B9);
    z = (z ^ (z >> 27)) * UINT64_C(0x94D049BB133111EB);
    return z ^ (z >> 31);
}

void mer_rng_seed(mer_rng *rng, uint64_t seed)
{
    uint64_t st = seed;
    for (int i = 0; i < 4; i++)
        rng->s[i] = mer_splitmix64(&st);
}

static uint64_t rotl(uint64_t x, int k)
{
    return (x << k) | (x >> (64 - k));
}

uint64_t mer_rng_next(mer_rng *rng)
{
    uint64_t *s = rng->s;
    const uint64_t result = rotl(s[1] * 5, 7) * 9;
    const uint64_t t = s[1] << 17;
    s[2] ^= s[0];
    s[3] ^= s[1];
    s[1] ^= s[2];
    s[0] ^= s[3];
    s[2] ^= t;
    s[3] = rotl(s[3], 45);
    return result;
}

float mer_rng_float(mer_rng *rng)
{
    return (float)(mer_rng_next(rng) >> 40) * (1.0f / 16777216.0f);
}

float mer_rng_range(mer_rng *rng, float lo, float hi)
{
    return lo + (hi - lo) * mer_rng_float(rng);
}

uint32_t mer_rng_below(mer_rng *rng, uint32_t n)
{
    /* Lemire's nearly-divisionless method, with rejection for exactness. */
    uint64_t m = (uint64_t)(uint32_t)(mer_rng_next(rng) >> 32) * n;
    uint32_t low = (uint32_t)m;
    if (low < n) {
        uint32_t threshold = (uint32_t)(-n) % n;
        while (low < threshold) {
            m = (uint64_t)(uint32_t)(mer_rng_next(rng) >> 32) * n;
            low = (uint32_t)m;
        }
    }
    return (uint32_t)(m >> 32);
}
