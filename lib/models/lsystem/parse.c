/* meristem — reading an L-system in cpfg's syntax (the notation of ABOP chapters
 * 1 and 2 as the cpfg program of vlab accepts it).
 *
 * A text is a sequence of lines; C comments are blanked first (positions stay).
 * Recognised: "#define NAME expr" (a constant), "lsystem:", "endlsystem",
 * "derivation length: n", "axiom: modules", "ignore: symbols" or
 * "consider: symbols" (ABOP §1.8), and productions
 *     lc < pred > rc : cond -> succ : prob
 * (also "-->"), where lc, rc and cond may be "*" or absent (ABOP §1.8, §1.10),
 * prob is the weight of a stochastic production (ABOP §1.7) and a successor "*"
 * is the empty string. Modules are one character, or "?" and a letter (the query
 * modules of ABOP's successors), optionally followed by "(args)". Every error
 * names its line and column.
 *
 * Sections, in cpfg's order: a line "decomposition" starts the decomposition
 * productions and a line "homomorphism" the homomorphism productions, each
 * optionally with "maximum depth: n" (default MERP_LS_DEPTH_DEFAULT); both are
 * context-free here (a context is refused at its position), with conditions
 * and probabilities as in the L-system's own productions.
 */
#include "config.h"

#include "models/lsystem/lsystem_private.h"

#include <assert.h>
#include <ctype.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>

#include "core/alloc.h"

/* A span of one line: [b, e), column of b. */
typedef struct span {
    const char *b, *e;
    int line, col;
} span;

typedef struct pctx {
    merp_lsys *ls;
    merp_ls_error *err;
    merp_ls_name names[MERP_LS_MAXVARS + 256];
    int nnames;
    int sect; /* the section the lines belong to */
} pctx;

static int error_at(pctx *c, int line, int col, const char *msg)
{
    c->err->line = line;
    c->err->col = col;
    snprintf(c->err->msg, sizeof c->err->msg, "%s", msg);
    return -1;
}

/* A warning at line, col (merp_lsys_warnings): kept while there is room. */
static void warn_at(pctx *c, int line, int col, const char *msg)
{
    merp_lsys *ls = c->ls;
    if (ls->nwarn < MERP_LS_WARN_MAX) {
        merp_ls_error *w = &ls->warn[ls->nwarn];
        w->line = line;
        w->col = col;
        snprintf(w->msg, sizeof w->msg, "%s", msg);
    }
    ls->nwarn++;
}

static span sub(span s, const char *b, const char *e)
{
    return (span){b, e, s.line, s.col + (int)(b - s.b)};
}

static span trim(span s)
{
    while (s.b < s.e && isspace((unsigned char)*s.b))
        s = sub(s, s.b + 1, s.e);
    while (s.e > s.b && isspace((unsigned char)s.e[-1]))
        s.e--;
    return s;
}

static int is_star(span s)
{
    s = trim(s);
    return s.e - s.b == 1 && *s.b == '*';
}

/* The first `ch` at parenthesis depth 0 in s (or s.e). */
static const char *find(span s, char ch, int last)
{
    const char *hit = s.e;
    int depth = 0;
    for (const char *p = s.b; p < s.e; p++) {
        if (*p == ch && depth == 0) {
            hit = p;
            if (!last)
                break;
        } else if (*p == '(') {
            depth++;
        } else if (*p == ')') {
            depth--;
        }
    }
    return hit;
}

/* Compiles an expression; constants only when `names` is the defines. */
static merp_expr *expr(pctx *c, span s, int nnames)
{
    s = trim(s);
    return merp_expr_compile(s.b, (size_t)(s.e - s.b), c->names, nnames, s.line,
                             s.col, c->err);
}

static double const_expr(pctx *c, span s, int *ok)
{
    merp_expr *e = expr(c, s, c->ls->ndefs);
    *ok = e != NULL;
    double v = e ? merp_expr_eval(e, NULL, NULL) : 0.0;
    merp_expr_free(e);
    return v;
}

/* Reads one module symbol at *p; 0 at the end of s. */
static merp_sym symbol(span s, const char **p)
{
    while (*p < s.e && isspace((unsigned char)**p))
        (*p)++;
    if (*p >= s.e)
        return 0;
    unsigned char ch = (unsigned char)*(*p)++;
    if (ch == '?' && *p < s.e && isalpha((unsigned char)**p))
        return (merp_sym)(256 + (unsigned char)*(*p)++);
    return ch;
}

/* The argument list "(a, b)" right after a symbol, as spans of its arguments;
 * returns the count, 0 when there is none, -1 on error. */
static int arglist(pctx *c, span s, const char **p, span *args)
{
    if (*p >= s.e || **p != '(')
        return 0;
    span in = sub(s, *p + 1, s.e);
    const char *close = find(in, ')', 0);
    if (close >= s.e)
        return error_at(c, s.line, s.col + (int)(*p - s.b), "unclosed '('");
    int n = 0;
    const char *a = *p + 1;
    for (;;) {
        const char *comma = find(sub(s, a, close), ',', 0);
        if (n == MERP_LS_MAXARGS)
            return error_at(c, s.line, s.col + (int)(a - s.b), "too many parameters");
        args[n++] = sub(s, a, comma);
        if (comma >= close)
            break;
        a = comma + 1;
    }
    *p = close + 1;
    return n;
}

static int grow(void **p, int *cap, int need, size_t size)
{
    if (need <= *cap)
        return 0;
    int nc = *cap ? *cap * 2 : 8;
    while (nc < need)
        nc *= 2;
    void *q = merp_realloc(*p, (size_t)nc * size);
    if (!q)
        return -1;
    *p = q;
    *cap = nc;
    return 0;
}

static int identifier(span s)
{
    for (const char *p = s.b; p < s.e; p++)
        if (!(isalpha((unsigned char)*p) || *p == '_' ||
              (p > s.b && isdigit((unsigned char)*p))))
            return 0;
    return s.b < s.e;
}

/* A predecessor or context: modules with formal parameter names, which become
 * variables (appended to c->names, slots from *slot on). */
static int patterns(pctx *c, span s, merp_ls_pat **out, int *n, int *slot)
{
    int cap = 0;
    const char *p = s.b;
    span args[MERP_LS_MAXARGS];
    *out = NULL, *n = 0;
    for (merp_sym y; (y = symbol(s, &p)) != 0;) {
        int na = arglist(c, s, &p, args);
        if (na < 0)
            return -1;
        if (grow((void **)out, &cap, *n + 1, sizeof **out))
            return error_at(c, s.line, s.col, "out of memory");
        (*out)[(*n)++] = (merp_ls_pat){y, (uint16_t)na, (uint16_t)*slot};
        for (int k = 0; k < na; k++) {
            span a = trim(args[k]);
            size_t len = (size_t)(a.e - a.b);
            if (*slot >= MERP_LS_MAXVARS || len == 0 || len >= 32 || !identifier(a))
                return error_at(c, a.line, a.col, "bad formal parameter");
            merp_ls_name *nm = &c->names[c->nnames++];
            memcpy(nm->name, a.b, len);
            nm->name[len] = '\0';
            nm->slot = (*slot)++;
            nm->value = 0.0;
        }
    }
    return 0;
}

/* A successor (or the axiom, with `nnames` = the defines only). Unbalanced
 * brackets are accepted, as cpfg does, with a warning. */
static int successor(pctx *c, span s, merp_ls_prod *pr, int nnames)
{
    int cap = 0, acap = 0, depth = 0, open_col = 0;
    const char *p = s.b;
    span args[MERP_LS_MAXARGS];
    if (is_star(s))
        return 0;
    for (merp_sym y; (y = symbol(s, &p)) != 0;) {
        int col = s.col + (int)(p - 1 - s.b);
        if (y == '[' && depth++ == 0)
            open_col = col;
        if (y == ']' && depth-- == 0) {
            depth = 0;
            warn_at(c, s.line, col, "this ']' closes no '[' (accepted, as cpfg does: "
                                    "the turtle has nothing to pop)");
        }
        int na = arglist(c, s, &p, args);
        if (na < 0)
            return -1;
        if (grow((void **)&pr->succ, &cap, pr->nsucc + 1, sizeof *pr->succ) ||
            grow((void **)&pr->args, &acap, pr->nargs + na, sizeof *pr->args))
            return error_at(c, s.line, s.col, "out of memory");
        pr->succ[pr->nsucc++] = (merp_ls_out){y, (uint16_t)na, (uint32_t)pr->nargs};
        if (y >= 256 && strchr("PHLUE", y - 256) && c->sect != MERP_LS_HOMOMORPHISM)
            c->ls->queries = 1;
        for (int k = 0; k < na; k++) {
            merp_expr *e = expr(c, args[k], nnames);
            if (!e)
                return -1;
            pr->args[pr->nargs++] = e;
        }
    }
    if (depth > 0)
        warn_at(c, s.line, open_col, "this '[' is never closed (accepted, as cpfg does: "
                                     "the branch runs to the end of the string)");
    return 0;
}

static void prod_free(merp_ls_prod *pr)
{
    merp_free(pr->lc);
    merp_free(pr->rc);
    merp_expr_free(pr->cond);
    for (int k = 0; k < pr->nargs; k++)
        merp_expr_free(pr->args[k]);
    merp_free(pr->args);
    merp_free(pr->succ);
}

/* "lc < pred > rc" into pr, binding formal parameters in text order. */
static int head(pctx *c, span h, merp_ls_prod *pr)
{
    const char *lt = find(h, '<', 0), *gt = find(h, '>', 0);
    span lc = lt < h.e ? sub(h, h.b, lt) : sub(h, h.b, h.b);
    span pd = sub(h, lt < h.e ? lt + 1 : h.b, gt);
    span rc = gt < h.e ? sub(h, gt + 1, h.e) : sub(h, h.e, h.e);
    int slot = 0, npred;
    merp_ls_pat *pp = NULL;
    if ((!is_star(lc) && patterns(c, lc, &pr->lc, &pr->nlc, &slot)) ||
        patterns(c, pd, &pp, &npred, &slot) ||
        (!is_star(rc) && patterns(c, rc, &pr->rc, &pr->nrc, &slot))) {
        merp_free(pp);
        return -1;
    }
    if (npred != 1) {
        merp_free(pp);
        span t = trim(pd);
        return error_at(c, t.line, t.col, "the predecessor must be one module");
    }
    pr->pred = pp[0];
    merp_free(pp);
    if (c->sect != MERP_LS_PRODUCTIONS && pr->nlc + pr->nrc > 0) {
        span at = pr->nlc > 0 ? trim(lc) : sub(h, gt, h.e);
        return error_at(c, at.line, at.col,
                        c->sect == MERP_LS_DECOMPOSITION
                            ? "a context in a decomposition production (they are context-free)"
                            : "a context in a homomorphism production (they are context-free)");
    }
    for (int k = 0; k < pr->nlc; k++)
        if (pr->lc[k].sym == '[' || pr->lc[k].sym == ']')
            return error_at(c, lc.line, lc.col, "brackets in a left context");
    pr->nvars = slot;
    return 0;
}

/* One production line, arrow at `arrow` (`alen` bytes). */
static int production(pctx *c, span s, const char *arrow, int alen)
{
    merp_ls_prod pr;
    memset(&pr, 0, sizeof pr);
    pr.line = s.line;
    pr.section = c->sect;
    c->nnames = c->ls->ndefs;
    span left = sub(s, s.b, arrow), right = sub(s, arrow + alen, s.e);
    const char *colon = find(left, ':', 0);
    span cond = sub(left, colon < left.e ? colon + 1 : left.e, left.e);
    const char *pc = find(right, ':', 1);
    span succ = sub(right, right.b, pc);
    int rc = head(c, sub(left, left.b, colon), &pr);
    if (!rc && colon < left.e && !is_star(cond) && !(pr.cond = expr(c, cond, c->nnames)))
        rc = -1;
    if (!rc)
        rc = successor(c, succ, &pr, c->nnames);
    if (!rc && pc < right.e) {
        int ok;
        c->nnames = c->ls->ndefs;
        pr.prob = const_expr(c, sub(right, pc + 1, right.e), &ok);
        pr.has_prob = 1;
        if (!ok)
            rc = -1;
        else if (!(pr.prob >= 0.0))
            rc = error_at(c, s.line, s.col + (int)(pc + 1 - s.b), "negative probability");
    }
    if (!rc && grow((void **)&c->ls->prods, &c->ls->pcap, c->ls->nprod + 1,
                    sizeof pr))
        rc = error_at(c, s.line, s.col, "out of memory");
    if (rc) {
        prod_free(&pr);
        return -1;
    }
    c->ls->prods[c->ls->nprod++] = pr;
    return 0;
}

static int define(pctx *c, span s)
{
    const char *p = s.b;
    while (p < s.e && !isspace((unsigned char)*p))
        p++;
    span name = sub(s, s.b, p);
    size_t len = (size_t)(name.e - name.b);
    if (len >= 32 || !identifier(name))
        return error_at(c, s.line, s.col, "bad #define name");
    merp_lsys *ls = c->ls;
    if (ls->ndefs >= 256)
        return error_at(c, s.line, s.col, "too many #define");
    int ok;
    double v = const_expr(c, sub(s, p, s.e), &ok);
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
static void context_set(merp_lsys *ls, span s, int consider)
{
    if (consider)
        memset(ls->skip, 1, sizeof ls->skip);
    const char *p = s.b;
    for (merp_sym y; (y = symbol(s, &p)) != 0;)
        ls->skip[y] = (uint8_t)!consider;
    ls->skip['['] = ls->skip[']'] = 0;
}

/* When s starts with keyword `kw` (case-insensitive, blanks collapsed), returns
 * the rest of the line after it. */
static int keyword(span s, const char *kw, span *rest)
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
    *rest = sub(s, p, s.e);
    return 1;
}

/* "decomposition" or "homomorphism": the productions that follow belong to it. */
static int section(pctx *c, span s, span rest)
{
    int sect = tolower((unsigned char)*s.b) == 'd' ? MERP_LS_DECOMPOSITION : MERP_LS_HOMOMORPHISM;
    rest = trim(rest);
    if (rest.b < rest.e && !(rest.e - rest.b == 1 && *rest.b == ':'))
        return error_at(c, rest.line, rest.col, "unexpected text after the section's name");
    if (sect <= c->sect)
        return error_at(c, s.line, s.col,
                        sect == c->sect ? "this section was started before"
                                        : "the decomposition comes before the homomorphism");
    c->sect = sect;
    return 0;
}

static int max_depth(pctx *c, span s, span r)
{
    int ok;
    if (c->sect == MERP_LS_PRODUCTIONS)
        return error_at(c, s.line, s.col, "maximum depth: outside a decomposition or homomorphism");
    double v = const_expr(c, r, &ok);
    if (ok && !(v >= 1.0 && v <= MERP_LS_DEPTH_MAX && v == (double)(int)v))
        return error_at(c, r.line, trim(r).col, "bad maximum depth (an integer from 1 to 1000)");
    c->ls->tab[c->sect].depth = (int)v;
    return ok ? 0 : -1;
}

static int directive(pctx *c, span s, int *done)
{
    merp_lsys *ls = c->ls;
    span r;
    int ok = 1;
    *done = 1;
    if (keyword(s, "#define ", &r))
        return define(c, trim(r));
    if (keyword(s, "derivation length:", &r)) {
        double v = const_expr(c, r, &ok);
        if (ok && !(v >= 0.0 && v <= 1e6))
            return error_at(c, r.line, trim(r).col, "bad derivation length");
        ls->dlen = (int)v;
        return ok ? 0 : -1;
    }
    if (keyword(s, "axiom:", &r)) {
        merp_ls_prod pr;
        memset(&pr, 0, sizeof pr);
        int rc = successor(c, r, &pr, ls->ndefs);
        merp_lstr_clear(&ls->axiom);
        float a[MERP_LS_MAXARGS];
        for (int i = 0; !rc && i < pr.nsucc; i++) {
            for (int k = 0; k < pr.succ[i].nargs; k++)
                a[k] = (float)merp_expr_eval(pr.args[pr.succ[i].arg0 + k], NULL, NULL);
            if (merp_lstr_push(&ls->axiom, pr.succ[i].sym, a, pr.succ[i].nargs))
                rc = error_at(c, s.line, s.col, "out of memory");
        }
        prod_free(&pr);
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
        return error_at(c, s.line, s.col, "not supported yet");
    *done = 0;
    return 0;
}

static int line(pctx *c, span s)
{
    s = trim(s);
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
        return error_at(c, s.line, s.col, "expected a production (\"->\")");
    int alen = 2;
    if (a > s.b && a[-1] == '-')
        a--, alen = 3;
    return production(c, s, a, alen);
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
    pctx *c = merp_calloc(1, sizeof *c);
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
            rc = line(c, (span){b, e, ln, 1});
            if (*e == '\0')
                break;
            b = e + 1;
        }
        for (int k = 0; !rc && k < MERP_LS_SECTIONS; k++)
            if (index_heads(ls, k))
                rc = error_at(c, 0, 0, "out of memory");
        if (!rc && !(ls->defs = merp_malloc(((size_t)ls->ndefs + 1) * sizeof *ls->defs)))
            rc = error_at(c, 0, 0, "out of memory");
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
        prod_free(&ls->prods[i]);
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
