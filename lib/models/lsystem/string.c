/* meristem — the module string of an L-system (ABOP §1.2 strings, §1.10 modules
 * with parameters): symbols and parameter floats in flat arrays, so memory is
 * linear in the string and derivation walks it sequentially.
 */
#include "config.h"

#include "models/lsystem/lsystem.h"

#include <assert.h>
#include <stdio.h>
#include <string.h>

#include "core/alloc.h"

void merp_lstr_init(merp_lstr *s)
{
    assert(s);
    memset(s, 0, sizeof *s);
}

void merp_lstr_free(merp_lstr *s)
{
    assert(s);
    merp_free(s->sym);
    merp_free(s->poff);
    merp_free(s->par);
    merp_lstr_init(s);
}

void merp_lstr_clear(merp_lstr *s)
{
    assert(s);
    s->n = 0;
    s->npar = 0;
    if (s->poff)
        s->poff[0] = 0;
}

/* Grows `*p` (elements of `size` bytes, capacity `*cap`) to hold `need`. */
static int grow(void **p, size_t *cap, size_t need, size_t size)
{
    if (need <= *cap)
        return 0;
    size_t c = *cap ? *cap : 16;
    while (c < need)
        c *= 2;
    void *q = merp_realloc(*p, c * size);
    if (!q)
        return -1;
    *p = q;
    *cap = c;
    return 0;
}

int merp_lstr_reserve(merp_lstr *s, size_t n, size_t npar)
{
    assert(s);
    if (n + 1 > s->cap) {
        size_t cap = s->cap, cap2 = s->cap;
        if (grow((void **)&s->sym, &cap, n + 1, sizeof *s->sym) ||
            grow((void **)&s->poff, &cap2, n + 1, sizeof *s->poff))
            return -1;
        s->cap = cap < cap2 ? cap : cap2;
        if (s->n == 0)
            s->poff[0] = 0;
    }
    if (npar > s->pcap && grow((void **)&s->par, &s->pcap, npar, sizeof *s->par))
        return -1;
    return 0;
}

int merp_lstr_push(merp_lstr *s, merp_sym sym, const float *par, unsigned np)
{
    assert(s && (par || np == 0));
    if ((s->n + 2 > s->cap || s->npar + np > s->pcap) &&
        merp_lstr_reserve(s, s->n + 1, s->npar + np))
        return -1;
    if (np > UINT32_MAX - s->npar)
        return -1;
    s->sym[s->n] = sym;
    /* Modules hold few parameters: a loop beats a call to memcpy. */
    float *to = s->par + s->npar;
    for (unsigned k = 0; k < np; k++)
        to[k] = par[k];
    s->npar += np;
    s->n++;
    s->poff[s->n] = (uint32_t)s->npar;
    return 0;
}

void merp_lstr_swap(merp_lstr *a, merp_lstr *b)
{
    assert(a && b);
    merp_lstr t = *a;
    *a = *b;
    *b = t;
}

int merp_lstr_copy(merp_lstr *dst, const merp_lstr *src)
{
    assert(dst && src && dst != src);
    merp_lstr_clear(dst);
    for (size_t i = 0; i < src->n; i++)
        if (merp_lstr_push(dst, src->sym[i], src->par + src->poff[i],
                           merp_lstr_np(src, i)))
            return -1;
    return 0;
}

size_t merp_lstr_count(const merp_lstr *s, merp_sym sym)
{
    assert(s);
    size_t k = 0;
    for (size_t i = 0; i < s->n; i++)
        k += s->sym[i] == sym;
    return k;
}

/* Appends `text` to buf at *len (counting past cap, like snprintf). */
static void put(char *buf, size_t cap, size_t *len, const char *text)
{
    for (const char *t = text; *t; t++, (*len)++)
        if (*len + 1 < cap)
            buf[*len] = *t;
}

size_t merp_lstr_format(const merp_lstr *s, char *buf, size_t cap)
{
    assert(s && (buf || cap == 0));
    size_t len = 0;
    char tmp[40];
    for (size_t i = 0; i < s->n; i++) {
        merp_sym y = s->sym[i];
        if (y >= 256)
            snprintf(tmp, sizeof tmp, "?%c", (char)(y - 256));
        else
            snprintf(tmp, sizeof tmp, "%c", (char)y);
        put(buf, cap, &len, tmp);
        unsigned np = merp_lstr_np(s, i);
        for (unsigned k = 0; k < np; k++) {
            snprintf(tmp, sizeof tmp, "%s%g", k ? "," : "(",
                     (double)s->par[s->poff[i] + k]);
            put(buf, cap, &len, tmp);
        }
        if (np)
            put(buf, cap, &len, ")");
    }
    if (cap)
        buf[len < cap ? len : cap - 1] = '\0';
    return len;
}

int merp_lstr_brackets(const merp_lstr *s, size_t *match)
{
    assert(s && (match || s->n == 0));
    size_t *stack = NULL, depth = 0, cap = 0;
    for (size_t i = 0; i < s->n; i++) {
        match[i] = SIZE_MAX;
        if (s->sym[i] == '[') {
            if (grow((void **)&stack, &cap, depth + 1, sizeof *stack)) {
                merp_free(stack);
                return -1;
            }
            stack[depth++] = i;
        } else if (s->sym[i] == ']' && depth > 0) {
            size_t o = stack[--depth];
            match[i] = o;
            match[o] = i;
        }
    }
    merp_free(stack);
    return 0;
}

size_t merp_lstr_branch_end(const merp_lstr *s, size_t i)
{
    assert(s && i <= s->n);
    size_t depth = 0;
    for (; i < s->n; i++) {
        if (s->sym[i] == '[')
            depth++;
        else if (s->sym[i] == ']' && depth-- == 0)
            return i;
    }
    return s->n;
}
