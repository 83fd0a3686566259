/* meristem — the text formats of graphically defined functions: .func (one
 * function, "fver 1 1") and .fset (a gallery, "funcgalleryver 1 1"), as the
 * L-studio function editor writes them and lpfg reads them. The layout is in
 * gfunc.h. Errors name the line and column where reading stopped. */
#include "config.h"

#include <assert.h>
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "models/inverse/gfunc.h"

/* A cursor over the text, one line at a time. */
typedef struct reader {
    const char *text;
    size_t len, pos;
    uint32_t line;    /* 1-based number of the current line */
    size_t line_at;   /* offset of its first byte */
    size_t line_end;  /* offset of its end (the newline or len) */
} reader;

static uint32_t column(const reader *r, size_t at) { return (uint32_t)(at - r->line_at) + 1; }

__attribute__((format(printf, 5, 6)))
static mer_result fail_at(const reader *r, size_t at, mer_result code, mer_error *err,
                          const char *fmt, ...)
{
    char msg[160];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    unsigned line = r->line > 0 ? r->line : 1, col = column(r, at);
    mer_result rc = mer_error_set(err, code, NULL, "line %u, column %u: %s", line, col, msg);
    if (err != NULL) {
        err->line = line;
        err->column = col;
    }
    return rc;
}

static int is_blank_line(const reader *r, size_t from, size_t to)
{
    for (size_t i = from; i < to; i++)
        if (!isspace((unsigned char)r->text[i]))
            return 0;
    return 1;
}

/* Moves to the next line that is not blank; 0 at the end of the text. */
static int next_line(reader *r)
{
    while (r->pos < r->len) {
        size_t start = r->pos, end = start;
        while (end < r->len && r->text[end] != '\n')
            end++;
        r->line++;
        r->pos = end < r->len ? end + 1 : end;
        if (!is_blank_line(r, start, end)) {
            r->line_at = start;
            r->line_end = end;
            return 1;
        }
    }
    r->line_at = r->line_end = r->len;
    return 0;
}

static size_t skip_space(const reader *r, size_t at)
{
    while (at < r->line_end && isspace((unsigned char)r->text[at]))
        at++;
    return at;
}

/* Expects the next non-blank line to start with `key` (after spaces); leaves *at
 * after it. */
static mer_result expect_line(reader *r, const char *key, size_t *at, mer_error *err)
{
    if (!next_line(r))
        return fail_at(r, r->len, MER_ERR_FORMAT, err, "expected \"%s\", found the end", key);
    size_t p = skip_space(r, r->line_at), n = strlen(key);
    if (r->line_end - p < n || memcmp(r->text + p, key, n) != 0)
        return fail_at(r, p, MER_ERR_FORMAT, err, "expected \"%s\"", key);
    *at = p + n;
    return MER_OK;
}

/* The word at *at (up to a space or the line's end) into buf; 0 when empty. */
static size_t word(const reader *r, size_t *at, char *buf, size_t cap)
{
    size_t p = skip_space(r, *at), n = 0;
    while (p + n < r->line_end && !isspace((unsigned char)r->text[p + n]))
        n++;
    size_t k = n < cap - 1 ? n : cap - 1;
    memcpy(buf, r->text + p, k);
    buf[k] = '\0';
    *at = p;
    return n;
}

static mer_result read_float(const reader *r, size_t *at, float *out, mer_error *err)
{
    char buf[64];
    size_t n = word(r, at, buf, sizeof buf);
    char *end = NULL;
    errno = 0;
    double v = n > 0 && n < sizeof buf ? strtod(buf, &end) : 0.0;
    if (n == 0 || n >= sizeof buf || *end != '\0' || errno != 0 || !isfinite(v) ||
        fabs(v) > 3.0e38)
        return fail_at(r, *at, MER_ERR_FORMAT, err, "expected a number");
    *out = (float)v;
    *at += n;
    return MER_OK;
}

static mer_result read_uint(const reader *r, size_t *at, uint32_t lo, uint32_t hi, uint32_t *out,
                            mer_error *err)
{
    char buf[32];
    size_t n = word(r, at, buf, sizeof buf);
    char *end = NULL;
    errno = 0;
    unsigned long v = n > 0 && n < sizeof buf && isdigit((unsigned char)buf[0])
                          ? strtoul(buf, &end, 10)
                          : 0;
    if (end == NULL || *end != '\0' || errno != 0 || v < lo || v > hi)
        return fail_at(r, *at, MER_ERR_FORMAT, err, "expected a whole number in %u..%u", lo, hi);
    *out = (uint32_t)v;
    *at += n;
    return MER_OK;
}

/* Nothing but spaces may follow on the line. */
static mer_result line_done(const reader *r, size_t at, mer_error *err)
{
    at = skip_space(r, at);
    return at == r->line_end ? MER_OK
                             : fail_at(r, at, MER_ERR_FORMAT, err, "unexpected text");
}

static mer_result read_version(reader *r, const char *key, mer_error *err)
{
    size_t at;
    uint32_t major, minor;
    mer_result rc = expect_line(r, key, &at, err);
    if (rc == MER_OK)
        rc = read_uint(r, &at, 1, 1, &major, err);
    if (rc == MER_OK)
        rc = read_uint(r, &at, 1, 1, &minor, err);
    return rc == MER_OK ? line_done(r, at, err) : rc;
}

static mer_result read_name(reader *r, merp_gfunc *f, mer_error *err)
{
    size_t at;
    mer_result rc = expect_line(r, "name:", &at, err);
    if (rc != MER_OK)
        return rc;
    size_t n = word(r, &at, f->name, sizeof f->name);
    if (n == 0)
        return fail_at(r, at, MER_ERR_FORMAT, err, "expected a name");
    if (n >= sizeof f->name)
        return fail_at(r, at, MER_ERR_FORMAT, err, "a name has at most %u bytes",
                       MERP_GF_NAME_MAX - 1);
    return line_done(r, at + n, err);
}

static mer_result read_flip(reader *r, merp_gfunc *f, mer_error *err)
{
    size_t at;
    char buf[8];
    mer_result rc = expect_line(r, "flip:", &at, err);
    if (rc != MER_OK)
        return rc;
    size_t n = word(r, &at, buf, sizeof buf);
    if (strcmp(buf, "on") != 0 && strcmp(buf, "off") != 0)
        return fail_at(r, at, MER_ERR_FORMAT, err, "expected on or off");
    f->flip = strcmp(buf, "on") == 0;
    return line_done(r, at + n, err);
}

/* "kind: linear" (ours) or "points: N". */
static mer_result read_kind_and_count(reader *r, merp_gfunc *f, mer_error *err)
{
    size_t at;
    if (!next_line(r))
        return fail_at(r, r->len, MER_ERR_FORMAT, err, "expected \"points:\", found the end");
    at = skip_space(r, r->line_at);
    if (r->line_end - at >= 5 && memcmp(r->text + at, "kind:", 5) == 0) {
        char buf[16];
        at += 5;
        size_t n = word(r, &at, buf, sizeof buf);
        if (strcmp(buf, "linear") == 0)
            f->kind = MERP_GF_LINEAR;
        else if (strcmp(buf, "bspline") == 0)
            f->kind = MERP_GF_BSPLINE;
        else
            return fail_at(r, at, MER_ERR_FORMAT, err, "expected linear or bspline");
        mer_result rc = line_done(r, at + n, err);
        if (rc == MER_OK)
            rc = expect_line(r, "points:", &at, err);
        if (rc != MER_OK)
            return rc;
    } else if (r->line_end - at >= 7 && memcmp(r->text + at, "points:", 7) == 0) {
        at += 7;
    } else {
        return fail_at(r, at, MER_ERR_FORMAT, err, "expected \"points:\"");
    }
    mer_result rc = read_uint(r, &at, 2, MERP_GF_POINTS_MAX, &f->npts, err);
    return rc == MER_OK ? line_done(r, at, err) : rc;
}

static mer_result read_points(reader *r, merp_gfunc *f, mer_error *err)
{
    for (uint32_t i = 0; i < f->npts; i++) {
        if (!next_line(r))
            return fail_at(r, r->len, MER_ERR_FORMAT, err,
                           "expected %u points, found the end after %u", f->npts, i);
        size_t at = r->line_at;
        float a, b;
        mer_result rc = read_float(r, &at, &a, err);
        if (rc == MER_OK)
            rc = read_float(r, &at, &b, err);
        if (rc != MER_OK)
            return rc;
        f->pts[i] = (merp_gf_point){f->flip ? b : a, f->flip ? a : b, 1};
        if (skip_space(r, at) < r->line_end) {
            rc = read_uint(r, &at, 1, MERP_GF_EXPANDED_MAX, &f->pts[i].m, err);
            if (rc != MER_OK)
                return rc;
        }
        rc = line_done(r, at, err);
        if (rc != MER_OK)
            return rc;
    }
    return MER_OK;
}

/* One function from the cursor, prepared. */
static mer_result read_one(reader *r, merp_gfunc *f, mer_error *err)
{
    memset(f, 0, sizeof *f);
    size_t at;
    mer_result rc = read_version(r, "fver", err);
    if (rc == MER_OK)
        rc = read_name(r, f, err);
    if (rc == MER_OK && (rc = expect_line(r, "samples:", &at, err)) == MER_OK &&
        (rc = read_uint(r, &at, 2, MERP_GF_SAMPLES_MAX, &f->samples, err)) == MER_OK)
        rc = line_done(r, at, err);
    if (rc == MER_OK)
        rc = read_flip(r, f, err);
    if (rc == MER_OK)
        rc = read_kind_and_count(r, f, err);
    if (rc != MER_OK)
        return rc;
    uint32_t points_line = r->line;
    size_t points_at = r->line_at;
    rc = read_points(r, f, err);
    if (rc != MER_OK)
        return rc;
    mer_error inner;
    if (merp_gfunc_prepare(f, &inner) != MER_OK) {
        reader at_points = *r;
        at_points.line = points_line;
        at_points.line_at = points_at;
        return fail_at(&at_points, points_at, MER_ERR_INVALID, err, "%s", inner.message);
    }
    return MER_OK;
}

mer_result merp_func_read(const char *text, size_t len, merp_gfunc *out, mer_error *err)
{
    assert(text != NULL || len == 0);
    reader r = {text, len, 0, 0, 0, 0};
    mer_result rc = read_one(&r, out, err);
    if (rc == MER_OK && next_line(&r))
        return fail_at(&r, r.line_at, MER_ERR_FORMAT, err, "text after the last point");
    return rc;
}

mer_result merp_fset_read(const char *text, size_t len, merp_gfunc *out, uint32_t cap,
                          uint32_t *count, mer_error *err)
{
    assert((text != NULL || len == 0) && count != NULL);
    *count = 0;
    reader r = {text, len, 0, 0, 0, 0};
    size_t at;
    uint32_t items;
    mer_result rc = read_version(&r, "funcgalleryver", err);
    if (rc == MER_OK && (rc = expect_line(&r, "items:", &at, err)) == MER_OK &&
        (rc = read_uint(&r, &at, 0, UINT32_MAX, &items, err)) == MER_OK)
        rc = line_done(&r, at, err);
    if (rc != MER_OK)
        return rc;
    if (items > cap)
        return fail_at(&r, r.line_at, MER_ERR_LIMIT, err, "%u items, at most %u", items, cap);
    for (uint32_t i = 0; i < items; i++) {
        rc = read_one(&r, &out[i], err);
        if (rc != MER_OK)
            return rc;
    }
    if (next_line(&r))
        return fail_at(&r, r.line_at, MER_ERR_FORMAT, err, "text after the last item");
    *count = items;
    return MER_OK;
}

/* snprintf into buf[*used..cap), counting what the whole text needs. */
__attribute__((format(printf, 4, 5)))
static void put(char *buf, size_t cap, size_t *used, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    char *at = *used < cap ? buf + *used : NULL;
    int n = vsnprintf(at, at != NULL ? cap - *used : 0, fmt, ap);
    va_end(ap);
    if (n > 0)
        *used += (size_t)n;
}

static void write_one(const merp_gfunc *f, char *buf, size_t cap, size_t *used)
{
    put(buf, cap, used, "fver 1 1\nname: %s\nsamples: %u\nflip: %s\n", f->name, f->samples,
        f->flip ? "on" : "off");
    if (f->kind == MERP_GF_LINEAR)
        put(buf, cap, used, "kind: linear\n");
    put(buf, cap, used, "points: %u\n", f->npts);
    for (uint32_t i = 0; i < f->npts; i++) {
        const merp_gf_point *p = &f->pts[i];
        double a = (double)(f->flip ? p->y : p->x), b = (double)(f->flip ? p->x : p->y);
        if (p->m != 1)
            put(buf, cap, used, "%.9g %.9g %u\n", a, b, p->m);
        else
            put(buf, cap, used, "%.9g %.9g\n", a, b);
    }
}

size_t merp_func_write(const merp_gfunc *f, char *buf, size_t cap)
{
    assert(f != NULL && (buf != NULL || cap == 0));
    size_t used = 0;
    if (cap > 0)
        buf[0] = '\0';
    write_one(f, buf, cap, &used);
    return used;
}

size_t merp_fset_write(const merp_gfunc *fs, uint32_t n, char *buf, size_t cap)
{
    assert((fs != NULL || n == 0) && (buf != NULL || cap == 0));
    size_t used = 0;
    if (cap > 0)
        buf[0] = '\0';
    put(buf, cap, &used, "funcgalleryver 1 1\nitems: %u\n", n);
    for (uint32_t i = 0; i < n; i++)
        write_one(&fs[i], buf, cap, &used);
    return used;
}
