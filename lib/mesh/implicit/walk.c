/* meristem — lazily evaluated lattice samples and the walk over the cells
 * the surface crosses (walk.h). */
#include "config.h"

#include <assert.h>
#include <math.h>
#include <string.h>

#include "core/alloc.h"
#include "core/vec.h"
#include "mesh/implicit/walk.h"

/* At most this many regula falsi steps on an edge; fewer once the point is
 * within REFINE_TOL of the edge's length from the surface (|f − c| over the
 * bracket's slope). */
enum { REFINE_STEPS = 8 };
#define REFINE_TOL 1e-4f
/* A Newton step of at most this (a fraction of the edge) is taken as the
 * last, unchecked: its error, ~ δ²/2 over the field's curvature radius in
 * edge lengths (about one or more: a patch's grid has over a cell per
 * radius), is within REFINE_TOL, and checking it would cost a gradient
 * evaluation (a third of them on the 10k bench tree's patches). Across a
 * crease (a max of two terms) the error can reach δ: on that tree 99.85 %
 * of these points lie within REFINE_TOL, the worst 1.1 % of its edge off. */
#define NEWTON_LAST 1e-2f

const uint8_t merp_walk_face[6] = {0x55, 0xaa, 0x33, 0xcc, 0x0f, 0xf0};

static uint32_t cell_count(const merp_grid *g)
{
    return g->n[0] * g->n[1] * g->n[2];
}

mer_result merp_walk_init(merp_walk *w, const merp_grid *g, merp_field_fn f, const void *data,
                          mer_error *err)
{
    assert(g->n[0] >= 1 && g->n[1] >= 1 && g->n[2] >= 1 && g->h > 0.0f);
    uint64_t samples = (uint64_t)(g->n[0] + 1) * (g->n[1] + 1) * (g->n[2] + 1);
    assert(samples < UINT32_MAX);
    assert(g->n[0] < 1u << 21 && g->n[1] < 1u << 21 && g->n[2] < 1u << 21); /* the queue's fields */
    *w = (merp_walk){.g = g, .f = f, .data = data, .sx = g->n[0] + 1, .sy = g->n[1] + 1};
    for (uint32_t c = 0; c < 8; c++)
        w->corner[c] = (c & 1) + (c >> 1 & 1) * w->sx + (c >> 2 & 1) * w->sx * w->sy;
    uint32_t cells = cell_count(g);
    w->value = merp_malloc((size_t)samples * sizeof(float));
    w->known = merp_calloc((size_t)(samples / 32 + 1), sizeof(uint32_t));
    w->seen = merp_calloc((size_t)(cells / 32 + 1), sizeof(uint32_t));
    w->queue = merp_malloc((size_t)cells * sizeof *w->queue);
    if (w->value == NULL || w->known == NULL || w->seen == NULL || w->queue == NULL) {
        merp_walk_free(w);
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory polygonizing a field");
    }
    return MER_OK;
}

void merp_walk_free(merp_walk *w)
{
    merp_free(w->value);
    merp_free(w->known);
    merp_free(w->seen);
    merp_free(w->queue);
    w->value = NULL, w->known = w->seen = NULL, w->queue = NULL;
}

mer_result merp_walk_begin(merp_walk *w, const merp_grid *g, merp_field_fn f, const void *data,
                           const float (*seeds)[3], uint32_t nseeds, size_t scratch_count, uint32_t **scratch,
                           merp_trimesh *out, mer_error *err)
{
    if (merp_walk_init(w, g, f, data, err) != MER_OK)
        return MER_ERR_NOMEM;
    *scratch = merp_malloc((scratch_count ? scratch_count : 1) * sizeof(uint32_t));
    if (*scratch == NULL) {
        merp_walk_free(w);
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory polygonizing a field");
    }
    merp_walk_start(w, seeds, nseeds);
    out->vertex_count = out->triangle_count = 0;
    return MER_OK;
}

/* f at sample s = (i, j, k), evaluated on first use. */
static inline float value_at(merp_walk *w, uint32_t s, uint32_t i, uint32_t j, uint32_t k)
{
    if (!(w->known[s >> 5] >> (s & 31) & 1u)) {
        float p[3];
        merp_grid_point(w->g, i, j, k, p);
        w->value[s] = w->f(p, w->data);
        w->known[s >> 5] |= 1u << (s & 31);
    }
    return w->value[s];
}

float merp_walk_value(merp_walk *w, uint32_t i, uint32_t j, uint32_t k)
{
    return value_at(w, merp_walk_sample(w, i, j, k), i, j, k);
}

uint8_t merp_walk_corners(merp_walk *w, const uint32_t cell[3], float cf[8])
{
    /* The samples from the lowest corner's index by the corners' steps. */
    const uint32_t s0 = merp_walk_sample(w, cell[0], cell[1], cell[2]);
    uint8_t mask = 0;
    for (uint32_t c = 0; c < 8; c++) {
        const uint32_t s = s0 + w->corner[c];
        /* known: most corners (a cell shares them with the cells walked before it) */
        cf[c] = w->known[s >> 5] >> (s & 31) & 1u
                    ? w->value[s]
                    : value_at(w, s, cell[0] + (c & 1), cell[1] + (c >> 1 & 1), cell[2] + (c >> 2 & 1));
        mask |= (uint8_t)((cf[c] >= MERP_ISO) << c);
    }
    return mask;
}

static void push(merp_walk *w, uint32_t i, uint32_t j, uint32_t k)
{
    uint32_t c = i + w->g->n[0] * (j + w->g->n[1] * k);
    if (w->seen[c >> 5] >> (c & 31) & 1u)
        return;
    w->seen[c >> 5] |= 1u << (c & 31);
    w->queue[w->tail++] = (uint64_t)i | (uint64_t)j << 21 | (uint64_t)k << 42;
}

void merp_walk_seed(merp_walk *w, const float p[3])
{
    uint32_t cell[3];
    merp_grid_locate(w->g, p, cell);
    float cf[8];
    for (; cell[0] < w->g->n[0]; cell[0]++) {
        uint8_t mask = merp_walk_corners(w, cell, cf);
        if (mask != 0 && mask != 0xff) {
            push(w, cell[0], cell[1], cell[2]);
            return;
        }
    }
}

void merp_walk_all(merp_walk *w)
{
    for (uint32_t k = 0; k < w->g->n[2]; k++)
        for (uint32_t j = 0; j < w->g->n[1]; j++)
            for (uint32_t i = 0; i < w->g->n[0]; i++)
                push(w, i, j, k);
}

void merp_walk_start(merp_walk *w, const float (*seeds)[3], uint32_t nseeds)
{
    if (seeds == NULL)
        merp_walk_all(w);
    for (uint32_t s = 0; s < nseeds; s++)
        merp_walk_seed(w, seeds[s]);
}

bool merp_walk_next(merp_walk *w, uint32_t cell[3], float cf[8], uint8_t *mask)
{
    const uint32_t *n = w->g->n;
    while (w->head < w->tail) {
        uint64_t at = w->queue[w->head++];
        cell[0] = (uint32_t)(at & 0x1fffff), cell[1] = (uint32_t)(at >> 21 & 0x1fffff);
        cell[2] = (uint32_t)(at >> 42);
        *mask = merp_walk_corners(w, cell, cf);
        if (*mask == 0 || *mask == 0xff)
            continue;
        for (int face = 0; face < 6; face++) {
            uint8_t fm = *mask & merp_walk_face[face];
            if (fm == 0 || fm == merp_walk_face[face])
                continue; /* no surface through this face */
            int a = face / 2, up = face % 2;
            if (up ? cell[a] + 1 >= n[a] : cell[a] == 0)
                continue;
            uint32_t q[3] = {cell[0], cell[1], cell[2]};
            q[a] = up ? q[a] + 1 : q[a] - 1;
            push(w, q[0], q[1], q[2]);
        }
        return true;
    }
    return false;
}

void merp_walk_normal(const merp_walk *w, const float p[3], float fp, const float fallback[3], float n[3])
{
    if (w->grad != NULL) {
        w->grad(p, w->data, n);
        for (int a = 0; a < 3; a++)
            n[a] = -n[a];
    } else {
        float e = w->g->h * 0.02f;
        for (int a = 0; a < 3; a++) {
            float q[3] = {p[0], p[1], p[2]};
            q[a] += e;
            n[a] = fp - w->f(q, w->data);
        }
    }
    if (!v3_normalize(n)) {
        memcpy(n, fallback, sizeof(float) * 3);
        v3_normalize(n);
    }
}

float merp_walk_solve(const merp_walk *w, const float pa[3], float fa, const float pb[3], float fb,
                      float p[3])
{
    float ta = 0.0f, tb = 1.0f, ga = fa - MERP_ISO, gb = fb - MERP_ISO;
    int side = 0;
    float t = 0.5f;
    for (int it = 0; it < REFINE_STEPS; it++) {
        t = ga != gb ? ta + (tb - ta) * ga / (ga - gb) : 0.5f * (ta + tb);
        for (int k = 0; k < 3; k++)
            p[k] = pa[k] + t * (pb[k] - pa[k]);
        float gt = w->f(p, w->data) - MERP_ISO;
        /* ga − gb over the bracket is the slope per unit t; t times the
         * edge's length (h or more) is a distance. */
        if (fabsf(gt) * (tb - ta) < REFINE_TOL * fabsf(ga - gb))
            return gt + MERP_ISO;
        if (gt >= 0.0f) {
            ta = t, ga = gt;
            if (side == 1)
                gb *= 0.5f;
            side = 1;
        } else {
            tb = t, gb = gt;
            if (side == -1)
                ga *= 0.5f;
            side = -1;
        }
    }
    t = ga != gb ? ta + (tb - ta) * ga / (ga - gb) : 0.5f * (ta + tb);
    for (int k = 0; k < 3; k++)
        p[k] = pa[k] + t * (pb[k] - pa[k]);
    return w->f(p, w->data);
}

/* merp_walk_crossing with w->grad: Newton's method in the bracket. */
static void crossing_newton(const merp_walk *w, const float pa[3], float fa, const float pb[3], float fb,
                            float p[3], float g[3])
{
    float d[3] = {pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]};
    float ta = 0.0f, tb = 1.0f, ga = fa - MERP_ISO, gb = fb - MERP_ISO;
    float t = ga != gb ? ga / (ga - gb) : 0.5f;
    for (int it = 0; it < REFINE_STEPS; it++) {
        for (int k = 0; k < 3; k++)
            p[k] = pa[k] + t * d[k];
        float gt = w->grad(p, w->data, g) - MERP_ISO;
        /* merp_walk_solve's test: within REFINE_TOL of the edge's length. */
        if (fabsf(gt) * (tb - ta) < REFINE_TOL * fabsf(ga - gb))
            return;
        if (gt >= 0.0f)
            ta = t, ga = gt;
        else
            tb = t, gb = gt;
        float slope = v3_dot(g, d), tn = slope != 0.0f ? t - gt / slope : -1.0f;
        if (tn > ta && tn < tb && fabsf(tn - t) <= NEWTON_LAST) {
            /* NEWTON_LAST: the point moves without another evaluation;
             * g stays the gradient δ away. */
            for (int k = 0; k < 3; k++)
                p[k] = pa[k] + tn * d[k];
            return;
        }
        t = tn > ta && tn < tb ? tn : ta + (tb - ta) * ga / (ga - gb);
    }
}

void merp_walk_crossing(const merp_walk *w, const float pa[3], float fa, const float pb[3], float fb,
                        float p[3], float n[3])
{
    /* outside as merp_walk_corners has it: a NaN value counts as outside */
    assert(fa >= MERP_ISO && !(fb >= MERP_ISO));
    float out[3] = {pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]};
    if (w->grad == NULL) {
        merp_walk_normal(w, p, merp_walk_solve(w, pa, fa, pb, fb, p), out, n);
        return;
    }
    crossing_newton(w, pa, fa, pb, fb, p, n);
    for (int k = 0; k < 3; k++)
        n[k] = -n[k];
    if (!v3_normalize(n)) {
        memcpy(n, out, sizeof out);
        v3_normalize(n);
    }
}
