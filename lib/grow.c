/* meristem — one simulation step (P09 Fig. 3 right): environment, bud fate, new
 * shoots, shedding, pipe-model diameters. See scene.h for the choices made. */
#include "config.h"

#include <stdlib.h>
#include <string.h>

#include <meristem/fate.h>

#include "scene_private.h"
#include "vec_private.h"

static mer_result reserve_buds(mer_scene *s, size_t want, mer_error *err)
{
    if (want <= s->bcap)
        return MER_OK;
    size_t cap = want + want / 2 + 64;
    uint32_t *k = realloc(s->bkey, cap * sizeof *k);
    if (k == NULL)
        goto nomem;
    s->bkey = k;
    float **fl[] = {&s->bpos, &s->bdir, &s->bv};
    for (int i = 0; i < 3; i++) {
        float *f = realloc(*fl[i], cap * 3 * sizeof *f);
        if (f == NULL)
            goto nomem;
        *fl[i] = f;
    }
    float *q = realloc(s->bq, cap * sizeof *q);
    if (q == NULL)
        goto nomem;
    s->bq = q;
    uint8_t *qu = realloc(s->bquiet, cap);
    if (qu == NULL)
        goto nomem;
    s->bquiet = qu;
    s->bcap = cap;
    return MER_OK;
nomem:
    return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for buds");
}

/* Marks (s->mark) the nodes whose buds may grow under the brush constraint. */
static void mark_constraint(mer_scene *s)
{
    uint32_t c = s->child[3 * s->con_node + s->con_slot];
    for (uint32_t i = 0; i < s->n; i++) {
        uint32_t p = s->parent[i];
        s->mark[i] = s->alive[i] && (i == c || (p != MER_NO_NODE && s->mark[p]));
    }
}

static int bud_exists(const mer_scene *s, uint32_t i, uint32_t k)
{
    return s->bud[3 * i + k] == MER_BUD_DORMANT && (k == 0 || k <= s->p.buds_per_node);
}

/* Environment (P09 §4.1): Q and V for every bud that may grow this round. Buds that
 * may not still clear their occupancy zone of markers, and cast shadow. */
static mer_result environment(mer_scene *s, int syllepsis, mer_error *err)
{
    const mer_params *p = &s->p;
    int constrained = s->con_node != MER_NO_NODE;
    if (constrained)
        mark_constraint(s);
    s->bn = 0;
    for (uint32_t i = 0; i < s->n; i++) {
        if (!s->alive[i])
            continue;
        for (uint32_t k = 0; k < 3; k++) {
            s->qb[3 * i + k] = 0.0f;
            s->vb[3 * i + k] = 0.0f;
            if (!bud_exists(s, i, k))
                continue;
            int ok = 1;
            if (syllepsis)
                ok = k > 0 && s->born[i] == s->step;
            if (ok && constrained)
                ok = s->mark[i] || (i == s->con_node && k == s->con_slot);
            /* A bud known to have no marker near it, with no marker added and no
             * bud moved since, can neither take nor remove one: Q = 0, skip it. */
            if (p->environment == MER_ENV_MARKERS && s->quiet[3 * i + k] == s->env_epoch + 1)
                continue;
            float e[3];
            merp_node_end(s, i, e);
            if (!ok) {
                if (p->environment == MER_ENV_MARKERS)
                    mer_markers_remove_sphere(s->markers, e, p->rho);
                continue;
            }
            mer_result rc = reserve_buds(s, s->bn + 1, err);
            if (rc != MER_OK)
                return rc;
            size_t b = s->bn++;
            s->bkey[b] = 3 * i + k;
            memcpy(s->bpos + 3 * b, e, sizeof e);
            merp_bud_dir(s, i, k, s->bdir + 3 * b);
        }
    }
    if (p->environment == MER_ENV_MARKERS) {
        mer_result rc = mer_markers_colonize(s->markers, s->bn, s->bpos, s->bdir, p->rho, p->r,
                                             p->theta, s->bq, s->bv, NULL, s->bquiet, err);
        if (rc != MER_OK)
            return rc;
        for (size_t b = 0; b < s->bn; b++)
            s->quiet[s->bkey[b]] = s->bquiet[b] ? s->env_epoch + 1 : 0;
    } else {
        for (size_t b = 0; b < s->bn; b++) {
            s->bq[b] = mer_shadow_light(s->shadow, s->bpos + 3 * b, p->shadow_c);
            mer_shadow_direction(s->shadow, s->bpos + 3 * b, s->bdir + 3 * b, p->theta,
                                 p->shadow_dir, s->bv + 3 * b);
        }
    }
    for (size_t b = 0; b < s->bn; b++)
        s->qb[s->bkey[b]] = s->bq[b];
    return MER_OK;
}

/* Basipetal pass: light Q of the buds that may grow, the number of living
 * (dormant) buds, and the internode count, per subtree. The priority model sorts
 * branches by Q per living bud (P09 Fig. 8b: 2.1/3), so shaded buds count. */
static void basipetal(mer_scene *s)
{
    for (uint32_t i = s->n; i-- > 0;) {
        if (!s->alive[i])
            continue;
        float q = 0.0f;
        uint32_t nb = 0, ni = 1;
        for (uint32_t k = 0; k < 3; k++) {
            uint32_t c = s->child[3 * i + k];
            if (c != MER_NO_NODE) {
                q += s->qsub[c];
                nb += s->nbuds[c];
                ni += s->nint[c];
            } else if (bud_exists(s, i, k)) {
                q += s->qb[3 * i + k];
                nb++;
            }
        }
        s->qsub[i] = q;
        s->nbuds[i] = nb;
        s->nint[i] = ni;
    }
}

/* Shedding (P09 §4.4, Takenaka): lateral branches whose light per internode is
 * below the threshold. Returns the number of branches shed. */
static mer_result shed(mer_scene *s, uint32_t *count, mer_error *err)
{
    *count = 0;
    float th = s->p.shed_threshold;
    for (uint32_t i = 0; i < s->n; i++) {
        if (!s->alive[i] || s->slot[i] == 0 || s->parent[i] == MER_NO_NODE)
            continue;
        if (s->qsub[i] / (float)s->nint[i] < th) {
            mer_result rc = merp_kill(s, i, err);
            if (rc != MER_OK)
                return rc;
            (*count)++;
        }
    }
    return MER_OK;
}

/* Extended Borchert-Honda, acropetal pass (P09 §4.2, Fig. 8a). */
static void allocate_bh(mer_scene *s)
{
    float lambda = mer_params_lambda_at(&s->p, s->step);
    for (uint32_t i = 0; i < s->n; i++) {
        if (!s->alive[i])
            continue;
        if (s->parent[i] == MER_NO_NODE)
            s->vin[i] = s->p.alpha * s->qsub[i]; /* v_base = α·Q_base */
        if (s->vin[i] == 0.0f) {
            /* Nothing to share (most of a crown under space colonization): the
             * children get 0 and the buds keep the 0 environment() gave them. */
            for (int k = 0; k < 3; k++)
                if (s->child[3 * i + k] != MER_NO_NODE)
                    s->vin[s->child[3 * i + k]] = 0.0f;
            continue;
        }
        float q[3];
        for (int k = 0; k < 3; k++) {
            uint32_t c = s->child[3 * i + k];
            q[k] = c != MER_NO_NODE ? s->qsub[c] : s->qb[3 * i + k];
        }
        float v[3];
        mer_bh_split2(s->vin[i], lambda, q[0], q + 1, &v[0], v + 1);
        for (int k = 0; k < 3; k++) {
            uint32_t c = s->child[3 * i + k];
            if (c != MER_NO_NODE)
                s->vin[c] = v[k];
            else
                s->vb[3 * i + k] = v[k];
        }
    }
}

static mer_result reserve_items(mer_scene *s, size_t want, mer_error *err)
{
    if (want <= s->pcap)
        return MER_OK;
    size_t cap = want * 2 + 16;
    float *a = realloc(s->pq, cap * sizeof *a);
    if (a == NULL)
        goto nomem;
    s->pq = a;
    a = realloc(s->pv, cap * sizeof *a);
    if (a == NULL)
        goto nomem;
    s->pv = a;
    uint32_t **u[] = {&s->pbuds, &s->prank, &s->pscr, &s->ptarget};
    for (int i = 0; i < 4; i++) {
        uint32_t *x = realloc(*u[i], cap * sizeof *x);
        if (x == NULL)
            goto nomem;
        *u[i] = x;
    }
    s->pcap = cap;
    return MER_OK;
nomem:
    return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the priority lists");
}

/* Priority model, acropetal pass over whole axes (P09 §4.2, Fig. 8b). Axes are
 * visited by the id of their base node, so an axis is always allocated before the
 * branches it supports. */
static mer_result allocate_priority(mer_scene *s, mer_error *err)
{
    const mer_params *p = &s->p;
    for (uint32_t b = 0; b < s->n; b++) {
        if (!s->alive[b] || (s->parent[b] != MER_NO_NODE && s->slot[b] == 0))
            continue;
        float v = s->parent[b] == MER_NO_NODE ? p->alpha * s->qsub[b] : s->vin[b];
        size_t n = 0;
        uint32_t terminal = UINT32_MAX;
        for (uint32_t j = b;;) {
            mer_result rc = reserve_items(s, n + 3, err);
            if (rc != MER_OK)
                return rc;
            for (uint32_t k = 1; k < 3; k++) {
                uint32_t c = s->child[3 * j + k];
                if (c != MER_NO_NODE) {
                    s->pq[n] = s->qsub[c];
                    s->pbuds[n] = s->nbuds[c];
                    s->ptarget[n++] = c | MERP_BRANCH_FLAG;
                } else if (bud_exists(s, j, k)) {
                    s->pq[n] = s->qb[3 * j + k];
                    s->pbuds[n] = 1;
                    s->ptarget[n++] = 3 * j + k;
                }
            }
            uint32_t next = s->child[3 * j];
            if (next == MER_NO_NODE) {
                if (bud_exists(s, j, 0)) {
                    terminal = (uint32_t)n;
                    s->pq[n] = s->qb[3 * j];
                    s->pbuds[n] = 1;
                    s->ptarget[n++] = 3 * j;
                }
                break;
            }
            j = next;
        }
        if (n == 0)
            continue;
        int apical = mer_params_apical_at(p, s->step, s->order[b]);
        mer_priority_allocate(v, (uint32_t)n, s->pq, s->pbuds, terminal, apical, NULL, p->w_max,
                              p->w_min, p->kappa, s->prank, s->pscr, s->pv);
        for (size_t t = 0; t < n; t++) {
            uint32_t tg = s->ptarget[t];
            if (tg & MERP_BRANCH_FLAG)
                s->vin[tg & ~MERP_BRANCH_FLAG] = s->pv[t];
            else
                s->vb[tg] = s->pv[t];
        }
    }
    return MER_OK;
}

/* New shoot of n metamers of length l from bud k of node i (P09 §4.3). */
static mer_result grow_shoot(mer_scene *s, uint32_t i, uint32_t k, uint32_t n, float l,
                             const float *V, mer_error *err)
{
    const mer_params *p = &s->p;
    uint32_t order = s->order[i] + (k > 0 ? 1u : 0u);
    float eta = mer_params_eta_at(p, s->step, order);
    const float T[3] = {0.0f, 1.0f, 0.0f}; /* tropism: up; η's sign sets up or down */
    float d_prev[3], start[3], side_prev[3];
    merp_bud_dir(s, i, k, d_prev);
    merp_node_end(s, i, start);
    memcpy(side_prev, s->side + 3 * i, sizeof side_prev);
    uint32_t cur = i, made = 0;
    for (uint32_t j = 0; j < n; j++) {
        float d[3];
        for (int a = 0; a < 3; a++)
            d[a] = d_prev[a] + p->xi * V[a] + eta * T[a]; /* default + ξV + ηT */
        if (!v3_normalize(d))
            memcpy(d, d_prev, sizeof d);
        float end[3];
        for (int a = 0; a < 3; a++)
            end[a] = start[a] + d[a] * l;
        if (merp_blocked(s, end))
            break;
        uint32_t c;
        mer_result rc = merp_node_new(s, &c, err);
        if (rc != MER_OK)
            return rc;
        uint32_t slot = j == 0 ? k : 0;
        s->parent[c] = cur;
        s->slot[c] = (uint8_t)slot;
        s->child[3 * cur + slot] = c;
        if (j == 0)
            merp_bud_set(s, i, k, MER_BUD_NONE);
        memcpy(s->pos + 3 * c, start, sizeof start);
        memcpy(s->dir + 3 * c, d, sizeof d);
        s->len[c] = l;
        s->order[c] = order;
        s->plant[c] = s->plant[i];
        merp_side_next(side_prev, d, p->divergence, s->side + 3 * c);
        for (uint32_t kk = 1; kk <= p->buds_per_node; kk++)
            merp_bud_set(s, c, kk, MER_BUD_DORMANT);
        memcpy(start, end, sizeof start);
        memcpy(d_prev, d, sizeof d);
        memcpy(side_prev, s->side + 3 * c, sizeof side_prev);
        cur = c;
        made++;
    }
    if (made > 0) {
        uint8_t tip = MER_BUD_DORMANT;
        if (p->sympodial)
            tip = p->sympodial_abort ? MER_BUD_ABORTED : MER_BUD_FLOWER;
        merp_bud_set(s, cur, 0, tip);
    }
    return MER_OK;
}

static mer_result round_(mer_scene *s, int syllepsis, mer_error *err)
{
    mer_result rc = environment(s, syllepsis, err);
    if (rc != MER_OK)
        return rc;
    basipetal(s);
    /* No shedding while growth is constrained to one bud: the other buds' Q is
     * held at 0 then, which says nothing about their light. */
    if (!syllepsis && s->p.shed_threshold > 0.0f && s->con_node == MER_NO_NODE) {
        uint32_t shed_count;
        rc = shed(s, &shed_count, err);
        if (rc != MER_OK)
            return rc;
        if (shed_count > 0)
            basipetal(s);
    }
    if (s->p.fate == MER_FATE_PRIORITY)
        rc = allocate_priority(s, err);
    else
        allocate_bh(s);
    if (rc != MER_OK)
        return rc;
    size_t nb = s->bn;
    for (size_t b = 0; b < nb; b++) {
        uint32_t key = s->bkey[b];
        uint32_t i = key / 3, k = key % 3;
        if (!s->alive[i] || s->bud[key] != MER_BUD_DORMANT)
            continue;
        float l;
        uint32_t n = mer_shoot_size(s->vb[key], s->p.max_shoot, s->p.internode_length, &l);
        if (n == 0)
            continue;
        float V[3];
        memcpy(V, s->bv + 3 * b, sizeof V);
        rc = grow_shoot(s, i, k, n, l, V, err);
        if (rc != MER_OK)
            return rc;
    }
    return MER_OK;
}

/* Pipe model with memory (P09 §4.5): d^n = Σ d_i^n basipetally, never shrinking. */
static void pipe(mer_scene *s)
{
    float leaf = powf(s->p.leaf_diameter, s->pipe_n_used);
    for (uint32_t i = s->n; i-- > 0;) {
        if (!s->alive[i])
            continue;
        uint32_t m = s->child[3 * i];
        float sum = m != MER_NO_NODE ? s->dn[m] : leaf;
        for (int k = 1; k < 3; k++) {
            uint32_t c = s->child[3 * i + k];
            if (c != MER_NO_NODE)
                sum += s->dn[c];
        }
        if (sum > s->dn[i])
            s->dn[i] = sum;
    }
}

static mer_result one_step(mer_scene *s, mer_error *err)
{
    mer_result rc = round_(s, 0, err);
    if (rc == MER_OK && s->p.sylleptic)
        rc = round_(s, 1, err);
    pipe(s);
    s->step++;
    return rc;
}

mer_result mer_scene_step(mer_scene *s, uint32_t count, mer_progress_fn progress, void *ctx,
                          const volatile int *cancel, uint32_t *done, mer_error *err)
{
    uint32_t k = 0;
    mer_result rc = MER_OK;
    for (; k < count; k++) {
        if (cancel != NULL && *cancel)
            break;
        rc = one_step(s, err);
        if (rc != MER_OK)
            break;
        if (progress != NULL)
            progress(ctx, k + 1, count);
    }
    if (done != NULL)
        *done = k;
    return rc;
}
