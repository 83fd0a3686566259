/* meristem — reading an L-system in cpfg's syntax (the notation of ABOP chapters
 * 1 and 2 as the cpfg program of vlab accepts it): the text, its lines and
 * directives; the productions themselves are read by parse_production.c.
 *
 * A text is a sequence of lines; C comments are blanked first (positions stay).
 * Recognised: "#define NAME expr" (a constant), "lsystem:", "endlsystem",
 * "derivation length: n", "axiom: modules", "ignore: symbols" or
 * "consider: symbols" (ABOP §1.8), and productions (parse_production.c). Every
 * error names its line and column.
 *
 * Sections, in cpfg's order: a line "decomposition" starts the decomposition
 * productions and a line "homomorphism" the homomorphism productions, each
 * optionally with "maximum depth: n" (default MERP_LS_DEPTH_DEFAULT); both are
 * context-free here (a context is refused at its position), with conditions
 * and probabilities as in the L-system's own productions.
 */
#include "config.h"

#include "models/lsystem/parse_private.h"

#include <assert.h>
#include <ctype.h>
#include <stdio.h>
#include <string.h>

#include "core/alloc.h"

static int define(merp_ls_pctx *c, merp_ls_span s)
{
    const char *p = s.b;
    while (p < s.e && !isspace((unsigned char)*p))
        p++;
    merp_ls_span name = merp_ls_sub(s, s.b, p);
    size_t len = (size_t)(name.e - name.b);
    if (len >= 32 || !merp_ls_identifier(name))
        return merp_ls_error_at(c, s.line, s.col, "bad #define name");
    merp_lsys *ls = c->ls;
    if (ls->ndefs >= 256)
        return merp_ls_error_at(c, s.line, s.col, "too many #define");
    int ok;
    double v = merp_ls_const_expr(c, merp_ls_sub(s, p, s.e), &ok);
    if (!ok)
        return -1;
    merp_ls_name *nm = &c->names[ls->ndefs++];
    memcpy(nm->name, name.b, len);
    nm->name[len] = '\0';
    nm->slot = -1;
    nm->value = v;
    return 0;
}

/* The symbols of ignore: or consider: (ABOP §1.8); brackets always count. */
static void context_set(merp_lsys *ls, merp_ls_span s, int consider)
{
    if (consider)
        memset(ls->skip, 1, sizeof ls->skip);
    const char *p = s.b;
    for (merp_sym y; (y = merp_ls_symbol(s, &p)) != 0;)
        ls->skip[y] = (uint8_t)!consider;
    ls->skip['['] = ls->skip[']'] = 0;
}

/* When s starts with keyword `kw` (case-insensitive, blanks collapsed), returns
 * the rest of the line after it. */
static int keyword(merp_ls_span s, const char *kw, merp_ls_span *rest)
{
    const char *p = s.b;
    for (const char *k = kw; *k; k++) {
        if (*k == ' ') {
            while (p < s.e && isspace((unsigned char)*p))
                p++;
            continue;
        }
        if (p >= s.e || tolower((unsigned char)*p) != *k)
            return 0;
        p++;
    }
    *rest = merp_ls_sub(s, p, s.e);
    return 1;
}

/* "decomposition" or "homomorphism": the productions that follow belong to it. */
static int section(merp_ls_pctx *c, merp_ls_span s, merp_ls_span rest)
{
    int sect = tolower((unsigned char)*s.b) == 'd' ? MERP_LS_DECOMPOSITION : MERP_LS_HOMOMORPHISM;
    rest = merp_ls_trim(rest);
    if (rest.b < rest.e && !(rest.e - rest.b == 1 && *rest.b == ':'))
        return merp_ls_error_at(c, rest.line, rest.col, "unexpected text after the section's name");
    if (sect <= c->sect)
        return merp_ls_error_at(c, s.line, s.col,
                                sect == c->sect
                                    ? "this section was started before"
                                    : "the decomposition comes before the homomorphism");
    c->sect = sect;
    return 0;
}

static int max_depth(merp_ls_pctx *c, merp_ls_span s, merp_ls_span r)
{
    int ok;
    if (c->sect == MERP_LS_PRODUCTIONS)
        return merp_ls_error_at(c, s.line, s.col,
                                "maximum depth: outside a decomposition or homomorphism");
    double v = merp_ls_const_expr(c, r, &ok);
    if (ok && !(v >= 1.0 && v <= MERP_LS_DEPTH_MAX && v == (double)(int)v))
        return merp_ls_error_at(c, r.line, merp_ls_trim(r).col,
                                "bad maximum depth (an integer from 1 to 1000)");
    c->ls->tab[c->sect].depth = (int)v;
    return ok ? 0 : -1;
}

static int directive(merp_ls_pctx *c, merp_ls_span s, int *done)
{
    merp_lsys *ls = c->ls;
    merp_ls_span r;
    int ok = 1;
    *done = 1;
    if (keyword(s, "#define ", &r))
        return define(c, merp_ls_trim(r));
    if (keyword(s, "derivation length:", &r)) {
        double v = merp_ls_const_expr(c, r, &ok);
        if (ok && !(v >= 0.0 && v <= 1e6))
            return merp_ls_error_at(c, r.line, merp_ls_trim(r).col, "bad derivation length");
        ls->dlen = (int)v;
        return ok ? 0 : -1;
    }
    if (keyword(s, "axiom:", &r)) {
        merp_ls_prod pr;
        memset(&pr, 0, sizeof pr);
        int rc = merp_ls_successor(c, r, &pr, ls->ndefs);
        merp_lstr_clear(&ls->axiom);
        float a[MERP_LS_MAXARGS];
        for (int i = 0; !rc && i < pr.nsucc; i++) {
            for (int k = 0; k < pr.succ[i].nargs; k++)
                a[k] = (float)merp_expr_eval(pr.args[pr.succ[i].arg0 + k], NULL, NULL);
            if (merp_lstr_push(&ls->axiom, pr.succ[i].sym, a, pr.succ[i].nargs))
                rc = merp_ls_error_at(c, s.line, s.col, "out of memory");
        }
        merp_ls_prod_free(&pr);
        return rc;
    }
    if (keyword(s, "ignore:", &r) || keyword(s, "consider:", &r)) {
        context_set(ls, r, tolower((unsigned char)*s.b) == 'c');
        return 0;
    }
    if (keyword(s, "lsystem:", &r) || keyword(s, "endlsystem", &r))
        return 0;
    if (keyword(s, "decomposition", &r) || keyword(s, "homomorphism", &r))
        return section(c, s, r);
    if (keyword(s, "maximum depth:", &r))
        return max_depth(c, s, r);
    if (*s.b == '#')
        return merp_ls_error_at(c, s.line, s.col, "not supported yet");
    *done = 0;
    return 0;
}

static int line(merp_ls_pctx *c, merp_ls_span s)
{
    s = merp_ls_trim(s);
    if (s.b == s.e)
        return 0;
    int done, rc = directive(c, s, &done);
    if (done)
        return rc;
    const char *a = NULL;
    for (const char *p = s.b; p + 1 < s.e; p++)
        if (p[0] == '-' && p[1] == '>') {
            a = p;
            break;
        }
    if (!a)
        return merp_ls_error_at(c, s.line, s.col, "expected a production (\"->\")");
    int alen = 2;
    if (a > s.b && a[-1] == '-')
        a--, alen = 3;
    return merp_ls_production(c, s, a, alen);
}

/* Groups the productions of section `sect` by predecessor symbol, keeping
 * their order. */
static int index_heads(merp_lsys *ls, int sect)
{
    merp_ls_table *t = &ls->tab[sect];
    t->head_off = merp_calloc(MERP_LS_NSYM + 1, sizeof *t->head_off);
    t->by_head = merp_malloc(((size_t)ls->nprod + 1) * sizeof *t->by_head);
    if (!t->head_off || !t->by_head)
        return -1;
    for (int i = 0; i < ls->nprod; i++)
        if (ls->prods[i].section == sect) {
            t->head_off[ls->prods[i].pred.sym + 1]++;
            t->nprod++;
        }
    for (int y = 0; y < MERP_LS_NSYM; y++)
        t->head_off[y + 1] += t->head_off[y];
    int fill[MERP_LS_NSYM];
    memcpy(fill, t->head_off, sizeof fill);
    for (int i = 0; i < ls->nprod; i++)
        if (ls->prods[i].section == sect)
            t->by_head[fill[ls->prods[i].pred.sym]++] = i;
    return 0;
}

/* A copy of `text` with C comments blanked (newlines kept, so positions hold). */
static char *strip_comments(const char *text, size_t len)
{
    char *t = merp_malloc(len + 1);
    if (!t)
        return NULL;
    memcpy(t, text, len + 1);
    for (size_t i = 0; i + 1 < len; i++) {
        if (t[i] != '/' || t[i + 1] != '*')
            continue;
        const char *close = strstr(t + i + 2, "*/");
        size_t j = close ? (size_t)(close - t) + 2 : len;
        for (size_t k = i; k < j; k++)
            if (t[k] != '\n')
                t[k] = ' ';
        i = j - 1;
    }
    return t;
}

merp_lsys *merp_lsys_parse(const char *text, merp_ls_error *err)
{
    assert(text && err);
    memset(err, 0, sizeof *err);
    merp_lsys *ls = merp_calloc(1, sizeof *ls);
    merp_ls_pctx *c = merp_calloc(1, sizeof *c);
    size_t len = strlen(text);
    char *t = strip_comments(text, len);
    int rc = 0;
    if (!ls || !c || !t) {
        snprintf(err->msg, sizeof err->msg, "out of memory");
        rc = -1;
    } else {
        merp_lstr_init(&ls->axiom);
        c->ls = ls, c->err = err;
        ls->tab[MERP_LS_DECOMPOSITION].depth = MERP_LS_DEPTH_DEFAULT;
        ls->tab[MERP_LS_HOMOMORPHISM].depth = MERP_LS_DEPTH_DEFAULT;
        const char *b = t;
        for (int ln = 1; !rc; ln++) {
            const char *e = strchr(b, '\n');
            if (!e)
                e = t + len;
            rc = line(c, (merp_ls_span){b, e, ln, 1});
            if (*e == '\0')
                break;
            b = e + 1;
        }
        for (int k = 0; !rc && k < MERP_LS_SECTIONS; k++)
            if (index_heads(ls, k))
                rc = merp_ls_error_at(c, 0, 0, "out of memory");
        if (!rc && !(ls->defs = merp_malloc(((size_t)ls->ndefs + 1) * sizeof *ls->defs)))
            rc = merp_ls_error_at(c, 0, 0, "out of memory");
        if (!rc)
            memcpy(ls->defs, c->names, (size_t)ls->ndefs * sizeof *ls->defs);
    }
    merp_free(t);
    merp_free(c);
    if (rc && ls) {
        merp_lsys_free(ls);
        ls = NULL;
    }
    return ls;
}

void merp_lsys_free(merp_lsys *ls)
{
    if (!ls)
        return;
    for (int i = 0; i < ls->nprod; i++)
        merp_ls_prod_free(&ls->prods[i]);
    merp_free(ls->prods);
    for (int k = 0; k < MERP_LS_SECTIONS; k++) {
        merp_free(ls->tab[k].by_head);
        merp_free(ls->tab[k].head_off);
    }
    merp_free(ls->defs);
    merp_lstr_free(&ls->axiom);
    merp_free(ls);
}

int merp_lsys_warnings(const merp_lsys *ls, const merp_ls_error **out)
{
    assert(ls != NULL && out != NULL);
    *out = ls->warn;
    return ls->nwarn;
}

int merp_lsys_derivation_length(const merp_lsys *ls)
{
    assert(ls);
    return ls->dlen;
}

const merp_lstr *merp_lsys_axiom(const merp_lsys *ls)
{
    assert(ls);
    return &ls->axiom;
}

int merp_lsys_nprod(const merp_lsys *ls)
{
    assert(ls);
    return ls->nprod;
}

int merp_lsys_section_size(const merp_lsys *ls, int sect)
{
    assert(ls && sect >= 0 && sect < MERP_LS_SECTIONS);
    return ls->tab[sect].nprod;
}

int merp_lsys_has_queries(const merp_lsys *ls)
{
    assert(ls);
    return ls->queries;
}
