/* meristemd — the body of a relayed request, byte by byte (see front.h).
 *
 * Once a request head has passed merd_head_check, the front forwards the body
 * after it to libmicrohttpd only as far as it has checked it, so that a
 * malformed chunk anywhere in a chunked body is refused with problem+json
 * before libmicrohttpd sees it (it would answer with its HTML page). The rules
 * are those of head.h for chunks, in a form that takes the body in pieces:
 *   - a chunk-size line: hexadecimal digits, then an optional extension after
 *     ';', then CR LF or LF; no digits, or another byte      400
 *     a size beyond 64 bits                                  413
 *   - chunk data, then CR LF or LF                           400 otherwise
 *   - after the last chunk (size 0), trailer lines NAME: VALUE (or continued
 *     with a space or tab) up to an empty line               400 otherwise
 *   - a chunk-size line or the trailers longer than `budget`      431
 * A Content-Length body is its bytes; a body of another Transfer-Encoding runs
 * to the end of the connection.
 *
 * Pure and bounded: no allocation, O(bytes fed). */
#ifndef MERISTEMD_FRAMING_H
#define MERISTEMD_FRAMING_H

#include <stdbool.h>
#include <stddef.h>

#include "server/head.h"

typedef struct merd_framing {
    merd_body_kind kind;
    int state;
    unsigned long long left; /* bytes left of the body (Content-Length) or chunk */
    unsigned long long size; /* the chunk size being read */
    size_t line;             /* bytes of the chunk-size line or of the trailers so far */
    size_t budget;
    bool digits, any_trailer, folded, colon, nul;
} merd_framing;

/* Starts reading the body announced by `head` (a MERD_HEAD_GOOD verdict). */
void merd_framing_start(merd_framing *f, const merd_head_verdict *head, size_t budget);

/* Reads the next `size` bytes of the connection. Sets *used to how many of
 * them belong to the body and are good, and returns
 *   MERD_HEAD_MORE  all `size` are the body's, and it goes on;
 *   MERD_HEAD_GOOD  the body ended after *used bytes (the next request follows);
 *   MERD_HEAD_BAD   data[*used] is malformed; `v` holds the refusal.
 * Once GOOD or BAD, start again before feeding more. */
merd_head_state merd_framing_feed(merd_framing *f, const char *data, size_t size, size_t *used,
                                  merd_head_verdict *v);

#endif
