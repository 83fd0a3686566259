/* meristem — the L-system growth model (ABOP chapters 1–2, cpfg's syntax): its
 * ops table. The definition is the cpfg text; one step is one derivation step,
 * then the turtle draws the whole string onto the skeleton (draw.c). How nodes,
 * joints, prune and bend map onto the string: model_private.h. */
#include "config.h"

#include <assert.h>
#include <stdio.h>
#include <string.h>

#include "core/alloc.h"
#include "core/array.h"
#include "core/bytes.h"
#include "core/hash.h"
#include "models/lsystem/lsystem_private.h"
#include "models/lsystem/model_private.h"

#define NOMEM(err) mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the L-system")

static mer_result ls_create(const mer_params *p, merp_model **out, mer_error *err)
{
    (void)p;
    assert(out != NULL);
    *out = merp_calloc(1, sizeof **out);
    if (*out == NULL)
        return NOMEM(err);
    merp_lstr_init(&(*out)->str);
    return MER_OK;
}

static void ls_free(merp_model *m)
{
    if (m == NULL)
        return;
    merp_free(m->text);
    merp_lsys_free(m->ls);
    merp_lstr_free(&m->str);
    merp_free(m->module);
    merp_free(m->frame);
    merp_free(m->width);
    merp_free(m);
}

/* Parses `len` bytes of text into *ls and a NUL-terminated copy into *text. */
static mer_result parse(const char *src, size_t len, char **text, merp_lsys **ls, mer_error *err)
{
    *text = merp_malloc(len + 1);
    if (*text == NULL)
        return NOMEM(err);
    memcpy(*text, src, len);
    (*text)[len] = '\0';
    merp_ls_error le = {0};
    *ls = strlen(*text) == len ? merp_lsys_parse(*text, &le) : NULL;
    if (*ls != NULL)
        return MER_OK;
    merp_free(*text);
    *text = NULL;
    if (memchr(src, '\0', len) != NULL)
        return mer_error_set(err, MER_ERR_INVALID, "definition", "the L-system holds a NUL byte");
    if (le.line == 0 || strcmp(le.msg, "out of memory") == 0)
        return NOMEM(err);
    mer_result rc = mer_error_set(err, MER_ERR_INVALID, "definition", "line %d, column %d: %s",
                                  le.line, le.col, le.msg);
    if (err != NULL) {
        err->line = (unsigned)le.line;
        err->column = (unsigned)le.col;
    }
    return rc;
}

/* The derivation step the axiom's decomposition is keyed with (merp_lsys_run's). */
#define AXIOM_STEP UINT32_MAX

/* The decomposition of `s` in place, when the text has one. 0, or -1 when out
 * of memory (s unchanged). */
static int decompose_with(const merp_lsys *ls, merp_lstr *s, uint64_t seed, uint32_t step)
{
    if (merp_lsys_section_size(ls, MERP_LS_DECOMPOSITION) == 0)
        return 0;
    merp_lstr out;
    merp_lstr_init(&out);
    int rc = merp_lsys_decompose(ls, s, &out, seed, step);
    if (rc == 0)
        merp_lstr_swap(s, &out);
    merp_lstr_free(&out);
    return rc;
}

/* The turtle's drawing of m->str onto the skeleton. */
static mer_result draw(merp_model *m, const merp_world *w, mer_error *err)
{
    merp_ls_segs segs = {0};
    mer_result rc = MER_OK;
    if (merp_lsm_interpret(m, w, &segs))
        rc = NOMEM(err);
    else if (segs.n > MER_NODES_MAX)
        rc = mer_error_set(err, MER_ERR_LIMIT, "nodes", "the L-system draws %zu internodes, more than %u",
                           segs.n, (unsigned)MER_NODES_MAX);
    if (rc == MER_OK)
        rc = merp_lsm_build(m, w, &segs, err);
    merp_ls_segs_free(&segs);
    return rc;
}

static mer_result ls_set_definition(merp_model *m, const merp_world *w, const char *src,
                                    size_t len, mer_error *err)
{
    assert(m != NULL && w != NULL && src != NULL);
    char *text;
    merp_lsys *ls;
    mer_result rc = parse(src, len, &text, &ls, err);
    if (rc != MER_OK)
        return rc;
    int first = m->text == NULL;
    mer_rng peek = *w->rng; /* the seed drawn below, for the axiom's decomposition */
    uint64_t seed = mer_rng_next(&peek);
    if (first && (merp_lstr_copy(&m->str, merp_lsys_axiom(ls)) ||
                  decompose_with(ls, &m->str, seed, AXIOM_STEP))) {
        merp_free(text);
        merp_lsys_free(ls);
        return NOMEM(err);
    }
    merp_free(m->text);
    merp_lsys_free(m->ls);
    m->text = text;
    m->tlen = len;
    m->ls = ls;
    if (!first)
        return MER_OK; /* the string and the drawing stay */
    /* The plant stands where the scene's first seedling was put. */
    const merp_skeleton *sk = w->sk;
    if (sk->nplants > 0)
        memcpy(m->base, sk->pos + 3 * sk->roots[0], sizeof m->base);
    m->seed = mer_rng_next(w->rng);
    assert(m->seed == seed);
    m->dstep = 0;
    return draw(m, w, err);
}

static const char *ls_definition(const merp_model *m, size_t *len)
{
    if (len != NULL)
        *len = m->tlen;
    return m->text;
}

/* 1 once derived as far as the text's `derivation length:` asks. */
static int ls_finished(const merp_model *m, const mer_params *p)
{
    (void)p;
    int dlen = m->ls != NULL ? merp_lsys_derivation_length(m->ls) : 0;
    return dlen > 0 && m->dstep >= (uint32_t)dlen;
}

static mer_result ls_step(merp_model *m, const merp_world *w, mer_error *err)
{
    assert(m != NULL && w != NULL);
    if (m->ls == NULL)
        return mer_error_set(err, MER_ERR_INVALID, "definition",
                             "an L-system scene grows once it has its source");
    if (ls_finished(m, w->p))
        return MER_OK;
    merp_lstr folded, next;
    merp_lstr_init(&folded);
    merp_lstr_init(&next);
    int changed = 0;
    mer_result rc = MER_OK;
    if (merp_lsm_fold(m, w, &folded, &changed) ||
        merp_lsys_derive(m->ls, changed ? &folded : &m->str, &next, m->seed, m->dstep) ||
        decompose_with(m->ls, &next, m->seed, m->dstep))
        rc = NOMEM(err);
    else if (next.n > MERP_LS_MODULES_MAX)
        rc = mer_error_set(err, MER_ERR_LIMIT, "nodes",
                           "the L-system's string would hold %zu modules, more than %u", next.n,
                           (unsigned)MERP_LS_MODULES_MAX);
    if (rc == MER_OK) {
        merp_lstr_swap(&m->str, &next);
        m->dstep++;
        rc = draw(m, w, err);
    }
    merp_lstr_free(&folded);
    merp_lstr_free(&next);
    return rc;
}

static size_t ls_warnings(const merp_model *m, mer_warning *out, size_t cap)
{
    if (m->ls == NULL)
        return 0;
    const merp_ls_error *w;
    size_t n = (size_t)merp_lsys_warnings(m->ls, &w);
    for (size_t i = 0; i < n && i < cap && i < MERP_LS_WARN_MAX; i++) {
        out[i].line = (unsigned)w[i].line;
        out[i].column = (unsigned)w[i].col;
        snprintf(out[i].message, sizeof out[i].message, "%s", w[i].msg);
    }
    return n;
}

static void ls_diameters(const merp_model *m, const merp_world *w)
{
    merp_lsm_diameters(m, w);
}

static uint64_t hash_string(const merp_lstr *s, uint64_t h)
{
    h = merp_fnv(h, &s->n, sizeof s->n);
    if (s->n == 0)
        return h;
    h = merp_fnv(h, s->sym, s->n * sizeof *s->sym);
    h = merp_fnv(h, s->poff, (s->n + 1) * sizeof *s->poff);
    return merp_fnv(h, s->par, s->npar * sizeof *s->par);
}

static uint64_t ls_hash(const merp_model *m, uint64_t h)
{
    h = merp_fnv(h, &m->tlen, sizeof m->tlen);
    if (m->text != NULL)
        h = merp_fnv(h, m->text, m->tlen);
    h = merp_fnv(h, &m->dstep, sizeof m->dstep);
    h = merp_fnv(h, &m->seed, sizeof m->seed);
    h = merp_fnv(h, m->base, sizeof m->base);
    h = hash_string(&m->str, h);
    h = merp_fnv(h, &m->nn, sizeof m->nn);
    if (m->nn == 0)
        return h;
    h = merp_fnv(h, m->module, m->nn * sizeof *m->module);
    h = merp_fnv(h, m->frame, 6 * (size_t)m->nn * sizeof *m->frame);
    return merp_fnv(h, m->width, m->nn * sizeof *m->width);
}

/* The per-node arrays of `nn` nodes copied from `src`. */
static int copy_nodes(merp_model *c, const merp_model *src)
{
    c->nn = c->ncap = src->nn;
    return MERP_DUP(c->module, src->module, src->nn) &&
           MERP_DUP(c->frame, src->frame, 6 * (size_t)src->nn) &&
           MERP_DUP(c->width, src->width, src->nn);
}

static mer_result ls_clone(const merp_model *m, merp_model **out, mer_error *err)
{
    assert(m != NULL && out != NULL);
    *out = NULL;
    merp_model *c;
    mer_result rc = ls_create(NULL, &c, err);
    if (rc != MER_OK)
        return rc;
    if (m->text != NULL)
        rc = parse(m->text, m->tlen, &c->text, &c->ls, err);
    c->tlen = m->tlen;
    c->dstep = m->dstep;
    c->seed = m->seed;
    memcpy(c->base, m->base, sizeof c->base);
    if (rc == MER_OK && (merp_lstr_copy(&c->str, &m->str) || !copy_nodes(c, m)))
        rc = NOMEM(err);
    if (rc != MER_OK) {
        ls_free(c);
        return rc;
    }
    *out = c;
    return MER_OK;
}

static void ls_save(const merp_model *m, merp_bytes_out *out)
{
    merp_put_u64(out, m->text != NULL ? m->tlen + 1 : 0);
    merp_put(out, m->text, m->text != NULL ? m->tlen : 0);
    merp_put_u32(out, m->dstep);
    merp_put_u64(out, m->seed);
    merp_put(out, m->base, sizeof m->base);
    const merp_lstr *s = &m->str;
    merp_put_u64(out, s->n);
    merp_put_u64(out, s->npar);
    if (s->n > 0) {
        merp_put(out, s->sym, s->n * sizeof *s->sym);
        merp_put(out, s->poff, (s->n + 1) * sizeof *s->poff);
        merp_put(out, s->par, s->npar * sizeof *s->par);
    }
    merp_put_u32(out, m->nn);
    merp_put(out, m->module, m->nn * sizeof *m->module);
    merp_put(out, m->frame, 6 * (size_t)m->nn * sizeof *m->frame);
    merp_put(out, m->width, m->nn * sizeof *m->width);
}

/* The string of a checkpoint, checked: offsets from 0 rising to npar, symbols
 * in range. */
static void load_string(merp_model *m, merp_bytes_in *in)
{
    uint64_t n = merp_get_u64(in), npar = merp_get_u64(in);
    if (n > MERP_LS_MODULES_MAX || npar > UINT32_MAX || (n == 0 && npar != 0))
        in->bad = 1;
    merp_sym *sym = NULL;
    uint32_t *poff = NULL;
    float *par = NULL;
    if (n > 0 && MERP_GET_ARRAY(in, sym, n) && MERP_GET_ARRAY(in, poff, n + 1) &&
        MERP_GET_ARRAY(in, par, npar)) {
        int ok = poff[0] == 0 && poff[n] == npar;
        for (uint64_t i = 0; ok && i < n; i++)
            ok = sym[i] < MERP_LS_NSYM && poff[i] <= poff[i + 1] &&
                 poff[i + 1] - poff[i] <= MERP_LS_MAXARGS;
        for (uint64_t i = 0; ok && i < n; i++)
            if (merp_lstr_push(&m->str, sym[i], par + poff[i], poff[i + 1] - poff[i]))
                in->bad = 2, ok = 0;
        if (!ok && !in->bad)
            in->bad = 1;
    }
    merp_free(sym);
    merp_free(poff);
    merp_free(par);
}

static mer_result ls_load(merp_bytes_in *in, uint32_t nodes, merp_model **out, mer_error *err)
{
    *out = NULL;
    merp_model *m;
    mer_result rc = ls_create(NULL, &m, err);
    if (rc != MER_OK)
        return rc;
    uint64_t tl = merp_get_u64(in);
    char *text = NULL;
    if (tl > in->n - in->at + 1)
        in->bad = 1;
    if (tl > 0 && !in->bad && MERP_GET_ARRAY(in, text, tl - 1))
        rc = parse(text != NULL ? text : "", tl - 1, &m->text, &m->ls, NULL);
    merp_free(text);
    m->tlen = tl > 0 ? tl - 1 : 0;
    m->dstep = merp_get_u32(in);
    m->seed = merp_get_u64(in);
    merp_get(in, m->base, sizeof m->base);
    if (rc == MER_OK && !in->bad)
        load_string(m, in);
    uint32_t nn = merp_get_u32(in);
    if (nn != nodes && !in->bad)
        in->bad = 1;
    m->nn = m->ncap = nn;
    (void)(!in->bad && MERP_GET_ARRAY(in, m->module, nn) &&
           MERP_GET_ARRAY(in, m->frame, 6 * (size_t)nn) && MERP_GET_ARRAY(in, m->width, nn));
    for (uint32_t i = 0; !in->bad && i < nn; i++)
        if (m->module[i] != MERP_LS_JOINT && m->module[i] >= m->str.n)
            in->bad = 1;
    if (rc != MER_OK || in->bad) {
        int oom = rc == MER_ERR_NOMEM || in->bad == 2;
        ls_free(m);
        return oom ? NOMEM(err) : mer_error_set(err, MER_ERR_FORMAT, "model", "damaged L-system state");
    }
    *out = m;
    return MER_OK;
}

static size_t ls_stats(const merp_model *m, mer_model_stat *out, size_t cap)
{
    size_t k = 0;
#define STAT(label, v)                                                       \
    do {                                                                     \
        if (k < cap) {                                                       \
            snprintf(out[k].name, sizeof out[k].name, "%s", label);          \
            out[k].value = (double)(v);                                      \
        }                                                                    \
        k++;                                                                 \
    } while (0)
    STAT("derivation_step", m->dstep);
    STAT("derivation_length", m->ls != NULL ? merp_lsys_derivation_length(m->ls) : 0);
    STAT("string_length", m->str.n);
    uint32_t segments = 0;
    for (uint32_t i = 0; i < m->nn; i++)
        segments += m->module[i] != MERP_LS_JOINT;
    STAT("segments", segments);
    size_t *count = merp_calloc(MERP_LS_NSYM, sizeof *count);
    if (count == NULL)
        return k;
    for (size_t i = 0; i < m->str.n; i++)
        count[m->str.sym[i]]++;
    for (unsigned y = 0; y < MERP_LS_NSYM; y++) {
        if (count[y] == 0)
            continue;
        char label[24];
        if (y >= 256)
            snprintf(label, sizeof label, "modules.?%c", (char)(y - 256));
        else
            snprintf(label, sizeof label, "modules.%c", (char)y);
        STAT(label, count[y]);
    }
#undef STAT
    merp_free(count);
    return k;
}

const merp_model_ops merp_lsystem_ops = {
    .name = "lsystem",
    .param_rows = MERP_ROWS_LSYSTEM,
    .state_version = 1,
    .validate = NULL,
    .create = ls_create,
    /* No set_params, no nodes_changed: the turtle reads the parameters at each
     * drawing, and edits are folded into the string at the next step. */
    .step = ls_step,
    .hash = ls_hash,
    .clone = ls_clone,
    .save = ls_save,
    .load = ls_load,
    .free = ls_free,
    .set_definition = ls_set_definition,
    .definition = ls_definition,
    .warnings = ls_warnings,
    .diameters = ls_diameters,
    .stats = ls_stats,
    .finished = ls_finished,
};
