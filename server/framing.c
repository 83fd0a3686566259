/* meristemd — the body of a relayed request (see framing.h). Names of
 * libmicrohttpd's functions in comments refer to src/microhttpd/connection.c
 * of 0.9.75. */
#include "config.h"

#include <stdint.h>

#include "server/framing.h"

enum {
    SIZE,          /* the chunk-size line's digits */
    SIZE_CR,       /* a CR after them: LF must follow */
    EXTENSION,     /* after ';': anything up to LF */
    DATA,          /* chunk data: `left` bytes */
    DATA_END,      /* CR LF or LF after the data */
    DATA_END_CR,   /* a CR after the data: LF must follow */
    TRAILER_BEGIN, /* the start of a trailer line, or the empty line */
    TRAILER_CR,    /* a CR at the start of a line */
    TRAILER,       /* inside a trailer line */
    DONE,
};

void merd_framing_start(merd_framing *f, const merd_head_verdict *head, size_t budget)
{
    *f = (merd_framing){.kind = head->body, .left = head->length, .budget = budget};
    f->state = head->body == MERD_BODY_CHUNKED ? SIZE : DONE;
}

static merd_head_state too_long(const merd_framing *f, merd_head_verdict *v)
{
    return merd_head_refuse(v, 431, "header-fields-too-large",
                            "a chunk-size line or the trailers are longer than meristemd takes "
                            "(%zu bytes; --connection-memory is twice that)", f->budget);
}

/* A chunk-size line's byte (process_request_body): MERD_HEAD_MORE to go on. */
static merd_head_state size_byte(merd_framing *f, char c, merd_head_verdict *v)
{
    int d = merd_head_hex_digit(c);
    if (f->state == SIZE && d >= 0) {
        if (f->size > (UINT64_MAX - (unsigned)d) / 16)
            return merd_head_chunk_too_large(v);
        f->size = f->size * 16 + (unsigned)d;
        f->digits = true;
    } else if (f->state == SIZE && c == ';' && f->digits) {
        f->state = EXTENSION;
    } else if (f->state == SIZE && c == '\r' && f->digits) {
        f->state = SIZE_CR;
    } else if (c == '\n' && (f->state != SIZE || f->digits)) {
        f->left = f->size;
        f->state = f->size == 0 ? TRAILER_BEGIN : DATA;
        f->line = 0;
        return MERD_HEAD_MORE;
    } else if (f->state != EXTENSION) {
        return merd_head_bad_chunk(v);
    }
    return ++f->line > f->budget ? too_long(f, v) : MERD_HEAD_MORE;
}

/* A trailer's byte (as head.c's check_trailers): MERD_HEAD_GOOD at the empty
 * line that ends the body. */
static merd_head_state trailer_byte(merd_framing *f, char c, merd_head_verdict *v)
{
    if (++f->line > f->budget)
        return too_long(f, v);
    if (f->state == TRAILER_BEGIN || f->state == TRAILER_CR) {
        if (c == '\n') {
            f->state = DONE;
            return MERD_HEAD_GOOD;
        }
        if (f->state == TRAILER_BEGIN && c == '\r') {
            f->state = TRAILER_CR;
            return MERD_HEAD_MORE;
        }
        // A line begun with CR has that CR as its first byte.
        f->folded = f->state == TRAILER_BEGIN && f->any_trailer && (c == ' ' || c == '\t');
        f->colon = f->nul = false;
        f->state = TRAILER;
    } else if (c == '\n') {
        if (!f->folded && !f->colon)
            return merd_head_bad_chunk(v);
        f->any_trailer = true;
        f->state = TRAILER_BEGIN;
        return MERD_HEAD_MORE;
    }
    // The name ends at a colon, and a colon after a NUL is not seen (strchr).
    f->nul = f->nul || c == '\0';
    f->colon = f->colon || (c == ':' && !f->nul);
    return MERD_HEAD_MORE;
}

static merd_head_state chunks(merd_framing *f, const char *data, size_t size, size_t *used,
                              merd_head_verdict *v)
{
    size_t at = 0;
    merd_head_state s = MERD_HEAD_MORE;
    while (at < size && s == MERD_HEAD_MORE) {
        char c = data[at];
        switch (f->state) {
        case DATA: {
            size_t n = size - at < f->left ? size - at : (size_t)f->left;
            f->left -= n;
            at += n;
            if (f->left == 0)
                f->state = DATA_END;
            continue;
        }
        case DATA_END:
        case DATA_END_CR:
            if (c == '\r' && f->state == DATA_END) {
                f->state = DATA_END_CR;
            } else if (c == '\n') {
                *f = (merd_framing){.kind = f->kind, .state = SIZE, .budget = f->budget};
            } else {
                s = merd_head_bad_chunk(v);
                continue;
            }
            break;
        case SIZE:
        case SIZE_CR:
        case EXTENSION:
            s = size_byte(f, c, v);
            if (s == MERD_HEAD_BAD)
                continue;
            break;
        default:
            s = trailer_byte(f, c, v);
            if (s == MERD_HEAD_BAD)
                continue;
            break;
        }
        at++;
    }
    *used = at;
    return s;
}

merd_head_state merd_framing_feed(merd_framing *f, const char *data, size_t size, size_t *used,
                                  merd_head_verdict *v)
{
    switch (f->kind) {
    case MERD_BODY_CHUNKED:
        return chunks(f, data, size, used, v);
    case MERD_BODY_UNTIL_CLOSE:
        *used = size;
        return MERD_HEAD_MORE;
    case MERD_BODY_LENGTH:
        *used = size < f->left ? size : (size_t)f->left;
        f->left -= *used;
        return f->left == 0 ? MERD_HEAD_GOOD : MERD_HEAD_MORE;
    case MERD_BODY_NONE:
        break;
    }
    *used = 0;
    return MERD_HEAD_GOOD;
}
