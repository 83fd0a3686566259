/* meristem — the forest's definition: the sow request as text (forest.h). */
#include "config.h"

#include <assert.h>
#include <ctype.h>
#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "models/forest/forest.h"

/* A cursor over one line of the text. */
typedef struct cursor {
    const char *p, *end, *line_start;
    unsigned line;
} cursor;

/* A refusal at the cursor: the message is `a` then `b`. */
static mer_result fault(const cursor *c, mer_error *err, const char *a, const char *b)
{
    mer_error_set(err, MER_ERR_INVALID, "definition", "%s%s", a, b);
    err->line = c->line;
    err->column = (unsigned)(c->p - c->line_start) + 1;
    return MER_ERR_INVALID;
}

static void blanks(cursor *c)
{
    while (c->p < c->end && (*c->p == ' ' || *c->p == '\t' || *c->p == '\r'))
        c->p++;
}

/* The next word of the line into w (at most cap - 1 bytes); 0 at the line's end. */
static size_t word(cursor *c, char *w, size_t cap)
{
    blanks(c);
    size_t n = 0;
    while (c->p < c->end && !isspace((unsigned char)*c->p) && *c->p != '#') {
        if (n + 1 < cap)
            w[n] = *c->p;
        n++;
        c->p++;
    }
    w[n < cap ? n : cap - 1] = '\0';
    return n;
}

static mer_result number(cursor *c, double *out, mer_error *err)
{
    char w[64];
    blanks(c);
    const char *at = c->p;
    size_t n = word(c, w, sizeof w);
    char *end = NULL;
    errno = 0;
    *out = n > 0 && n < sizeof w ? strtod(w, &end) : (double)NAN;
    if (end == NULL || *end != '\0' || errno != 0 || !isfinite(*out)) {
        c->p = at;
        return fault(c, err, "a number expected", "");
    }
    return MER_OK;
}

static mer_result line(cursor *c, merp_sow *s, unsigned *seen, mer_error *err)
{
    static const char *const keys[] = {"area", "count", "min_distance", "seed", "presets"};
    char key[32];
    const char *at = c->p;
    if (word(c, key, sizeof key) == 0)
        return MER_OK;
    unsigned k = 0;
    while (k < 5 && strcmp(key, keys[k]) != 0)
        k++;
    c->p = at;
    if (k == 5)
        return fault(c, err, "use area, count, min_distance, seed or presets, not ", key);
    word(c, key, sizeof key);
    *seen |= 1u << k;
    double v[4];
    mer_result rc = MER_OK;
    for (int i = 0; rc == MER_OK && i < (k == 0 ? 4 : k < 4 ? 1 : 0); i++)
        rc = number(c, &v[i], err);
    if (rc != MER_OK)
        return rc;
    if (k == 0) {
        s->lo[0] = (float)fmin(v[0], v[2]), s->hi[0] = (float)fmax(v[0], v[2]);
        s->lo[1] = (float)fmin(v[1], v[3]), s->hi[1] = (float)fmax(v[1], v[3]);
    } else if (k == 1) {
        if (!(v[0] >= 1 && v[0] <= MER_PLANTS_MAX && v[0] == floor(v[0])))
            return fault(c, err, "count must be an integer from 1 to 10000", "");
        s->count = (uint32_t)v[0];
    } else if (k == 2) {
        s->r = (float)v[0];
    } else if (k == 3) {
        if (!(v[0] >= 0 && v[0] < 9007199254740992.0 && v[0] == floor(v[0])))
            return fault(c, err, "seed must be an integer from 0 to 2^53 - 1", "");
        s->seed = (uint64_t)v[0];
    } else {
        char name[MERP_FOREST_NAME_MAX];
        size_t n;
        s->npresets = 0;
        while ((at = c->p, n = word(c, name, sizeof name)) > 0) {
            if (n >= sizeof name || s->npresets == MERP_FOREST_PRESETS_MAX) {
                c->p = at;
                return fault(c, err, "presets: at most 16 names of at most 63 bytes", "");
            }
            memcpy(s->presets[s->npresets++], name, n + 1);
            blanks(c);
        }
    }
    char rest[8];
    blanks(c);
    at = c->p;
    if (word(c, rest, sizeof rest) > 0) {
        c->p = at;
        return fault(c, err, "unexpected words at the end of the line: ", rest);
    }
    return MER_OK;
}

mer_result merp_sow_parse(const char *text, size_t len, merp_sow *out, mer_error *err)
{
    assert(text != NULL && out != NULL);
    memset(out, 0, sizeof *out);
    cursor c = {text, text, text, 1};
    unsigned seen = 0;
    const char *stop = text + len;
    while (c.p < stop) {
        const char *nl = memchr(c.p, '\n', (size_t)(stop - c.p));
        c.end = nl != NULL ? nl : stop;
        c.line_start = c.p;
        mer_result rc = line(&c, out, &seen, err);
        if (rc != MER_OK)
            return rc;
        c.p = c.end < stop ? c.end + 1 : stop;
        c.line++;
    }
    if ((seen & 0x17u) != 0x17u || out->npresets == 0) {
        c.line_start = c.p;
        return fault(&c, err, "area, count, min_distance and presets are required", "");
    }
    return MER_OK;
}

size_t merp_sow_format(const merp_sow *s, char *buf, size_t cap)
{
    int n = snprintf(buf, cap, "area %.9g %.9g %.9g %.9g\ncount %" PRIu32
                     "\nmin_distance %.9g\nseed %" PRIu64 "\npresets",
                     (double)s->lo[0], (double)s->lo[1], (double)s->hi[0], (double)s->hi[1],
                     s->count, (double)s->r, s->seed);
    size_t at = n > 0 ? (size_t)n : 0;
    for (uint32_t i = 0; i < s->npresets; i++) {
        n = snprintf(at < cap ? buf + at : NULL, at < cap ? cap - at : 0, " %s", s->presets[i]);
        at += n > 0 ? (size_t)n : 0;
    }
    n = snprintf(at < cap ? buf + at : NULL, at < cap ? cap - at : 0, "\n");
    return at + (n > 0 ? (size_t)n : 0);
}
