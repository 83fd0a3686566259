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

/* How the body after a head is framed (RFC 9112 §6.3, as libmicrohttpd reads it). */
typedef enum merd_body_kind {
    MERD_BODY_NONE,        /* no body: the next request follows the head */
    MERD_BODY_LENGTH,      /* Content-Length bytes */
    MERD_BODY_CHUNKED,     /* Transfer-Encoding: chunked */
    MERD_BODY_UNTIL_CLOSE, /* another Transfer-Encoding: the rest of the connection */
} merd_body_kind;

typedef struct merd_head_verdict {
    unsigned status;  /* 400, 413, 414, 431 or 505 when MERD_HEAD_BAD */
    const char *slug; /* urn:meristem:problem:SLUG */
    char detail[200];
    /* When MERD_HEAD_GOOD: */
    size_t head_size;    /* bytes of the head, empty lines before it included */
    merd_body_kind body; /* the framing of the body after it */
    unsigned long long length; /* MERD_BODY_LENGTH: its bytes */
} merd_head_verdict;

/* The verdict on the first `size` bytes of a request (`data` may hold NUL
 * bytes). MERD_HEAD_MORE only while the head is incomplete and has cost at
 * most `budget`; so a caller that looks at more than `budget` bytes always
 * gets a verdict. For a chunked body, the chunks after the head are checked
 * as far as the bytes go. `v` is filled for MERD_HEAD_BAD (the problem) and
 * MERD_HEAD_GOOD (the head's size and framing). */
merd_head_state merd_head_check(const char *data, size_t size, size_t budget,
                                merd_head_verdict *v);

/* Fills `v` with a refusal; returns MERD_HEAD_BAD. For the checks of head.c
 * and framing.c. */
merd_head_state merd_head_refuse(merd_head_verdict *v, unsigned status, const char *slug,
                                 const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;

/* The value of a hexadecimal digit, or -1. */
int merd_head_hex_digit(char c);

/* The refusals of a malformed chunk (400) and of a chunk size beyond 64 bits (413). */
merd_head_state merd_head_bad_chunk(merd_head_verdict *v);
merd_head_state merd_head_chunk_too_large(merd_head_verdict *v);

#endif
