/* meristem — one derivation step of an L-system: every module is rewritten in
 * parallel (ABOP §1.2), by the first production whose predecessor, contexts
 * (ABOP §1.8) and condition (ABOP §1.10) match; a module no production matches
 * stays as it is.
 *
 * Stochastic productions (ABOP §1.7): when the first matching production has a
 * probability, the choice is among all matching productions with one, in
 * proportion to their weights. Every random number of module i in step t — this
 * choice, then ran() and nran() in conditions and successors — is drawn from a
 * counter keyed by (seed, t, i), so the string does not depend on the order in
 * which modules are rewritten.
 *
 * Context with brackets (ABOP §1.8): looking left, a "]" skips the whole sibling
 * branch back to its "[" and a "[" steps into the parent; looking right, a "["
 * in the string skips the child branch unless the context itself has "[" there,
 * a "]" ends the branch, and a "]" in the context skips the rest of the branch.
 * Symbols of the ignore list are skipped either way.
 *
 * Decomposition and homomorphism (cpfg): a module is rewritten by the first
 * matching production of the section, and each module of its successor again,
 * depth first, until no production applies or the section's maximum depth is
 * reached (the module then stays as it is: truncation, as cpfg does, not an
 * error). The decomposition's result replaces the derived string; the
 * homomorphism's is only read by the turtle. Their productions are
 * context-free, so a module's rewriting needs nothing but the module: one
 * buffer per depth holds the successors being expanded, and the cost is linear
 * in the output. Draws are keyed by (seed, step, module) at the top and by the
 * parent's key, the depth and the position in the successor below it.
 */
#include "config.h"

#include "models/lsystem/lsystem_private.h"

#include <assert.h>
#include <string.h>

#include "core/alloc.h"

typedef struct dctx {
    const merp_lsys *ls;
    const merp_ls_table *tab; /* the section being applied */
    const merp_lstr *in;
    const size_t *match;
    int *cand; /* matching stochastic productions of one module */
    double vars[MERP_LS_MAXVARS];
} dctx;

/* Binds the formal parameters of pattern `p` to the parameters of module j;
 * 0 when the symbol or the parameter count differs. */
static int bind(dctx *d, const merp_ls_pat *p, size_t j)
{
    const merp_lstr *s = d->in;
    if (s->sym[j] != p->sym || merp_lstr_np(s, j) != p->nf)
        return 0;
    const float *par = s->par + s->poff[j];
    for (unsigned k = 0; k < p->nf; k++)
        d->vars[p->slot + k] = (double)par[k];
    return 1;
}

static int match_left(dctx *d, const merp_ls_prod *pr, size_t i)
{
    const merp_lstr *s = d->in;
    size_t j = i;
    for (int k = pr->nlc - 1; k >= 0; k--) {
        for (;;) {
            if (j == 0)
                return 0;
            j--;
            merp_sym y = s->sym[j];
            if (y == ']') {
                if (d->match[j] == SIZE_MAX)
                    return 0;
                j = d->match[j];
            } else if (y != '[' && !d->ls->skip[y]) {
                break;
            }
        }
        if (!bind(d, &pr->lc[k], j))
            return 0;
    }
    return 1;
}

/* Moves j past ignored symbols and child branches to the next module of the
 * same branch; 0 at the end of the branch or string. */
static int next_module(dctx *d, size_t *j)
{
    const merp_lstr *s = d->in;
    while (*j < s->n) {
        merp_sym y = s->sym[*j];
        if (y == ']')
            return 0;
        if (y == '[') {
            if (d->match[*j] == SIZE_MAX)
                return 0;
            *j = d->match[*j] + 1;
        } else if (d->ls->skip[y]) {
            (*j)++;
        } else {
            return 1;
        }
    }
    return 0;
}

static int match_right(dctx *d, const merp_ls_prod *pr, size_t i)
{
    const merp_lstr *s = d->in;
    size_t j = i + 1;
    for (int k = 0; k < pr->nrc; k++) {
        merp_sym want = pr->rc[k].sym;
        if (want == '[') {
            while (j < s->n && s->sym[j] != '[' && s->sym[j] != ']' &&
                   d->ls->skip[s->sym[j]])
                j++;
            if (j >= s->n || s->sym[j] != '[')
                return 0;
            j++;
        } else if (want == ']') {
            while (j < s->n && s->sym[j] != ']')
                j = s->sym[j] == '[' && d->match[j] != SIZE_MAX ? d->match[j] + 1 : j + 1;
            if (j >= s->n)
                return 0;
            j++;
        } else {
            if (!next_module(d, &j) || !bind(d, &pr->rc[k], j))
                return 0;
            j++;
        }
    }
    return 1;
}

/* Whether pr's predecessor and contexts match module i (binding variables). */
static int matches(dctx *d, const merp_ls_prod *pr, size_t i)
{
    return bind(d, &pr->pred, i) && (pr->nlc == 0 || match_left(d, pr, i)) &&
           (pr->nrc == 0 || match_right(d, pr, i));
}

static int applies(dctx *d, const merp_ls_prod *pr, size_t i, merp_ls_rand *rnd)
{
    return matches(d, pr, i) &&
           (!pr->cond || merp_expr_eval(pr->cond, d->vars, rnd) != 0.0);
}

/* The production for module i, its variables bound; NULL when none applies. */
static const merp_ls_prod *choose(dctx *d, size_t i, merp_ls_rand *rnd)
{
    const merp_lsys *ls = d->ls;
    const merp_ls_table *tab = d->tab;
    merp_sym y = d->in->sym[i];
    int ncand = 0;
    double total = 0.0;
    for (int k = tab->head_off[y]; k < tab->head_off[y + 1]; k++) {
        const merp_ls_prod *pr = &ls->prods[tab->by_head[k]];
        if ((ncand > 0 && !pr->has_prob) || !applies(d, pr, i, rnd))
            continue;
        if (!pr->has_prob)
            return pr;
        d->cand[ncand++] = tab->by_head[k];
        total += pr->prob;
    }
    if (ncand == 0 || !(total > 0.0))
        return NULL;
    double u = merp_ls_uniform(rnd) * total;
    int c = 0;
    for (; c < ncand - 1; c++) {
        if (u < ls->prods[d->cand[c]].prob)
            break;
        u -= ls->prods[d->cand[c]].prob;
    }
    /* Rounding can run past the last positive weight: step back to it. */
    while (c > 0 && ls->prods[d->cand[c]].prob <= 0.0)
        c--;
    const merp_ls_prod *pick = &ls->prods[d->cand[c]];
    matches(d, pick, i); /* rebinds the variables of the chosen one */
    return pick;
}

static int produce(dctx *d, const merp_ls_prod *pr, merp_lstr *out, merp_ls_rand *rnd)
{
    float a[MERP_LS_MAXARGS];
    for (int m = 0; m < pr->nsucc; m++) {
        const merp_ls_out *o = &pr->succ[m];
        for (unsigned k = 0; k < o->nargs; k++)
            a[k] = (float)merp_expr_eval(pr->args[o->arg0 + k], d->vars, rnd);
        if (merp_lstr_push(out, o->sym, a, o->nargs))
            return -1;
    }
    return 0;
}

/* Whether any production has a left or right context: only then does matching
 * need the brackets' partners. */
static int context_sensitive(const merp_lsys *ls)
{
    for (int k = 0; k < ls->nprod; k++)
        if (ls->prods[k].nlc > 0 || ls->prods[k].nrc > 0)
            return 1;
    return 0;
}

/* Room for the output of one step, an upper bound from one pass over the
 * symbols: a module becomes at most the longest successor of its productions
 * (modules and parameters), or stays itself. Reserving it saves the copies of a
 * doubling growth; pages never written are never touched. */
static int reserve_output(const merp_lsys *ls, const merp_lstr *in, merp_lstr *out)
{
    uint32_t msucc[MERP_LS_NSYM] = {0}, mpar[MERP_LS_NSYM] = {0};
    for (int k = 0; k < ls->nprod; k++) {
        const merp_ls_prod *pr = &ls->prods[k];
        uint32_t np = 0;
        if (pr->section != MERP_LS_PRODUCTIONS)
            continue;
        for (int m = 0; m < pr->nsucc; m++)
            np += pr->succ[m].nargs;
        merp_sym y = pr->pred.sym;
        msucc[y] = msucc[y] > (uint32_t)pr->nsucc ? msucc[y] : (uint32_t)pr->nsucc;
        mpar[y] = mpar[y] > np ? mpar[y] : np;
    }
    size_t n = 0, npar = 0;
    for (size_t i = 0; i < in->n; i++) {
        merp_sym y = in->sym[i];
        uint32_t np = merp_lstr_np(in, i);
        n += msucc[y] > 1 ? msucc[y] : 1;
        npar += mpar[y] > np ? mpar[y] : np;
    }
    return merp_lstr_reserve(out, n, npar);
}

int merp_lsys_derive(const merp_lsys *ls, const merp_lstr *in, merp_lstr *out,
                     uint64_t seed, uint32_t step)
{
    assert(ls && in && out && in != out);
    merp_lstr_clear(out);
    int ctx = context_sensitive(ls);
    size_t *match = ctx ? merp_malloc((in->n ? in->n : 1) * sizeof *match) : NULL;
    int *cand = merp_malloc(((size_t)ls->nprod + 1) * sizeof *cand);
    dctx *d = merp_malloc(sizeof *d);
    int rc = ((ctx && (!match || merp_lstr_brackets(in, match))) || !cand || !d ||
              reserve_output(ls, in, out))
                 ? -1
                 : 0;
    const merp_ls_table *tab = &ls->tab[MERP_LS_PRODUCTIONS];
    if (d)
        *d = (dctx){.ls = ls, .tab = tab, .in = in, .match = match, .cand = cand};
    for (size_t i = 0; !rc && i < in->n; i++) {
        if (tab->head_off[in->sym[i]] == tab->head_off[in->sym[i] + 1]) {
            rc = merp_lstr_push(out, in->sym[i], in->par + in->poff[i], merp_lstr_np(in, i));
            continue;
        }
        merp_ls_rand rnd = {merp_ls_key(seed, step, i), 0};
        const merp_ls_prod *pr = choose(d, i, &rnd);
        if (pr)
            rc = produce(d, pr, out, &rnd);
        else
            rc = merp_lstr_push(out, in->sym[i], in->par + in->poff[i],
                                merp_lstr_np(in, i));
    }
    merp_free(match);
    merp_free(cand);
    merp_free(d);
    return rc;
}

/* ---- decomposition and homomorphism ---- */

typedef struct sub {
    dctx d;
    merp_lstr *lvl;  /* the successor being expanded at each depth */
    merp_lstr *out;
    uint32_t *map;   /* homomorphism only: out's origins */
    size_t mcap;
    uint32_t top;    /* the module of the input being expanded */
} sub;

static int emit(sub *x, const merp_lstr *in, size_t i, int depth)
{
    if (x->map) {
        size_t n = x->out->n;
        if (n == x->mcap) {
            size_t c = x->mcap ? 2 * x->mcap : 256;
            uint32_t *q = merp_realloc(x->map, c * sizeof *q);
            if (!q)
                return -1;
            x->map = q, x->mcap = c;
        }
        x->map[n] = x->top | (depth > 0 ? MERP_LS_PRODUCED : 0);
    }
    return merp_lstr_push(x->out, in->sym[i], in->par + in->poff[i], merp_lstr_np(in, i));
}

/* Module i of `in`, at `depth`, rewritten recursively into x->out. */
static int expand(sub *x, const merp_lstr *in, size_t i, int depth, uint64_t key)
{
    const merp_ls_table *tab = x->d.tab;
    merp_sym y = in->sym[i];
    if (depth >= tab->depth || tab->head_off[y] == tab->head_off[y + 1])
        return emit(x, in, i, depth);
    merp_ls_rand rnd = {key, 0};
    x->d.in = in;
    const merp_ls_prod *pr = choose(&x->d, i, &rnd);
    if (!pr)
        return emit(x, in, i, depth);
    merp_lstr *buf = &x->lvl[depth];
    merp_lstr_clear(buf);
    if (produce(&x->d, pr, buf, &rnd))
        return -1;
    for (size_t j = 0; j < buf->n; j++)
        if (expand(x, buf, j, depth + 1, merp_ls_key(key, (uint32_t)depth + 1, j)))
            return -1;
    return 0;
}

/* Section `sect` applied to every module of `in`, into `out`. */
static int rewrite(const merp_lsys *ls, int sect, const merp_lstr *in, merp_lstr *out,
                   uint32_t **map, uint64_t seed, uint32_t step)
{
    assert(ls && in && out && in != out);
    merp_lstr_clear(out);
    const merp_ls_table *tab = &ls->tab[sect];
    sub x = {.d = {.ls = ls, .tab = tab}, .out = out};
    x.d.cand = merp_malloc(((size_t)ls->nprod + 1) * sizeof *x.d.cand);
    x.lvl = merp_calloc((size_t)tab->depth, sizeof *x.lvl);
    int rc = x.d.cand && x.lvl && (!map || (x.map = merp_malloc(256 * sizeof *x.map)))
                 ? merp_lstr_reserve(out, in->n, in->npar)
                 : -1;
    x.mcap = x.map ? 256 : 0;
    for (size_t i = 0; !rc && i < in->n; i++) {
        x.top = (uint32_t)i;
        rc = expand(&x, in, i, 0, merp_ls_key(seed, step, i));
    }
    for (int k = 0; x.lvl && k < tab->depth; k++)
        merp_lstr_free(&x.lvl[k]);
    merp_free(x.lvl);
    merp_free(x.d.cand);
    if (rc) {
        merp_free(x.map);
        x.map = NULL;
    }
    if (map)
        *map = x.map;
    return rc;
}

/* Keys of the decomposition's and the homomorphism's draws, apart from the
 * derivation's. */
#define DECOMPOSITION_KEY UINT64_C(0x6465636f6d706f73)
#define HOMOMORPHISM_KEY UINT64_C(0x686f6d6f6d6f7270)

int merp_lsys_decompose(const merp_lsys *ls, const merp_lstr *in, merp_lstr *out,
                        uint64_t seed, uint32_t step)
{
    return rewrite(ls, MERP_LS_DECOMPOSITION, in, out, NULL, seed ^ DECOMPOSITION_KEY, step);
}

int merp_lsys_homomorphism(const merp_lsys *ls, const merp_lstr *in, merp_lstr *out,
                           uint32_t **map, uint64_t seed, uint32_t step)
{
    assert(map);
    return rewrite(ls, MERP_LS_HOMOMORPHISM, in, out, map, seed ^ HOMOMORPHISM_KEY, step);
}

/* The decomposition of `s` in place, when the text has one. */
static int decompose_in_place(const merp_lsys *ls, merp_lstr *s, merp_lstr *tmp,
                              uint64_t seed, uint32_t step)
{
    if (ls->tab[MERP_LS_DECOMPOSITION].nprod == 0)
        return 0;
    int rc = merp_lsys_decompose(ls, s, tmp, seed, step);
    merp_lstr_swap(s, tmp);
    return rc;
}

int merp_lsys_run(const merp_lsys *ls, int n, uint64_t seed, merp_lstr *out)
{
    assert(ls && out && n >= 0);
    merp_lstr tmp;
    merp_lstr_init(&tmp);
    int rc = merp_lstr_copy(out, &ls->axiom);
    if (!rc)
        rc = decompose_in_place(ls, out, &tmp, seed, UINT32_MAX);
    for (int t = 0; !rc && t < n; t++) {
        rc = merp_lsys_derive(ls, out, &tmp, seed, (uint32_t)t);
        merp_lstr_swap(out, &tmp);
        if (!rc)
            rc = decompose_in_place(ls, out, &tmp, seed, (uint32_t)t);
    }
    merp_lstr_free(&tmp);
    return rc;
}
