/* meristem — growing the arrays of lib/'s struct-of-arrays stores. Not installed. */
#ifndef MERISTEM_CORE_ARRAY_H
#define MERISTEM_CORE_ARRAY_H

#include <assert.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"

/* Resizes the array `*pp` to `count` elements of `size` bytes. On failure (out of
 * memory, or a size that overflows) returns 0 and leaves `*pp` as it was, so a
 * caller that grows several arrays in turn never loses one. Returns 1 on success. */
static inline int merp_array_resize(void *pp, size_t count, size_t size)
{
    assert(pp != NULL && size > 0);
    if (count > SIZE_MAX / size)
        return 0;
    void *old; /* copied, not cast: `pp` points at a float * or a uint32_t * */
    memcpy(&old, pp, sizeof old);
    void *q = merp_realloc(old, (count ? count : 1) * size);
    if (q == NULL)
        return 0;
    memcpy(pp, &q, sizeof q);
    return 1;
}

/* merp_array_resize for a typed pointer variable `ptr`: `count` elements of *ptr. */
#define MERP_RESIZE(ptr, count) merp_array_resize(&(ptr), (count), sizeof *(ptr))

/* A copy of the first `count` elements of `size` bytes at `src` into a new block
 * at `*pp` (NULL when src is NULL or count is 0). Returns 0 when out of memory
 * (`*pp` is NULL then), else 1. */
static inline int merp_array_dup(void *pp, const void *src, size_t count, size_t size)
{
    assert(pp != NULL && size > 0);
    void *q = NULL;
    if (src != NULL && count > 0) {
        if (count > SIZE_MAX / size || (q = merp_malloc(count * size)) == NULL) {
            memcpy(pp, &q, sizeof q);
            return 0;
        }
        memcpy(q, src, count * size);
    }
    memcpy(pp, &q, sizeof q);
    return 1;
}
/* merp_array_dup into a typed pointer `dst` from the array `src` of the same type. */
#define MERP_DUP(dst, src, count) merp_array_dup(&(dst), (src), (count), sizeof *(src))

#endif
