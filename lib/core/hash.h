/* meristem — FNV-1a 64, the one hash of lib/ (scene hashes, shadow grids, mesh
 * digests). Not installed. Fast, deterministic, not cryptographic: it fingerprints
 * state for tests and ETags. */
#ifndef MERISTEM_CORE_HASH_H
#define MERISTEM_CORE_HASH_H

#include <stddef.h>
#include <stdint.h>

/* The start value every hash of lib/ has used. It is FNV's offset basis
 * 14695981039346656037 with its last digit lost; the rounds are FNV-1a's. Kept:
 * the scene hashes the golden test and clients have recorded depend on it. */
#define MERP_FNV_OFFSET UINT64_C(1469598103934665603)
#define MERP_FNV_PRIME UINT64_C(1099511628211)

/* Folds `n` bytes at `data` into `h` (start from MERP_FNV_OFFSET). O(n). */
static inline uint64_t merp_fnv(uint64_t h, const void *data, size_t n)
{
    const unsigned char *p = data;
    for (size_t i = 0; i < n; i++) {
        h ^= p[i];
        h *= MERP_FNV_PRIME;
    }
    return h;
}

/* Folds a 32-bit value's bytes, least significant first, whatever the host's byte
 * order: the same digest on every machine. */
static inline uint64_t merp_fnv_u32le(uint64_t h, uint32_t v)
{
    const unsigned char b[4] = {(unsigned char)v, (unsigned char)(v >> 8),
                                (unsigned char)(v >> 16), (unsigned char)(v >> 24)};
    return merp_fnv(h, b, sizeof b);
}

/* The word-wise variant: one FNV-1a round per 32-bit word rather than per byte
 * (the mesh digest's, kept so recorded hashes stay valid). */
static inline uint64_t merp_fnv_word(uint64_t h, uint32_t w)
{
    return (h ^ w) * MERP_FNV_PRIME;
}

#endif
