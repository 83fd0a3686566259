/* meristem — reading an L-system's productions in cpfg's syntax: a production
 *     lc < pred > rc : cond -> succ : prob
 * (also "-->"), where lc, rc and cond may be "*" or absent (ABOP §1.8, §1.10),
 * prob is the weight of a stochastic production (ABOP §1.7) and a successor "*"
 * is the empty string; the modules of its parts and the expressions in them.
 * Modules are one character, or "?" and a letter (the query modules of ABOP's
 * successors), optionally followed by "(args)". The lines, directives and
 * sections around the productions are parse.c's.
 */
#include "config.h"

#include "models/lsystem/parse_private.h"

#include <ctype.h>
#include <stdio.h>
#include <string.h>

#include "core/alloc.h"

/* A warning at line, col (merp_lsys_warnings): kept while there is room. */
static void warn_at(merp_ls_pctx *c, int line, int col, const char *msg)
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


merp_ls_span merp_ls_trim(merp_ls_span s)
{
    while (s.b < s.e && isspace((unsigned char)*s.b))
        s = merp_ls_sub(s, s.b + 1, s.e);
    while (s.e > s.b && isspace((unsigned char)s.e[-1]))
        s.e--;
    return s;
}

static int is_star(merp_ls_span s)
{
    s = merp_ls_trim(s);
    return s.e - s.b == 1 && *s.b == '*';
}

/* The first `ch` at parenthesis depth 0 in s (or s.e). */
static const char *find(merp_ls_span s, char ch, int last)
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
static merp_expr *expr(merp_ls_pctx *c, merp_ls_span s, int nnames)
{
    s = merp_ls_trim(s);
    return merp_expr_compile(s.b, (size_t)(s.e - s.b), c->names, nnames, s.line,
                             s.col, c->err);
}

double merp_ls_const_expr(merp_ls_pctx *c, merp_ls_span s, int *ok)
{
    merp_expr *e = expr(c, s, c->ls->ndefs);
    *ok = e != NULL;
    double v = e ? merp_expr_eval(e, NULL, NULL) : 0.0;
    merp_expr_free(e);
    return v;
}

/* Reads one module symbol at *p; 0 at the end of s. */
merp_sym merp_ls_symbol(merp_ls_span s, const char **p)
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
static int arglist(merp_ls_pctx *c, merp_ls_span s, const char **p, merp_ls_span *args)
{
    if (*p >= s.e || **p != '(')
        return 0;
    merp_ls_span in = merp_ls_sub(s, *p + 1, s.e);
    const char *close = find(in, ')', 0);
    if (close >= s.e)
        return merp_ls_error_at(c, s.line, s.col + (int)(*p - s.b), "unclosed '('");
    int n = 0;
    const char *a = *p + 1;
    for (;;) {
        const char *comma = find(merp_ls_sub(s, a, close), ',', 0);
        if (n == MERP_LS_MAXARGS)
            return merp_ls_error_at(c, s.line, s.col + (int)(a - s.b), "too many parameters");
        args[n++] = merp_ls_sub(s, a, comma);
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

int merp_ls_identifier(merp_ls_span s)
{
    for (const char *p = s.b; p < s.e; p++)
        if (!(isalpha((unsigned char)*p) || *p == '_' ||
              (p > s.b && isdigit((unsigned char)*p))))
            return 0;
    return s.b < s.e;
}

/* A predecessor or context: modules with formal parameter names, which become
 * variables (appended to c->names, slots from *slot on). */
static int patterns(merp_ls_pctx *c, merp_ls_span s, merp_ls_pat **out, int *n, int *slot)
{
    int cap = 0;
    const char *p = s.b;
    merp_ls_span args[MERP_LS_MAXARGS];
    *out = NULL, *n = 0;
    for (merp_sym y; (y = merp_ls_symbol(s, &p)) != 0;) {
        int na = arglist(c, s, &p, args);
        if (na < 0)
            return -1;
        if (grow((void **)out, &cap, *n + 1, sizeof **out))
            return merp_ls_error_at(c, s.line, s.col, "out of memory");
        (*out)[(*n)++] = (merp_ls_pat){y, (uint16_t)na, (uint16_t)*slot};
        for (int k = 0; k < na; k++) {
            merp_ls_span a = merp_ls_trim(args[k]);
            size_t len = (size_t)(a.e - a.b);
            if (*slot >= MERP_LS_MAXVARS || len == 0 || len >= 32 || !merp_ls_identifier(a))
                return merp_ls_error_at(c, a.line, a.col, "bad formal parameter");
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
int merp_ls_successor(merp_ls_pctx *c, merp_ls_span s, merp_ls_prod *pr, int nnames)
{
    int cap = 0, acap = 0, depth = 0, open_col = 0;
    const char *p = s.b;
    merp_ls_span args[MERP_LS_MAXARGS];
    if (is_star(s))
        return 0;
    for (merp_sym y; (y = merp_ls_symbol(s, &p)) != 0;) {
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
            return merp_ls_error_at(c, s.line, s.col, "out of memory");
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

void merp_ls_prod_free(merp_ls_prod *pr)
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
static int head(merp_ls_pctx *c, merp_ls_span h, merp_ls_prod *pr)
{
    const char *lt = find(h, '<', 0), *gt = find(h, '>', 0);
    merp_ls_span lc = lt < h.e ? merp_ls_sub(h, h.b, lt) : merp_ls_sub(h, h.b, h.b);
    merp_ls_span pd = merp_ls_sub(h, lt < h.e ? lt + 1 : h.b, gt);
    merp_ls_span rc = gt < h.e ? merp_ls_sub(h, gt + 1, h.e) : merp_ls_sub(h, h.e, h.e);
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
        merp_ls_span t = merp_ls_trim(pd);
        return merp_ls_error_at(c, t.line, t.col, "the predecessor must be one module");
    }
    pr->pred = pp[0];
    merp_free(pp);
    if (c->sect != MERP_LS_PRODUCTIONS && pr->nlc + pr->nrc > 0) {
        merp_ls_span at = pr->nlc > 0 ? merp_ls_trim(lc) : merp_ls_sub(h, gt, h.e);
        return merp_ls_error_at(
            c, at.line, at.col,
            c->sect == MERP_LS_DECOMPOSITION
                ? "a context in a decomposition production (they are context-free)"
                : "a context in a homomorphism production (they are context-free)");
    }
    for (int k = 0; k < pr->nlc; k++)
        if (pr->lc[k].sym == '[' || pr->lc[k].sym == ']')
            return merp_ls_error_at(c, lc.line, lc.col, "brackets in a left context");
    pr->nvars = slot;
    return 0;
}

/* One production line, arrow at `arrow` (`alen` bytes). */
int merp_ls_production(merp_ls_pctx *c, merp_ls_span s, const char *arrow, int alen)
{
    merp_ls_prod pr;
    memset(&pr, 0, sizeof pr);
    pr.line = s.line;
    pr.section = c->sect;
    c->nnames = c->ls->ndefs;
    merp_ls_span left = merp_ls_sub(s, s.b, arrow), right = merp_ls_sub(s, arrow + alen, s.e);
    const char *colon = find(left, ':', 0);
    merp_ls_span cond = merp_ls_sub(left, colon < left.e ? colon + 1 : left.e, left.e);
    const char *pc = find(right, ':', 1);
    merp_ls_span succ = merp_ls_sub(right, right.b, pc);
    int rc = head(c, merp_ls_sub(left, left.b, colon), &pr);
    if (!rc && colon < left.e && !is_star(cond) && !(pr.cond = expr(c, cond, c->nnames)))
        rc = -1;
    if (!rc)
        rc = merp_ls_successor(c, succ, &pr, c->nnames);
    if (!rc && pc < right.e) {
        int ok;
        c->nnames = c->ls->ndefs;
        pr.prob = merp_ls_const_expr(c, merp_ls_sub(right, pc + 1, right.e), &ok);
        pr.has_prob = 1;
        if (!ok)
            rc = -1;
        else if (!(pr.prob >= 0.0))
            rc = merp_ls_error_at(c, s.line, s.col + (int)(pc + 1 - s.b), "negative probability");
    }
    if (!rc && grow((void **)&c->ls->prods, &c->ls->pcap, c->ls->nprod + 1,
                    sizeof pr))
        rc = merp_ls_error_at(c, s.line, s.col, "out of memory");
    if (rc) {
        merp_ls_prod_free(&pr);
        return -1;
    }
    c->ls->prods[c->ls->nprod++] = pr;
    return 0;
}

