/* meristem — a growing byte buffer to write a scene into and a bounded cursor to
 * read one back (scene_io.c). Host byte order: a checkpoint says which order it
 * was written in and is refused on a machine of the other. Not installed. */
#ifndef MERISTEM_CORE_BYTES_H
#define MERISTEM_CORE_BYTES_H

#include <assert.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"

typedef struct merp_bytes_out {
    uint8_t *buf;
    size_t n, cap;
    int oom; /* an allocation failed: the buffer is incomplete */
} merp_bytes_out;

typedef struct merp_bytes_in {
    const uint8_t *p;
    size_t n, at;
    int bad; /* 1: a read went past the end or a value was out of range; 2: out of memory */
} merp_bytes_in;

static inline void merp_put(merp_bytes_out *o, const void *src, size_t size)
{
    if (o->oom || size == 0)
        return;
    if (size > SIZE_MAX / 2 - o->n) {
        o->oom = 1;
        return;
    }
    if (o->n + size > o->cap) {
        size_t cap = o->cap ? o->cap : 4096;
        while (cap < o->n + size)
            cap *= 2;
        uint8_t *b = merp_realloc(o->buf, cap);
        if (b == NULL) {
            o->oom = 1;
            return;
        }
        o->buf = b;
        o->cap = cap;
    }
    memcpy(o->buf + o->n, src, size);
    o->n += size;
}

static inline void merp_put_u32(merp_bytes_out *o, uint32_t v) { merp_put(o, &v, sizeof v); }
static inline void merp_put_u64(merp_bytes_out *o, uint64_t v) { merp_put(o, &v, sizeof v); }

/* Reads `size` bytes into `dst`; past the end, zeroes `dst` and marks `in` bad. */
static inline void merp_get(merp_bytes_in *in, void *dst, size_t size)
{
    if (in->bad || size > in->n - in->at) {
        in->bad = 1;
        memset(dst, 0, size);
        return;
    }
    memcpy(dst, in->p + in->at, size);
    in->at += size;
}

static inline uint32_t merp_get_u32(merp_bytes_in *in)
{
    uint32_t v;
    merp_get(in, &v, sizeof v);
    return v;
}

static inline uint64_t merp_get_u64(merp_bytes_in *in)
{
    uint64_t v;
    merp_get(in, &v, sizeof v);
    return v;
}

/* A new array of `count` elements of `size` bytes read from `in` into `*pp`
 * (NULL for 0). 0 when past the end or out of memory (`*pp` NULL, `in` bad). */
static inline int merp_get_array(merp_bytes_in *in, void *pp, size_t count, size_t size)
{
    void *q = NULL;
    if (!in->bad && count > 0) {
        if (count > (in->n - in->at) / size)
            in->bad = 1;
        else if ((q = merp_malloc(count * size)) == NULL)
            in->bad = 2;
        else
            merp_get(in, q, count * size);
    }
    memcpy(pp, &q, sizeof q);
    return !in->bad;
}
#define MERP_GET_ARRAY(in, ptr, count) merp_get_array((in), &(ptr), (count), sizeof *(ptr))

#endif
