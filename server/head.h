/* meristemd — the request-head check of the front (see front.h).
 *
 * Looks at the bytes a new connection has sent so far (its first request head
 * and, for a chunked body, the framing of the body that follows it) and tells
 * whether libmicrohttpd 0.9.75 would refuse them with one of its own HTML
 * pages. The rules mirror src/microhttpd/connection.c of that version:
 *   - a request line without a space, or with an empty method      400
 *   - a version that is not "HTTP/d.d"                             400
 *   - a version "HTTP/0.d" or "HTTP/2.d" and up                    505
 *   - a header line without a colon                                400
 *   - a header line that begins with a space or tab (obs-fold;
 *     libmicrohttpd joins it, RFC 9112 §5.2 lets a server refuse)  400
 *   - the first Content-Length (without a Transfer-Encoding) not
 *     all digits                                                   400
 *     and beyond 64 bits                                           413
 *   - a chunk-size line that is not hexadecimal, or a chunk not
 *     followed by a line end (as far as the bytes go)              400
 *     and a chunk size beyond 64 bits                              413
 *   - a head that costs libmicrohttpd more than `budget` bytes of
 *     its per-connection memory: the request line                  414
 *     or the header block                                          431
 * The cost of a head is its bytes plus MERD_HEAD_FIELD_COST for every field
 * libmicrohttpd records (each header, each query argument, each cookie) plus
 * the Cookie values it copies. With `budget` half of the connection memory,
 * a head the check passes always fits libmicrohttpd's pool.
 *
 * Pure and bounded: no allocation, O(size). */
#ifndef MERISTEMD_HEAD_H
#define MERISTEMD_HEAD_H

#include <stddef.h>

/* libmicrohttpd's record of one header or argument, with pool alignment. */
#define MERD_HEAD_FIELD_COST 64

typedef enum merd_head_state {
    MERD_HEAD_MORE, /* no verdict yet: the head is not complete */
    MERD_HEAD_GOOD, /* libmicrohttpd may have it */
    MERD_HEAD_BAD,  /* refuse with the problem in the verdict */
} merd_head_state;

typedef struct merd_head_verdict {
    unsigned status;  /* 400, 413, 414, 431 or 505 when MERD_HEAD_BAD */
    const char *slug; /* urn:meristem:problem:SLUG */
    char detail[200];
} merd_head_verdict;

/* The verdict on the first `size` bytes of a connection (`data` may hold NUL
 * bytes). MERD_HEAD_MORE only while the head is incomplete and has cost at
 * most `budget`; so a caller that looks at more than `budget` bytes always
 * gets a verdict. `v` is filled for MERD_HEAD_BAD only. */
merd_head_state merd_head_check(const char *data, size_t size, size_t budget,
                                merd_head_verdict *v);

#endif
