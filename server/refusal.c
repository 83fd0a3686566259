/* meristemd — refusals and the library-result mapping (see refusal.h). */
#include "config.h"

#include <assert.h>
#include <stdarg.h>
#include <stdio.h>

#include "server/refusal.h"

int merd_refuse(merd_refusal *why, unsigned status, const char *slug, const char *field,
                const char *fmt, ...)
{
    why->status = status;
    why->line = why->column = 0;
    snprintf(why->slug, sizeof why->slug, "%s", slug);
    snprintf(why->field, sizeof why->field, "%s", field != NULL ? field : "");
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(why->detail, sizeof why->detail, fmt, ap);
    va_end(ap);
    return -1;
}

static void append(char *out, size_t n, size_t *used, const char *text)
{
    while (*text != '\0' && *used + 1 < n)
        out[(*used)++] = *text++;
    out[*used] = '\0';
}

void merd_path(char *out, size_t n, const char *where, const char *key)
{
    assert(n > 0);
    size_t used = 0;
    out[0] = '\0';
    append(out, n, &used, where);
    if (where[0] != '\0' && key[0] != '\0')
        append(out, n, &used, ".");
    append(out, n, &used, key);
}

/* Indexed by mer_result: what each failure means to a client. */
static const struct {
    unsigned status;
    const char *slug;
} problems[] = {
    [MER_ERR_INVALID] = {422, "invalid-field"},  [MER_ERR_RANGE] = {422, "out-of-range"},
    [MER_ERR_NOMEM] = {503, "out-of-memory"},    [MER_ERR_FORMAT] = {422, "invalid-field"},
    [MER_ERR_LIMIT] = {409, "limit"},            [MER_ERR_INTERNAL] = {500, "internal"},
    [MER_ERR_NOT_FOUND] = {404, "unknown-node"}, [MER_ERR_GONE] = {409, "dead-node"},
    [MER_ERR_ROOT] = {422, "root-node"},
};

int merd_refuse_lib(merd_refusal *why, mer_result rc, const mer_error *err, const char *where)
{
    assert(rc != MER_OK && err != NULL);
    char f[MERD_FIELD_MAX];
    merd_path(f, sizeof f, where, err->field);
    unsigned status = 422;
    const char *slug = "invalid-field";
    if ((size_t)rc < sizeof problems / sizeof problems[0] && problems[rc].slug != NULL) {
        status = problems[rc].status;
        slug = problems[rc].slug;
    }
    merd_refuse(why, status, slug, f, "%s", err->message);
    why->line = err->line;
    why->column = err->column;
    return -1;
}
