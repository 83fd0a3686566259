/* meristem — the endpoints of Xu & Mould 2015's third step (guiding.h): early
 * ones in the crown's core, later ones on the surface extrapolated from the
 * tree (the outermost fraction t of the nodes k hops from it), optionally
 * inside the crown volume. */
#include "config.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "core/array.h"
#include "models/guiding/guiding.h"

int merp_gv_inside(uint32_t kind, const float center[3], const float size[3], const float p[3])
{
    assert(center != NULL && size != NULL && p != NULL);
    float d[3] = {p[0] - center[0], p[1] - center[1], p[2] - center[2]};
    switch (kind) {
    case MER_VOLUME_BOX:
        return fabsf(d[0]) <= size[0] && fabsf(d[1]) <= size[1] && fabsf(d[2]) <= size[2];
    case MER_VOLUME_SPHERE:
        return d[0] * d[0] + d[1] * d[1] + d[2] * d[2] <= size[0] * size[0];
    case MER_VOLUME_ELLIPSOID: {
        float s = 0.0f;
        for (int a = 0; a < 3; a++) {
            if (!(size[a] > 0.0f))
                return 0;
            s += (d[a] / size[a]) * (d[a] / size[a]);
        }
        return s <= 1.0f;
    }
    case MER_VOLUME_CYLINDER:
        return d[0] * d[0] + d[2] * d[2] <= size[0] * size[0] && fabsf(d[1]) <= size[1];
    case MER_VOLUME_CONE: {
        if (!(size[1] > 0.0f) || fabsf(d[1]) > size[1])
            return 0;
        float r = size[0] * (size[1] - d[1]) / (2.0f * size[1]); /* base at -size[1] */
        return d[0] * d[0] + d[2] * d[2] <= r * r;
    }
    default:
        return 0;
    }
}

void merp_gv_volume_box(uint32_t kind, const float center[3], const float size[3], float lo[3],
                        float hi[3])
{
    assert(center != NULL && size != NULL && lo != NULL && hi != NULL);
    float ext[3];
    if (kind == MER_VOLUME_SPHERE)
        ext[0] = ext[1] = ext[2] = size[0];
    else if (kind == MER_VOLUME_CYLINDER || kind == MER_VOLUME_CONE) {
        ext[0] = ext[2] = size[0];
        ext[1] = size[1];
    } else
        memcpy(ext, size, sizeof ext);
    for (int a = 0; a < 3; a++) {
        lo[a] = center[a] - ext[a];
        hi[a] = center[a] + ext[a];
    }
}

static int push(uint32_t **out, uint32_t *n, uint32_t *cap, uint32_t v)
{
    if (*n == *cap) {
        uint32_t c = *cap ? 2 * *cap : 256;
        if (!MERP_RESIZE(*out, c))
            return 0;
        *cap = c;
    }
    (*out)[(*n)++] = v;
    return 1;
}

/* Keeps `want` of the n candidates in out[0..want), drawn without replacement
 * (a partial Fisher-Yates shuffle), in draw order. */
static uint32_t draw(uint32_t *c, uint32_t n, uint32_t want, mer_rng *rng)
{
    if (want >= n)
        return n;
    for (uint32_t i = 0; i < want; i++) {
        uint32_t j = i + mer_rng_below(rng, n - i);
        uint32_t t = c[i];
        c[i] = c[j];
        c[j] = t;
    }
    return want;
}

typedef struct outward {
    float d2;
    uint32_t node;
} outward;

static int farther_first(const void *a, const void *b)
{
    const outward *x = a, *y = b;
    if (x->d2 != y->d2)
        return x->d2 > y->d2 ? -1 : 1;
    return x->node < y->node ? -1 : x->node > y->node;
}

/* The outermost fraction t of the candidates in out[0..n), by distance from root. */
static mer_result outermost(const merp_gv_graph *gr, const float root[3], float t, uint32_t *out,
                            uint32_t *n, mer_error *err)
{
    outward *o = merp_malloc((*n ? *n : 1) * sizeof *o);
    if (o == NULL)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the endpoints");
    for (uint32_t i = 0; i < *n; i++) {
        const float *q = gr->pos + 3 * (size_t)out[i];
        float d[3] = {q[0] - root[0], q[1] - root[1], q[2] - root[2]};
        o[i] = (outward){d[0] * d[0] + d[1] * d[1] + d[2] * d[2], out[i]};
    }
    qsort(o, *n, sizeof *o, farther_first);
    uint32_t keep = (uint32_t)ceil((double)t * (double)*n);
    for (uint32_t i = 0; i < keep; i++)
        out[i] = o[i].node;
    *n = keep;
    merp_free(o);
    return MER_OK;
}

mer_result merp_gv_endpoints(const mer_params *p, uint32_t it, const merp_gv_graph *gr,
                             const merp_gv_search *s, const uint32_t *in_tree,
                             const float root[3], uint32_t want, mer_rng *rng, uint32_t **out,
                             uint32_t *n, uint32_t *cap, mer_error *err)
{
    assert(p != NULL && gr != NULL && s != NULL && in_tree != NULL && out != NULL && n != NULL);
    *n = 0;
    float core[3];
    for (int a = 0; a < 3; a++)
        core[a] = p->marker_size[a] * 0.5f;
    for (uint32_t i = 0; i < gr->n; i++) {
        const float *q = gr->pos + 3 * (size_t)i;
        if (in_tree[i] != MER_NO_NODE || !isfinite(s->dist[i]))
            continue;
        int ok = it == 0 ? merp_gv_inside(p->marker_volume, p->marker_center, core, q)
                         : s->hsrc[i] == p->gv_k_hops &&
                               (!p->gv_bound ||
                                merp_gv_inside(p->marker_volume, p->marker_center, p->marker_size,
                                               q));
        if (ok && !push(out, n, cap, i))
            return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the endpoints");
    }
    if (it > 0) {
        mer_result rc = outermost(gr, root, p->gv_t, *out, n, err);
        if (rc != MER_OK)
            return rc;
    }
    *n = draw(*out, *n, want, rng);
    return MER_OK;
}
