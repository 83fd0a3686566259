/* meristem — the deterministic random number generator of a session.
 *
 * One generator per scene: xoshiro256** (Blackman and Vigna), seeded through
 * splitmix64 so that every 64-bit seed, 0 included, gives a good state. The state
 * is a plain value (not an opaque object) so a scene embeds it and a test can copy
 * it; its layout has no padding, so hashing it is safe. The C library's rand() is
 * never used: its sequence differs between platforms and breaks replay.
 */
#ifndef MERISTEM_RNG_H
#define MERISTEM_RNG_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct mer_rng {
    uint64_t s[4];
} mer_rng;

/* Seeds `rng` (not NULL) from `seed`: the same seed gives the same sequence on
 * every machine. O(1). */
void mer_rng_seed(mer_rng *rng, uint64_t seed);

/* The next 64 random bits. `rng` not NULL. O(1). */
uint64_t mer_rng_next(mer_rng *rng);

/* A float uniform in [0, 1): the top 24 bits of the next output. O(1). */
float mer_rng_float(mer_rng *rng);

/* A float uniform in [lo, hi). O(1). */
float mer_rng_range(mer_rng *rng, float lo, float hi);

/* An integer uniform in [0, n), n >= 1, without modulo bias. O(1) expected. */
uint32_t mer_rng_below(mer_rng *rng, uint32_t n);

/* The splitmix64 mixer: a bijection of 64-bit words; `*state` advances by the
 * golden-ratio increment. Exposed for tests and for deriving sub-seeds. O(1). */
uint64_t mer_splitmix64(uint64_t *state);

#ifdef __cplusplus
}
#endif

#endif
