/* meristemd — the request-head check (see head.h). Names of libmicrohttpd's
 * functions in comments refer to src/microhttpd/connection.c of 0.9.75. */
#include "config.h"

#include <stdarg.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>

#include "server/head.h"

merd_head_state merd_head_refuse(merd_head_verdict *v, unsigned status, const char *slug,
                                 const char *fmt, ...)
{
    v->status = status;
    v->slug = slug;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(v->detail, sizeof v->detail, fmt, ap);
    va_end(ap);
    return MERD_HEAD_BAD;
}

/* The next line from `*at`: a line ends at LF, and a CR just before it is not
 * part of it (get_next_header_line). False when no LF follows yet. */
static bool next_line(const char *d, size_t size, size_t *at, const char **line, size_t *len)
{
    const char *lf = memchr(d + *at, '\n', size - *at);
    if (lf == NULL)
        return false;
    *line = d + *at;
    *len = (size_t)(lf - *line);
    if (*len > 0 && (*line)[*len - 1] == '\r')
        (*len)--;
    *at = (size_t)(lf - d) + 1;
    return true;
}

int merd_head_hex_digit(char c)
{
    if (c >= '0' && c <= '9')
        return c - '0';
    if (c >= 'a' && c <= 'f')
        return c - 'a' + 10;
    if (c >= 'A' && c <= 'F')
        return c - 'A' + 10;
    return -1;
}

/* Digits of base 10 or 16 at the start of s[0..n) into *value: how many were
 * read, 0 on overflow of 64 bits (MHD_str_to_uint64_n_, MHD_strx_to_uint64_n_). */
static size_t parse_number(const char *s, size_t n, unsigned base, uint64_t *value)
{
    uint64_t v = 0;
    size_t i = 0;
    for (; i < n; i++) {
        int d = merd_head_hex_digit(s[i]);
        if (d < 0 || (unsigned)d >= base)
            break;
        if (v > (UINT64_MAX - (unsigned)d) / base)
            return 0;
        v = v * base + (unsigned)d;
    }
    *value = v;
    return i;
}

/* The request line (parse_initial_message_line, parse_http_version). Adds the
 * query arguments' records to *cost. */
static merd_head_state check_request_line(const char *line, size_t len, size_t *cost,
                                          merd_head_verdict *v)
{
    const char *end = line + len;
    const char *sp = memchr(line, ' ', len);
    if (sp == NULL || sp == line)
        return merd_head_refuse(v, 400, "bad-request-line",
                      "the request line must be METHOD, a space, the target, a space and "
                      "HTTP/1.1 (RFC 9112 §3)");
    const char *uri = sp + 1;
    while (uri < end && *uri == ' ')
        uri++;
    const char *version = end;
    if (uri < end) {
        const char *p = end - 1;
        while (*p == ' ' && p > uri)
            p--;
        while (*p != ' ' && p > uri)
            p--;
        if (p > uri) {
            version = p + 1;
            const char *query = memchr(uri, '?', (size_t)(p - uri));
            for (const char *q = query; q != NULL && q < p; q = memchr(q + 1, '&', (size_t)(p - q - 1)))
                *cost += MERD_HEAD_FIELD_COST;
        }
    }
    size_t n = (size_t)(end - version);
    if (n != 8 || memcmp(version, "HTTP/", 5) != 0 || version[6] != '.' || version[5] < '0' ||
        version[5] > '9' || version[7] < '0' || version[7] > '9')
        return merd_head_refuse(v, 400, "bad-request-line",
                      "the request line must end with the protocol version, HTTP/1.1 "
                      "(RFC 9112 §2.3)");
    if (version[5] != '1')
        return merd_head_refuse(v, 505, "http-version", "meristemd speaks HTTP/1.0 and HTTP/1.1, not %.8s",
                      version);
    return MERD_HEAD_GOOD;
}

typedef struct fields {
    const char *length, *encoding; /* first values, or NULL */
    size_t length_size, encoding_size;
} fields;

static bool named(const char *key, size_t n, const char *name)
{
    return n == strlen(name) && strncasecmp(key, name, n) == 0;
}

/* One header line (process_header_line); records Content-Length and
 * Transfer-Encoding in `f` and the line's records in *cost. */
static merd_head_state check_field(const char *line, size_t len, fields *f, size_t *cost,
                                   merd_head_verdict *v)
{
    if (line[0] == ' ' || line[0] == '\t')
        return merd_head_refuse(v, 400, "bad-header",
                      "a header line must not begin with a space or tab (obsolete line "
                      "folding, RFC 9112 §5.2)");
    // The value ends at a NUL, and a colon after a NUL is not seen (strchr).
    size_t text = strnlen(line, len);
    const char *colon = memchr(line, ':', text);
    if (colon == NULL)
        return merd_head_refuse(v, 400, "bad-header", "a header line must be NAME: VALUE (RFC 9112 §5)");
    size_t key = (size_t)(colon - line);
    const char *value = colon + 1;
    while (value < line + text && (*value == ' ' || *value == '\t'))
        value++;
    size_t value_size = (size_t)(line + text - value);
    *cost += MERD_HEAD_FIELD_COST;
    if (named(line, key, "Content-Length") && f->length == NULL) {
        f->length = value;
        f->length_size = value_size;
    } else if (named(line, key, "Transfer-Encoding") && f->encoding == NULL) {
        f->encoding = value;
        f->encoding_size = value_size;
    } else if (named(line, key, "Cookie")) {
        // parse_cookie_header copies the value and records each cookie.
        *cost += value_size + MERD_HEAD_FIELD_COST;
        for (const char *c = memchr(value, ';', value_size); c != NULL;
             c = memchr(c + 1, ';', (size_t)(value + value_size - c - 1)))
            *cost += MERD_HEAD_FIELD_COST;
    }
    return MERD_HEAD_GOOD;
}

/* The body's framing as announced (parse_connection_headers): a
 * Transfer-Encoding wins over Content-Length. */
static merd_head_state check_framing(const fields *f, merd_head_verdict *v)
{
    v->body = MERD_BODY_NONE;
    v->length = 0;
    if (f->encoding != NULL) {
        bool chunked = f->encoding_size == 7 && strncasecmp(f->encoding, "chunked", 7) == 0;
        v->body = chunked ? MERD_BODY_CHUNKED : MERD_BODY_UNTIL_CLOSE;
        return MERD_HEAD_GOOD;
    }
    if (f->length == NULL)
        return MERD_HEAD_GOOD;
    uint64_t n = 0;
    size_t digits = parse_number(f->length, f->length_size, 10, &n);
    if (digits == f->length_size && digits != 0) {
        v->body = n != 0 ? MERD_BODY_LENGTH : MERD_BODY_NONE;
        v->length = n;
        return MERD_HEAD_GOOD;
    }
    if (digits == 0 && f->length_size != 0 && f->length[0] >= '0' && f->length[0] <= '9')
        return merd_head_refuse(v, 413, "body-too-large",
                      "Content-Length does not fit in 64 bits; meristemd takes bodies of "
                      "at most --max-body bytes");
    return merd_head_refuse(v, 400, "bad-content-length",
                  "Content-Length must be a decimal number of bytes (RFC 9110 §8.6)");
}

merd_head_state merd_head_bad_chunk(merd_head_verdict *v)
{
    return merd_head_refuse(v, 400, "bad-chunk",
                  "a chunk must begin with its size in hexadecimal on a line of its own and "
                  "end with a line end (RFC 9112 §7.1)");
}

merd_head_state merd_head_chunk_too_large(merd_head_verdict *v)
{
    return merd_head_refuse(v, 413, "body-too-large",
                            "a chunk size does not fit in 64 bits; meristemd takes bodies of at "
                            "most --max-body bytes");
}

/* Trailer lines after the last chunk, as far as they go: each NAME: VALUE. */
static merd_head_state check_trailers(const char *d, size_t size, size_t at, merd_head_verdict *v)
{
    const char *line;
    size_t len;
    bool any = false;
    while (next_line(d, size, &at, &line, &len) && len > 0) {
        bool folded = any && (line[0] == ' ' || line[0] == '\t');
        if (!folded && memchr(line, ':', strnlen(line, len)) == NULL)
            return merd_head_bad_chunk(v);
        any = true;
    }
    return MERD_HEAD_GOOD;
}

/* The chunked body from `at`, as far as the bytes go (process_request_body). */
static merd_head_state check_chunks(const char *d, size_t size, size_t at, merd_head_verdict *v)
{
    while (at < size) {
        const char *s = d + at;
        size_t avail = size - at, i = 0, len = 0;
        bool found = false, ended = false;
        for (; i < avail; i++) {
            if (s[i] == '\n') {
                if (!found)
                    len = i > 0 && s[i - 1] == '\r' ? i - 1 : i;
                found = ended = true;
                break;
            }
            if (!found && s[i] == ';') {
                len = i;
                found = true;
            }
        }
        if (found && len == 0)
            return merd_head_bad_chunk(v);
        if (!found) {
            len = avail;
            if (s[avail - 1] == '\r' && --len == 0)
                return merd_head_bad_chunk(v);
        }
        uint64_t chunk = 0;
        size_t digits = parse_number(s, len, 16, &chunk);
        if (digits == 0 && merd_head_hex_digit(s[0]) >= 0)
            return merd_head_chunk_too_large(v);
        if (digits != len)
            return merd_head_bad_chunk(v);
        if (!ended)
            return MERD_HEAD_GOOD;
        at += i + 1;
        if (chunk == 0)
            return check_trailers(d, size, at, v);
        if (size - at <= chunk)
            return MERD_HEAD_GOOD;
        at += (size_t)chunk;
        if (d[at] == '\n')
            at++;
        else if (size - at >= 2 && d[at] == '\r' && d[at + 1] == '\n')
            at += 2;
        else if (size - at < 2)
            return MERD_HEAD_GOOD;
        else
            return merd_head_bad_chunk(v);
    }
    return MERD_HEAD_GOOD;
}

static merd_head_state too_large(merd_head_verdict *v, bool in_request_line, size_t budget)
{
    if (in_request_line)
        return merd_head_refuse(v, 414, "uri-too-long",
                      "the request line is longer than meristemd takes (%zu bytes; "
                      "--connection-memory is twice that)", budget);
    return merd_head_refuse(v, 431, "header-fields-too-large",
                  "the request head is larger than meristemd takes (%zu bytes, with %d for "
                  "each field; --connection-memory is twice that)", budget,
                  MERD_HEAD_FIELD_COST);
}

merd_head_state merd_head_check(const char *data, size_t size, size_t budget,
                                merd_head_verdict *v)
{
    size_t at = 0, cost = 0;
    const char *line;
    size_t len;
    // Empty lines before a request are skipped.
    do {
        if (!next_line(data, size, &at, &line, &len))
            return size > budget ? too_large(v, true, budget) : MERD_HEAD_MORE;
    } while (len == 0);
    merd_head_state s = check_request_line(line, len, &cost, v);
    if (s != MERD_HEAD_GOOD)
        return s;
    cost += at;
    if (cost > budget)
        return too_large(v, true, budget);
    fields f = {0};
    for (;;) {
        size_t start = at;
        if (!next_line(data, size, &at, &line, &len))
            return cost + (size - start) > budget ? too_large(v, false, budget) : MERD_HEAD_MORE;
        cost += at - start;
        if (len == 0)
            break;
        s = check_field(line, len, &f, &cost, v);
        if (s != MERD_HEAD_GOOD)
            return s;
        if (cost > budget)
            return too_large(v, false, budget);
    }
    if (cost > budget)
        return too_large(v, false, budget);
    s = check_framing(&f, v);
    if (s != MERD_HEAD_GOOD)
        return s;
    v->head_size = at;
    if (v->body != MERD_BODY_CHUNKED)
        return s;
    merd_head_verdict chunks;
    s = check_chunks(data, size, at, &chunks);
    if (s == MERD_HEAD_BAD)
        *v = chunks;
    return s;
}
