/* meristem — an L-system's string and the shared skeleton: the turtle's segments
 * become internodes (with joints where a segment has more than two branches),
 * and prunes and bends of the skeleton are folded back into the string. The
 * choices are in model_private.h. */
#include "config.h"

#include <assert.h>
#include <math.h>
#include <string.h>

#include "core/alloc.h"
#include "core/array.h"
#include "models/lsystem/model_private.h"

merp_ls_turtle merp_lsm_turtle(const mer_params *p)
{
    merp_ls_turtle t = merp_ls_turtle_default();
    t.delta = (double)p->ls_delta;
    t.step = (double)p->ls_step;
    t.width = (double)p->ls_width;
    t.elasticity = (double)p->ls_elasticity;
    return t;
}

/* ---- the string through the homomorphism, queries answered ---- */

/* ?E: Q and whether the point is blocked (model_private.h). */
static void env_answer(void *ctx, const double pos[3], const double head[3], float *par,
                       unsigned np)
{
    const merp_world *w = ctx;
    (void)head;
    float p[3] = {(float)pos[0], (float)pos[1], (float)pos[2]};
    if (np > 0) {
        par[0] = w->p->shadow_c + w->p->shadow_a;
        if (w->env->shadow != NULL) {
            uint32_t cell = merp_env_cell(w->env, p);
            merp_env_light_cells(w->env, &cell, 1, &par[0]);
        }
    }
    if (np > 1)
        par[1] = merp_env_blocked(w->env, p) ? 1.0f : 0.0f;
}

/* The answers to the string's own query modules, from the homomorphism's
 * output `view` back into m->str. */
static void copy_answers(merp_model *m, const merp_lstr *view, const uint32_t *map)
{
    for (size_t j = 0; j < view->n; j++) {
        if (view->sym[j] < 256 || (map[j] & MERP_LS_PRODUCED))
            continue;
        unsigned np = merp_lstr_np(view, j);
        memcpy(m->str.par + m->str.poff[map[j]], view->par + view->poff[j], np * sizeof(float));
    }
}

int merp_lsm_interpret(merp_model *m, const merp_world *w, merp_ls_segs *segs)
{
    merp_ls_turtle tp = merp_lsm_turtle(w->p);
    int homo = merp_lsys_section_size(m->ls, MERP_LS_HOMOMORPHISM) > 0;
    int ask = merp_lsys_has_queries(m->ls);
    if (!homo && !ask)
        return merp_ls_interpret(&m->str, &tp, segs);
    merp_lstr view;
    merp_lstr_init(&view);
    uint32_t *map = NULL;
    const merp_lstr *s = &m->str;
    int rc = 0;
    if (homo) {
        rc = merp_lsys_homomorphism(m->ls, &m->str, &view, &map, m->seed, m->dstep);
        s = &view;
    }
    merp_ls_query q = {.par = s->par, .env = env_answer, .ctx = (void *)w};
    for (int k = 0; k < 3; k++)
        q.origin[k] = (double)m->base[k];
    if (rc == 0)
        rc = merp_ls_interpret_query(s, &tp, ask ? &q : NULL, segs);
    if (rc == 0 && homo) {
        for (size_t k = 0; k < segs->n; k++)
            segs->seg[k].module = map[segs->seg[k].module] & ~MERP_LS_PRODUCED;
        if (ask)
            copy_answers(m, &view, map);
    }
    merp_free(map);
    merp_lstr_free(&view);
    return rc;
}

/* ---- segments onto the skeleton ---- */

typedef struct node_spec {
    float pos[3], dir[3], side[3];
    float len, width;
    uint32_t order, module;
} node_spec;

static mer_result add_node(merp_model *m, const merp_world *w, const node_spec *ns,
                           uint32_t parent, uint32_t slot, uint32_t *out, mer_error *err)
{
    merp_skeleton *sk = w->sk;
    uint32_t id;
    mer_result rc = merp_skel_node_new(sk, w->step, &id, err);
    if (rc != MER_OK)
        return rc;
    if (id >= m->ncap) {
        uint32_t cap = m->ncap ? 2 * m->ncap : 256;
        if (!MERP_RESIZE(m->module, cap) || !MERP_RESIZE(m->frame, 6 * (size_t)cap) ||
            !MERP_RESIZE(m->width, cap))
            return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the L-system's nodes");
        m->ncap = cap;
    }
    memcpy(sk->pos + 3 * id, ns->pos, sizeof ns->pos);
    memcpy(sk->dir + 3 * id, ns->dir, sizeof ns->dir);
    memcpy(sk->side + 3 * id, ns->side, sizeof ns->side);
    memcpy(m->frame + 6 * id, ns->dir, sizeof ns->dir);
    memcpy(m->frame + 6 * id + 3, ns->side, sizeof ns->side);
    sk->len[id] = ns->len;
    sk->order[id] = ns->order;
    m->module[id] = ns->module;
    m->width[id] = ns->width;
    m->nn = id + 1;
    *out = id;
    if (parent == MER_NO_NODE)
        return merp_skel_add_root(sk, id, err);
    sk->parent[id] = parent;
    sk->slot[id] = (uint8_t)slot;
    sk->plant[id] = sk->plant[parent];
    sk->child[3 * parent + slot] = id;
    return MER_OK;
}

/* A joint at the tip of node `at`, in its slot 0 (model_private.h). */
static mer_result add_joint(merp_model *m, const merp_world *w, uint32_t at, uint32_t *out,
                            mer_error *err)
{
    const merp_skeleton *sk = w->sk;
    node_spec ns = {.len = 0.0f, .width = m->width[at], .order = sk->order[at],
                    .module = MERP_LS_JOINT};
    merp_skel_node_end(sk, at, ns.pos);
    memcpy(ns.dir, sk->dir + 3 * at, sizeof ns.dir);
    memcpy(ns.side, sk->side + 3 * at, sizeof ns.side);
    return add_node(m, w, &ns, at, 0, out, err);
}

static void spec_of(const merp_model *m, const merp_ls_seg *g, const mer_params *p,
                    uint32_t module, node_spec *ns)
{
    float d[3], len2 = 0.0f;
    for (int k = 0; k < 3; k++) {
        d[k] = g->tip[k] - g->base[k];
        len2 += d[k] * d[k];
        ns->pos[k] = m->base[k] + g->base[k];
    }
    ns->len = sqrtf(len2);
    for (int k = 0; k < 3; k++) /* F(0) keeps the heading as its direction */
        ns->dir[k] = ns->len > 1e-6f ? d[k] / ns->len : g->head[k];
    memcpy(ns->side, g->left, sizeof ns->side);
    ns->width = g->width > 0.0f ? g->width * p->ls_width_scale : 0.0f;
    ns->order = g->order;
    ns->module = module;
}

/* Marks in `tail` a segment not drawn (ls_blocking). */
#define BLOCKED (UINT32_MAX - 1)

/* Whether the ground or an obstacle stops segment g (its end inside), or
 * stopped its parent. */
static int blocked(const merp_world *w, const merp_ls_seg *g, const node_spec *ns,
                   const uint32_t *tail)
{
    if (!w->p->ls_blocking)
        return 0;
    if (g->parent != UINT32_MAX && tail[g->parent] == BLOCKED)
        return 1;
    float end[3];
    for (int k = 0; k < 3; k++)
        end[k] = ns->pos[k] + ns->dir[k] * ns->len;
    return merp_env_blocked(w->env, end);
}

mer_result merp_lsm_build(merp_model *m, const merp_world *w, const merp_ls_segs *segs,
                          mer_error *err)
{
    merp_skeleton *sk = w->sk;
    uint32_t *tail = merp_malloc((segs->n ? segs->n : 1) * sizeof *tail);
    if (tail == NULL)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the L-system's nodes");
    merp_skel_reset(sk);
    m->nn = 0;
    mer_result rc = MER_OK;
    for (size_t k = 0; k < segs->n && rc == MER_OK; k++) {
        const merp_ls_seg *g = &segs->seg[k];
        node_spec ns;
        spec_of(m, g, w->p, g->module, &ns);
        if (blocked(w, g, &ns, tail)) {
            tail[k] = BLOCKED;
            continue;
        }
        uint32_t at = g->parent == UINT32_MAX ? MER_NO_NODE : tail[g->parent], slot = 0;
        if (at != MER_NO_NODE && g->order != sk->order[at]) { /* a branch */
            if (sk->child[3 * at + 1] == MER_NO_NODE)
                slot = 1;
            else if (sk->child[3 * at + 2] == MER_NO_NODE)
                slot = 2;
            else if ((rc = add_joint(m, w, at, &at, err)) == MER_OK) {
                tail[g->parent] = at;
                slot = 1;
            }
        } else if (at != MER_NO_NODE && sk->child[3 * at] != MER_NO_NODE) {
            rc = mer_error_set(err, MER_ERR_INTERNAL, NULL, "two main continuations of node %u",
                               (unsigned)at);
        }
        if (rc == MER_OK)
            rc = add_node(m, w, &ns, at, slot, &tail[k], err);
    }
    merp_free(tail);
    return rc;
}

void merp_lsm_diameters(const merp_model *m, const merp_world *w)
{
    merp_skeleton *sk = w->sk;
    uint32_t n = m->nn < sk->n ? m->nn : sk->n;
    for (uint32_t i = 0; i < n; i++)
        if (sk->alive[i] && m->width[i] > 0.0f)
            sk->dn[i] = powf(m->width[i], sk->pipe_n);
}

/* ---- edits back into the string ---- */

/* A frame as the columns H, L, U = H × L of a 3×3 matrix (row-major). */
static void frame_of(const float *h, const float *l, double f[9])
{
    for (int r = 0; r < 3; r++) {
        f[3 * r] = (double)h[r];
        f[3 * r + 1] = (double)l[r];
    }
    f[2] = f[3] * f[7] - f[6] * f[4];
    f[5] = f[6] * f[1] - f[0] * f[7];
    f[8] = f[0] * f[4] - f[3] * f[1];
}

/* out = a · b, or aᵀ · b when `ta`. */
static void mul(const double a[9], const double b[9], int ta, double out[9])
{
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) {
            double v = 0.0;
            for (int k = 0; k < 3; k++)
                v += (ta ? a[3 * k + r] : a[3 * r + k]) * b[3 * k + c];
            out[3 * r + c] = v;
        }
}

/* The turtle turns +(a) &(b) \(c), in degrees, that take the frame to the one
 * whose H and L are the first two columns of `c` in the frame's own axes. */
static void turns_of(const double c[9], float abc[3])
{
    double a = atan2(c[3], c[0]), b = atan2(-c[6], hypot(c[0], c[3]));
    double l2[3] = {-sin(a), cos(a), 0.0};
    double u2[3] = {sin(b) * cos(a), sin(b) * sin(a), cos(b)};
    double lu = c[1] * u2[0] + c[4] * u2[1] + c[7] * u2[2];
    double ll = c[1] * l2[0] + c[4] * l2[1] + c[7] * l2[2];
    abc[0] = (float)(a * 180.0 / M_PI);
    abc[1] = (float)(b * 180.0 / M_PI);
    abc[2] = (float)(atan2(lu, ll) * 180.0 / M_PI);
}

typedef struct fold_plan {
    size_t *cut;   /* per module: 1 + the end of the branch cut from it, 0: none */
    float *turn;   /* 3 per module: +, &, \ to insert before it */
    uint8_t *has;  /* per module: turn holds one */
    double *rot;   /* 9 per node: the node's frame now times its frame as drawn, transposed */
} fold_plan;

/* The cut and the turn, if any, that node i asks for (nodes in id order). */
static void plan_node(const merp_model *m, const merp_skeleton *sk, uint32_t i, fold_plan *fp)
{
    static const double eye[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    uint32_t par = sk->parent[i], mod = m->module[i];
    const double *rp = par == MER_NO_NODE ? eye : fp->rot + 9 * (size_t)par;
    double *ri = fp->rot + 9 * (size_t)i;
    memcpy(ri, rp, 9 * sizeof *ri);
    if (!sk->alive[i]) {
        if (mod != MERP_LS_JOINT &&
            (par == MER_NO_NODE || sk->alive[par] || m->module[par] == MERP_LS_JOINT))
            fp->cut[mod] = 1 + merp_lstr_branch_end(&m->str, mod);
        return;
    }
    const float *f0 = m->frame + 6 * (size_t)i;
    if (mod == MERP_LS_JOINT || (rp == eye && memcmp(f0, sk->dir + 3 * i, 3 * sizeof *f0) == 0 &&
                                 memcmp(f0 + 3, sk->side + 3 * i, 3 * sizeof *f0) == 0))
        return;
    double drawn[9], now[9], expect[9], c[9];
    frame_of(f0, f0 + 3, drawn);
    frame_of(sk->dir + 3 * i, sk->side + 3 * i, now);
    mul(rp, drawn, 0, expect);
    mul(expect, now, 1, c);
    float abc[3];
    turns_of(c, abc);
    double tr[9] = {drawn[0], drawn[3], drawn[6], drawn[1], drawn[4], drawn[7],
                    drawn[2], drawn[5], drawn[8]};
    mul(now, tr, 0, ri);
    if (fabsf(abc[0]) + fabsf(abc[1]) + fabsf(abc[2]) > 1e-3f) {
        memcpy(fp->turn + 3 * (size_t)mod, abc, sizeof abc);
        fp->has[mod] = 1;
    }
}

/* Whether any node was pruned or turned since the drawing. */
static int any_edit(const merp_model *m, const merp_skeleton *sk, uint32_t nn)
{
    for (uint32_t i = 0; i < nn; i++)
        if (!sk->alive[i] || memcmp(m->frame + 6 * (size_t)i, sk->dir + 3 * i, 3 * sizeof(float)) ||
            memcmp(m->frame + 6 * (size_t)i + 3, sk->side + 3 * i, 3 * sizeof(float)))
            return 1;
    return 0;
}

static int write_folded(const merp_lstr *s, const fold_plan *fp, merp_lstr *out)
{
    static const merp_sym turn_sym[3] = {'+', '&', '\\'};
    for (size_t j = 0; j < s->n; j++) {
        if (fp->cut[j]) {
            j = fp->cut[j] - 2; /* the loop steps to the branch's ']' */
            continue;
        }
        for (int k = 0; fp->has[j] && k < 3; k++)
            if (fp->turn[3 * j + k] != 0.0f &&
                merp_lstr_push(out, turn_sym[k], &fp->turn[3 * j + k], 1))
                return -1;
        if (merp_lstr_push(out, s->sym[j], s->par + s->poff[j], merp_lstr_np(s, j)))
            return -1;
    }
    return 0;
}

int merp_lsm_fold(const merp_model *m, const merp_world *w, merp_lstr *out, int *changed)
{
    const merp_skeleton *sk = w->sk;
    merp_lstr_clear(out);
    /* Nodes past the drawing (a plant added by hand) go at the next drawing. */
    uint32_t nn = m->nn < sk->n ? m->nn : sk->n;
    *changed = any_edit(m, sk, nn);
    if (!*changed)
        return 0;
    size_t n = m->str.n ? m->str.n : 1;
    fold_plan fp = {merp_calloc(n, sizeof *fp.cut), merp_calloc(3 * n, sizeof *fp.turn),
                    merp_calloc(n, 1), merp_malloc(9 * ((size_t)m->nn + 1) * sizeof *fp.rot)};
    int rc = fp.cut && fp.turn && fp.has && fp.rot ? 0 : -1;
    for (uint32_t i = 0; rc == 0 && i < nn; i++)
        plan_node(m, sk, i, &fp);
    if (rc == 0)
        rc = write_folded(&m->str, &fp, out);
    merp_free(fp.cut);
    merp_free(fp.turn);
    merp_free(fp.has);
    merp_free(fp.rot);
    return rc;
}
