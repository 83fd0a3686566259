/* meristem — the turtle interpretation of a module string (ABOP §1.5 in three
 * dimensions, §1.6 branching, §2.2 tropism), producing internode segments.
 *
 * The state is a position and the frame H (heading), L (left), U (up) with
 * H × L = U. Signs follow ABOP and cpfg, not Houdini: + turns left (H towards
 * L) and - right, about U; & pitches down (H towards -U) and ^ up, about L;
 * \ rolls left (L towards U) and / right, about H; | turns around; $ rolls L
 * horizontal (ABOP eq. 2.2 with V = +y). A parameter overrides the angle δ or
 * the step. F and G draw a segment, f moves without drawing; [ and ] push and
 * pop the state; !(w) sets the width and '(c) the colour; % drops the rest of
 * its branch; . ~ { } and unknown symbols draw nothing. After each step the
 * heading bends towards T by e·|H × T| (ABOP §2.2).
 *
 * Query modules (cpfg): given a merp_ls_query, ?P receives the position, ?H ?L
 * ?U the frame's vectors and ?E the environment's answer, written into the
 * query's parameter array; without one they draw nothing, like any module.
 */
#include "config.h"

#include "models/lsystem/lsystem.h"

#include <assert.h>
#include <math.h>
#include <string.h>

#include "core/alloc.h"

typedef struct tstate {
    double p[3], h[3], l[3], u[3];
    double width;
    uint32_t last;
    uint16_t order, color;
} tstate;

merp_ls_turtle merp_ls_turtle_default(void)
{
    return (merp_ls_turtle){.delta = 90.0, .step = 1.0, .width = 1.0,
                            .tropism = {0.0, -1.0, 0.0}, .elasticity = 0.0};
}

static void cross(const double a[3], const double b[3], double out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

static void normalize(double v[3])
{
    double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (n > 0.0)
        for (int k = 0; k < 3; k++)
            v[k] /= n;
}

/* cos and sin of the last angle turned: strings turn by few distinct angles
 * (δ, the #define'd ones), and the same angle gives the same values. */
typedef struct trig {
    double deg, c, s;
} trig;

/* Turns the pair (a, b) of frame vectors by `deg` degrees, a towards b. */
static void turn(double a[3], double b[3], double deg, trig *tr)
{
    if (memcmp(&deg, &tr->deg, sizeof deg) != 0) { /* bitwise: -0 is not 0 */
        double r = deg * (M_PI / 180.0);
        tr->deg = deg, tr->c = cos(r), tr->s = sin(r);
    }
    double c = tr->c, s = tr->s;
    for (int k = 0; k < 3; k++) {
        double x = a[k], y = b[k];
        a[k] = x * c + y * s;
        b[k] = y * c - x * s;
    }
}

/* Rotates v about the unit axis `ax` by `rad` (Rodrigues). */
static void rotate(double v[3], const double ax[3], double rad)
{
    double c = cos(rad), s = sin(rad), kv[3], d = 0.0;
    cross(ax, v, kv);
    for (int k = 0; k < 3; k++)
        d += ax[k] * v[k];
    for (int k = 0; k < 3; k++)
        v[k] = v[k] * c + kv[k] * s + ax[k] * d * (1.0 - c);
}

/* ABOP §2.2: H bends towards T by α = e·|H × T|, about H × T; L and U follow. */
static void tropism(tstate *t, const merp_ls_turtle *tp)
{
    if (tp->elasticity == 0.0)
        return;
    double ax[3];
    cross(t->h, tp->tropism, ax);
    double m = sqrt(ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2]);
    if (m < 1e-12)
        return;
    for (int k = 0; k < 3; k++)
        ax[k] /= m;
    double a = tp->elasticity * m;
    rotate(t->h, ax, a);
    rotate(t->l, ax, a);
    rotate(t->u, ax, a);
}

/* ABOP eq. 2.2: L = V × H / |V × H|, U = H × L, with V the opposite of gravity. */
static void roll_horizontal(tstate *t)
{
    static const double v[3] = {0.0, 1.0, 0.0};
    double l[3];
    cross(v, t->h, l);
    if (l[0] * l[0] + l[1] * l[1] + l[2] * l[2] < 1e-24)
        return; /* heading vertical: any L is horizontal */
    normalize(l);
    memcpy(t->l, l, sizeof l);
    cross(t->h, t->l, t->u);
}

/* Grows out's room to `need` segments (at least doubling). */
static int reserve(merp_ls_segs *out, size_t need)
{
    if (need > out->cap) {
        size_t c = out->cap ? out->cap * 2 : 64;
        if (c < need)
            c = need;
        merp_ls_seg *q = merp_realloc(out->seg, c * sizeof *q);
        if (!q)
            return -1;
        out->seg = q;
        out->cap = c;
    }
    return 0;
}

static int draw(tstate *t, double len, uint32_t module, merp_ls_segs *out)
{
    if (out->n == out->cap && reserve(out, out->n + 1))
        return -1;
    merp_ls_seg *g = &out->seg[out->n];
    for (int k = 0; k < 3; k++) {
        g->base[k] = (float)t->p[k];
        t->p[k] += t->h[k] * len;
        g->tip[k] = (float)t->p[k];
        g->head[k] = (float)t->h[k];
        g->left[k] = (float)t->l[k];
    }
    g->width = (float)t->width;
    g->parent = t->last;
    g->module = module;
    g->order = t->order;
    g->color = t->color;
    t->last = (uint32_t)out->n++;
    return 0;
}

/* Answers query module i (symbol y >= 256) through q. */
static void query(const tstate *t, const merp_lstr *s, size_t i, const merp_ls_query *q)
{
    unsigned np = merp_lstr_np(s, i);
    float *par = q->par + s->poff[i];
    double pos[3];
    for (int k = 0; k < 3; k++)
        pos[k] = q->origin[k] + t->p[k];
    const double *v = NULL;
    switch (s->sym[i] - 256) {
    case 'P': v = pos; break;
    case 'H': v = t->h; break;
    case 'L': v = t->l; break;
    case 'U': v = t->u; break;
    case 'E':
        if (q->env)
            q->env(q->ctx, pos, t->h, par, np);
        return;
    default: return;
    }
    for (unsigned k = 0; k < np && k < 3; k++)
        par[k] = (float)v[k];
}

/* Changes the state by module i (not a bracket); -1 when out of memory. */
static int act(tstate *t, const merp_lstr *s, size_t i, const merp_ls_turtle *tp,
               const merp_ls_query *q, merp_ls_segs *out, trig *tr)
{
    unsigned np = merp_lstr_np(s, i);
    double a = np ? (double)s->par[s->poff[i]] : tp->delta;
    double len = np ? (double)s->par[s->poff[i]] : tp->step;
    switch (s->sym[i]) {
    case 'F':
    case 'G':
        if (draw(t, len, (uint32_t)i, out))
            return -1;
        tropism(t, tp);
        break;
    case 'f':
        for (int k = 0; k < 3; k++)
            t->p[k] += t->h[k] * len;
        tropism(t, tp);
        break;
    case '+': turn(t->h, t->l, a, tr); break;
    case '-': turn(t->h, t->l, -a, tr); break;
    case '&': turn(t->u, t->h, a, tr); break;
    case '^': turn(t->u, t->h, -a, tr); break;
    case '\\': turn(t->l, t->u, a, tr); break;
    case '/': turn(t->l, t->u, -a, tr); break;
    case '|': turn(t->h, t->l, 180.0, tr); break;
    case '$': roll_horizontal(t); break;
    case '!':
        if (np)
            t->width = (double)s->par[s->poff[i]];
        break;
    case '\'':
        if (np)
            t->color = (uint16_t)s->par[s->poff[i]];
        break;
    default:
        if (q && s->sym[i] >= 256)
            query(t, s, i, q);
        break;
    }
    return 0;
}

int merp_ls_interpret(const merp_lstr *s, const merp_ls_turtle *tp, merp_ls_segs *out)
{
    return merp_ls_interpret_query(s, tp, NULL, out);
}

int merp_ls_interpret_query(const merp_lstr *s, const merp_ls_turtle *tp,
                            const merp_ls_query *q, merp_ls_segs *out)
{
    assert(s && tp && out && (!q || q->par || s->npar == 0));
    out->n = 0;
    tstate t = {.p = {0, 0, 0}, .h = {0, 1, 0}, .l = {-1, 0, 0}, .u = {0, 0, 1},
                .width = tp->width, .last = UINT32_MAX};
    tstate *stack = NULL;
    size_t depth = 0, cap = 0;
    /* Room for every F and G at once: one allocation, no copies as it grows. */
    int rc = reserve(out, merp_lstr_count(s, 'F') + merp_lstr_count(s, 'G'));
    trig tr = {0.0, 1.0, 0.0};
    for (size_t i = 0; !rc && i < s->n; i++) {
        merp_sym y = s->sym[i];
        if (y == '[') {
            if (depth == cap) {
                size_t c = cap ? cap * 2 : 32;
                tstate *grown = merp_realloc(stack, c * sizeof *grown);
                if (!grown) {
                    rc = -1;
                    break;
                }
                stack = grown, cap = c;
            }
            stack[depth++] = t;
            t.order++;
        } else if (y == ']') {
            if (depth > 0)
                t = stack[--depth];
        } else if (y == '%') {
            i = merp_lstr_branch_end(s, i + 1) - 1; /* the ']' comes next, or the end */
        } else {
            rc = act(&t, s, i, tp, q, out, &tr);
        }
    }
    merp_free(stack);
    return rc;
}

void merp_ls_segs_free(merp_ls_segs *segs)
{
    assert(segs);
    merp_free(segs->seg);
    memset(segs, 0, sizeof *segs);
}
