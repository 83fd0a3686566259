/* meristem — an inverse-model tree's definition as one text: optional
 * `name: value` lines for its species and scalars, then its functions as .fset
 * text (funcfile.c). What a session's definition (mer_scene_set_definition) and
 * a preset's read, and what the model gives back (written whole, so reading it
 * again gives the same definition).
 *
 *     species: populus-deltoides   (the base: populus-deltoides, conifer, weeping)
 *     y_max: 27
 *     h_max: 25
 *     funcgalleryver 1 1
 *     items: 1
 *     ...                          (any subset of the functions, each once)
 *
 * A text without a species line changes what it names and keeps the rest. */
#include "config.h"

#include <assert.h>
#include <errno.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "models/inverse/inverse.h"

typedef struct scalar {
    const char *name;
    size_t at;
    int whole; /* a uint32_t field, else a float */
} scalar;

#define F(n) {#n, offsetof(merp_inv_def, n), 0}
#define U(n) {#n, offsetof(merp_inv_def, n), 1}
static const scalar scalars[] = {
    U(y_max),     F(h_max),     F(l_min),      F(l_max),     F(ls_max), U(m_max),
    F(a_max),     F(s_min),     F(theta_max),  F(beta_short), F(beta_long),
    F(leaf_size), F(span),      U(order_max),  F(jitter),     F(r_max),
};
#undef F
#undef U
#define NSCALARS (sizeof scalars / sizeof scalars[0])

static const struct {
    const char *name;
    mer_result (*def)(merp_inv_def *d, mer_error *err);
} species[] = {
    {"populus-deltoides", merp_inv_populus},
    {"conifer", merp_inv_conifer},
    {"weeping", merp_inv_weeping},
};

static mer_result bad(mer_error *err, unsigned line, unsigned column, const char *what)
{
    mer_result rc = mer_error_set(err, MER_ERR_INVALID, "definition", "line %u, column %u: %s",
                                  line, column, what);
    if (err != NULL) {
        err->line = line;
        err->column = column;
    }
    return rc;
}

/* One `name: value` line (no newline) into d. */
static mer_result read_line(merp_inv_def *d, const char *s, size_t n, unsigned line,
                            mer_error *err)
{
    const char *colon = memchr(s, ':', n);
    if (colon == NULL)
        return bad(err, line, 1, "expected `name: value` or funcgalleryver");
    size_t kn = (size_t)(colon - s);
    char value[64];
    size_t vn = n - kn - 1;
    const char *v = colon + 1;
    while (vn > 0 && (*v == ' ' || *v == '\t'))
        v++, vn--;
    while (vn > 0 && (v[vn - 1] == ' ' || v[vn - 1] == '\t' || v[vn - 1] == '\r'))
        vn--;
    if (vn == 0 || vn >= sizeof value)
        return bad(err, line, (unsigned)kn + 2, "expected a value");
    memcpy(value, v, vn);
    value[vn] = '\0';
    unsigned vcol = (unsigned)(v - s) + 1;
    if (kn == 7 && memcmp(s, "species", 7) == 0) {
        for (size_t i = 0; i < sizeof species / sizeof species[0]; i++)
            if (strcmp(species[i].name, value) == 0)
                return species[i].def(d, err);
        return bad(err, line, vcol, "unknown species; use populus-deltoides, conifer or weeping");
    }
    for (size_t i = 0; i < NSCALARS; i++) {
        if (strlen(scalars[i].name) != kn || memcmp(scalars[i].name, s, kn) != 0)
            continue;
        char *end;
        errno = 0;
        double x = strtod(value, &end);
        if (*end != '\0' || errno != 0 || !isfinite(x) ||
            (scalars[i].whole && (x < 0 || x > 4e9 || x != floor(x))))
            return bad(err, line, vcol, scalars[i].whole ? "expected a whole number"
                                                         : "expected a number");
        if (scalars[i].whole) {
            uint32_t u = (uint32_t)x;
            memcpy((char *)d + scalars[i].at, &u, sizeof u);
        } else {
            float f = (float)x;
            memcpy((char *)d + scalars[i].at, &f, sizeof f);
        }
        return MER_OK;
    }
    return bad(err, line, 1, "unknown name; a species, a scalar or funcgalleryver");
}

mer_result merp_inv_def_read(merp_inv_def *d, const char *text, size_t len, mer_error *err)
{
    assert(d != NULL && (text != NULL || len == 0));
    merp_inv_def nd = *d;
    size_t at = 0;
    unsigned line = 1;
    mer_result rc = MER_OK;
    while (at < len && rc == MER_OK) {
        const char *s = text + at;
        const char *nl = memchr(s, '\n', len - at);
        size_t n = nl != NULL ? (size_t)(nl - s) : len - at;
        if (n >= 14 && memcmp(s, "funcgalleryver", 14) == 0)
            break;
        size_t blank = 0;
        while (blank < n && (s[blank] == ' ' || s[blank] == '\t' || s[blank] == '\r'))
            blank++;
        if (blank < n)
            rc = read_line(&nd, s, n, line, err);
        at += n + (nl != NULL);
        line++;
    }
    if (rc == MER_OK && at < len) {
        rc = merp_inv_def_replace(&nd, text + at, len - at, err);
        if (rc != MER_OK && err != NULL && err->line > 0) {
            /* The .fset's own position, past the lines before it. */
            const char *m = err->message;
            const char *colon = strncmp(m, "line ", 5) == 0 ? strstr(m, ": ") : NULL;
            char msg[sizeof err->message];
            snprintf(msg, sizeof msg, "%s", colon != NULL ? colon + 2 : m);
            unsigned l = err->line + line - 1, c = err->column;
            (void)mer_error_set(err, rc, "definition", "line %u, column %u: %s", l, c, msg);
            err->line = l;
            err->column = c;
        }
    }
    if (rc == MER_OK)
        rc = merp_inv_def_check(&nd, err);
    if (rc == MER_OK)
        *d = nd;
    return rc;
}

char *merp_inv_def_write(const merp_inv_def *d, size_t *len)
{
    assert(d != NULL);
    char head[1024];
    size_t h = 0;
    for (size_t i = 0; i < NSCALARS && h < sizeof head; i++) {
        const char *p = (const char *)d + scalars[i].at;
        if (scalars[i].whole) {
            uint32_t u;
            memcpy(&u, p, sizeof u);
            h += (size_t)snprintf(head + h, sizeof head - h, "%s: %u\n", scalars[i].name, u);
        } else {
            float f;
            memcpy(&f, p, sizeof f);
            h += (size_t)snprintf(head + h, sizeof head - h, "%s: %.9g\n", scalars[i].name,
                                  (double)f);
        }
    }
    size_t body = merp_fset_write(d->g, MERP_G_COUNT, NULL, 0);
    char *text = merp_malloc(h + body + 1);
    if (text == NULL)
        return NULL;
    memcpy(text, head, h);
    merp_fset_write(d->g, MERP_G_COUNT, text + h, body + 1);
    if (len != NULL)
        *len = h + body;
    return text;
}
