/* meristemd — inverse-model functions from JSON to .fset text (functions_json.h). */
#include "config.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "server/functions_json.h"

#define FUNCTIONS_MAX 64   /* a gallery; the model has 14 */
#define POINTS_MAX 64      /* lpfg's editor draws far fewer */

/* Appends to a growing buffer; 0 when out of memory. */
typedef struct buf {
    char *p;
    size_t n, cap;
} buf;

static int put(buf *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static int put(buf *b, const char *fmt, ...)
{
    for (;;) {
        va_list ap;
        va_start(ap, fmt);
        int k = vsnprintf(b->p != NULL ? b->p + b->n : NULL, b->p != NULL ? b->cap - b->n : 0,
                          fmt, ap);
        va_end(ap);
        if (k < 0)
            return 0;
        if (b->p != NULL && b->n + (size_t)k < b->cap) {
            b->n += (size_t)k;
            return 1;
        }
        size_t cap = b->cap ? 2 * b->cap : 4096;
        while (cap <= b->n + (size_t)k)
            cap *= 2;
        char *p = realloc(b->p, cap);
        if (p == NULL)
            return 0;
        b->p = p;
        b->cap = cap;
    }
}

/* One point [x, y] or [x, y, m] as a line. */
static int point(buf *b, const json_t *p, const char *f, merd_refusal *why)
{
    size_t n = json_array_size(p);
    if (!json_is_array(p) || n < 2 || n > 3 || !json_is_number(json_array_get(p, 0)) ||
        !json_is_number(json_array_get(p, 1)) ||
        (n == 3 && !json_is_integer(json_array_get(p, 2))))
        return merd_refuse(why, 422, "invalid-field", f, "%s must be [x, y] or [x, y, m]", f);
    double x = json_number_value(json_array_get(p, 0)), y = json_number_value(json_array_get(p, 1));
    json_int_t m = n == 3 ? json_integer_value(json_array_get(p, 2)) : 1;
    if (!isfinite(x) || !isfinite(y) || m < 1 || m > 16)
        return merd_refuse(why, 422, "out-of-range", f,
                           "%s: x and y must be finite and m from 1 to 16", f);
    if (!put(b, "%.9g %.9g %d\n", x, y, (int)m))
        return merd_refuse(why, 503, "out-of-memory", f, "out of memory");
    return 0;
}

/* One function object. */
static int function(buf *b, const json_t *o, const char *f, merd_refusal *why)
{
    char g[MERD_FIELD_MAX];
    const json_t *name = json_object_get(o, "name"), *kind = json_object_get(o, "kind");
    const json_t *samples = json_object_get(o, "samples"), *pts = json_object_get(o, "points");
    merd_path(g, sizeof g, f, "name");
    if (!json_is_object(o) || !json_is_string(name) || json_string_length(name) == 0 ||
        json_string_length(name) > 31 || strpbrk(json_string_value(name), "\n\r") != NULL)
        return merd_refuse(why, 422, "invalid-field", g, "%s must be a function's name", g);
    merd_path(g, sizeof g, f, "kind");
    const char *k = kind != NULL && json_is_string(kind) ? json_string_value(kind) : "";
    if (kind != NULL && strcmp(k, "bspline") != 0 && strcmp(k, "linear") != 0)
        return merd_refuse(why, 422, "invalid-field", g, "%s must be bspline or linear", g);
    merd_path(g, sizeof g, f, "samples");
    json_int_t ns = samples != NULL && json_is_integer(samples) ? json_integer_value(samples) : 64;
    if (samples != NULL && (!json_is_integer(samples) || ns < 2 || ns > 512))
        return merd_refuse(why, 422, "out-of-range", g, "%s must be from 2 to 512", g);
    merd_path(g, sizeof g, f, "points");
    size_t np = json_array_size(pts);
    if (!json_is_array(pts) || np < 2 || np > POINTS_MAX)
        return merd_refuse(why, 422, "invalid-field", g, "%s must be 2 to %d points", g,
                           POINTS_MAX);
    if (!put(b, "fver 1 1\nname: %s\nsamples: %d\nflip: off\n%spoints: %zu\n",
             json_string_value(name), (int)ns, strcmp(k, "linear") == 0 ? "kind: linear\n" : "",
             np))
        return merd_refuse(why, 503, "out-of-memory", f, "out of memory");
    for (size_t i = 0; i < np; i++) {
        char h[MERD_FIELD_MAX + 24];
        snprintf(h, sizeof h, "%s[%zu]", g, i);
        if (point(b, json_array_get(pts, i), h, why) != 0)
            return -1;
    }
    return 0;
}

int merd_functions_fset(const json_t *v, const char *f, char **out, size_t *len,
                        merd_refusal *why)
{
    *out = NULL;
    size_t n = json_array_size(v);
    if (!json_is_array(v) || n < 1 || n > FUNCTIONS_MAX)
        return merd_refuse(why, 422, "invalid-field", f, "%s must be an array of 1 to %d functions",
                           f, FUNCTIONS_MAX);
    buf b = {0};
    if (!put(&b, "funcgalleryver 1 1\nitems: %zu\n", n)) {
        free(b.p);
        return merd_refuse(why, 503, "out-of-memory", f, "out of memory");
    }
    for (size_t i = 0; i < n; i++) {
        char g[MERD_FIELD_MAX + 24];
        snprintf(g, sizeof g, "%s[%zu]", f, i);
        if (function(&b, json_array_get(v, i), g, why) != 0) {
            free(b.p);
            return -1;
        }
    }
    *out = b.p;
    *len = b.n;
    return 0;
}
