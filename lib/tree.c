/* meristem — metamer storage, buds and their shadow, subtrees (P09 §3). */
#include "config.h"

#include <stdlib.h>
#include <string.h>

#include "scene_private.h"
#include "vec_private.h"

#define GROW(field, count)                                                    \
    do {                                                                      \
        void *q_ = realloc(s->field, (size_t)cap * (count) * sizeof *s->field); \
        if (q_ == NULL)                                                       \
            return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for nodes"); \
        s->field = q_;                                                        \
    } while (0)

static mer_result reserve(mer_scene *s, uint32_t want, mer_error *err)
{
    if (want <= s->cap)
        return MER_OK;
    if (want > MER_NODES_MAX)
        return mer_error_set(err, MER_ERR_LIMIT, "nodes",
                             "the scene would exceed %u internodes", (unsigned)MER_NODES_MAX);
    uint32_t cap = s->cap ? s->cap : 256;
    while (cap < want)
        cap = cap > MER_NODES_MAX / 2 ? MER_NODES_MAX : cap * 2;
    /* Each realloc either succeeds or leaves the old block: a failure midway leaves
     * some arrays longer than s->cap, which is harmless. */
    GROW(parent, 1);
    GROW(child, 3);
    GROW(bud, 3);
    GROW(slot, 1);
    GROW(alive, 1);
    GROW(plant, 1);
    GROW(order, 1);
    GROW(born, 1);
    GROW(pos, 3);
    GROW(dir, 3);
    GROW(side, 3);
    GROW(len, 1);
    GROW(dn, 1);
    GROW(qsub, 1);
    GROW(nbuds, 1);
    GROW(nint, 1);
    GROW(vin, 1);
    GROW(qb, 3);
    GROW(vb, 3);
    GROW(quiet, 3);
    GROW(mark, 1);
    s->cap = cap;
    return MER_OK;
}

mer_result merp_node_new(mer_scene *s, uint32_t *id, mer_error *err)
{
    mer_result rc = reserve(s, s->n + 1, err);
    if (rc != MER_OK)
        return rc;
    uint32_t i = s->n++;
    s->parent[i] = MER_NO_NODE;
    for (int k = 0; k < 3; k++) {
        s->child[3 * i + k] = MER_NO_NODE;
        s->bud[3 * i + k] = MER_BUD_NONE;
        s->qb[3 * i + k] = 0.0f;
        s->vb[3 * i + k] = 0.0f;
        s->quiet[3 * i + k] = 0;
        s->pos[3 * i + k] = s->dir[3 * i + k] = s->side[3 * i + k] = 0.0f;
    }
    s->slot[i] = 0;
    s->alive[i] = 1;
    s->plant[i] = 0;
    s->order[i] = 0;
    s->born[i] = s->step;
    s->len[i] = 0.0f;
    s->dn[i] = 0.0f;
    s->qsub[i] = 0.0f;
    s->nbuds[i] = 0;
    s->nint[i] = 1;
    s->vin[i] = 0.0f;
    s->mark[i] = 0;
    *id = i;
    return MER_OK;
}

void merp_node_end(const mer_scene *s, uint32_t i, float out[3])
{
    for (int a = 0; a < 3; a++)
        out[a] = s->pos[3 * i + a] + s->dir[3 * i + a] * s->len[i];
}

void merp_bud_dir(const mer_scene *s, uint32_t i, uint32_t k, float out[3])
{
    const float *d = s->dir + 3 * i, *sd = s->side + 3 * i;
    if (k == 0) {
        memcpy(out, d, 3 * sizeof *out);
        return;
    }
    float c = s->cos_beta, sn = k == 1 ? s->sin_beta : -s->sin_beta;
    for (int a = 0; a < 3; a++)
        out[a] = c * d[a] + sn * sd[a];
    v3_normalize(out);
}

void merp_bud_set(mer_scene *s, uint32_t i, uint32_t k, uint8_t state)
{
    uint8_t old = s->bud[3 * i + k];
    if (old == state)
        return;
    s->bud[3 * i + k] = state;
    if (s->shadow == NULL || !s->alive[i])
        return;
    if (old == MER_BUD_DORMANT || state == MER_BUD_DORMANT) {
        float e[3];
        merp_node_end(s, i, e);
        mer_shadow_cast_at(s->shadow, e, state == MER_BUD_DORMANT ? 1 : -1);
    }
}

/* Collects the subtree of `root` (root first, then depth-first) into s->stack[0..count). */
mer_result merp_subtree(mer_scene *s, uint32_t root, size_t *count, mer_error *err)
{
    size_t top = 0, out = 0;
    /* The output is written to the front of the array while the work stack grows
     * from the same array's back half: use one buffer of 2·cap entries. */
    if (s->stack_cap < 2 * (size_t)s->n + 2) {
        size_t cap = 2 * (size_t)s->n + 64;
        uint32_t *st = realloc(s->stack, cap * sizeof *st);
        if (st == NULL)
            return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for a subtree walk");
        s->stack = st;
        s->stack_cap = cap;
    }
    uint32_t *work = s->stack + s->n + 1;
    work[top++] = root;
    while (top > 0) {
        uint32_t i = work[--top];
        s->stack[out++] = i;
        for (int k = 2; k >= 0; k--) {
            uint32_t c = s->child[3 * i + k];
            if (c != MER_NO_NODE && s->alive[c])
                work[top++] = c;
        }
    }
    *count = out;
    return MER_OK;
}

mer_result merp_kill(mer_scene *s, uint32_t root, mer_error *err)
{
    size_t cnt;
    mer_result rc = merp_subtree(s, root, &cnt, err);
    if (rc != MER_OK)
        return rc;
    for (size_t t = 0; t < cnt; t++) {
        uint32_t i = s->stack[t];
        for (uint32_t k = 0; k < 3; k++)
            merp_bud_set(s, i, k, MER_BUD_NONE);
        s->alive[i] = 0;
    }
    uint32_t p = s->parent[root];
    if (p != MER_NO_NODE)
        s->child[3 * p + s->slot[root]] = MER_NO_NODE;
    if (s->con_node != MER_NO_NODE && !s->alive[s->con_node])
        s->con_node = MER_NO_NODE;
    return MER_OK;
}

int merp_inside_obstacle(const merp_obstacle *o, const float *p)
{
    if (o->kind == MERP_OBS_MESH)
        return merp_solid_inside(o->solid, p); /* checks its bounding box first */
    if (o->kind == MERP_OBS_BOX)
        return p[0] >= o->a[0] && p[0] <= o->b[0] && p[1] >= o->a[1] && p[1] <= o->b[1] &&
               p[2] >= o->a[2] && p[2] <= o->b[2];
    float d[3] = {p[0] - o->a[0], p[1] - o->a[1], p[2] - o->a[2]};
    return v3_dot(d, d) <= o->r * o->r;
}

int merp_blocked(const mer_scene *s, const float p[3])
{
    if (s->p.ground_enabled && p[1] < s->p.ground)
        return 1;
    for (uint32_t o = 0; o < s->nobs; o++)
        if (merp_inside_obstacle(&s->obs[o], p))
            return 1;
    return 0;
}

/* An obstacle shades each voxel whose centre it contains fully (C + a, so Q = 0
 * there) and casts a bud's pyramid from each such voxel whose upper neighbour it
 * does not contain (its top surface). */
void merp_shadow_obstacle(mer_scene *s, const merp_obstacle *o, int sign)
{
    if (s->shadow == NULL)
        return;
    int dim[3];
    mer_shadow_dims(s->shadow, dim);
    float lo[3], hi[3];
    if (o->kind == MERP_OBS_BOX || o->kind == MERP_OBS_MESH) {
        memcpy(lo, o->a, sizeof lo);
        memcpy(hi, o->b, sizeof hi);
    } else {
        for (int a = 0; a < 3; a++) {
            lo[a] = o->a[a] - o->r;
            hi[a] = o->a[a] + o->r;
        }
    }
    float vox = s->p.voxel;
    int i0[3], i1[3];
    for (int a = 0; a < 3; a++) {
        float f0 = (lo[a] - s->p.bounds_min[a]) / vox - 0.5f;
        float f1 = (hi[a] - s->p.bounds_min[a]) / vox - 0.5f;
        i0[a] = f0 < 0.0f ? 0 : (int)ceilf(f0);
        i1[a] = f1 >= (float)(dim[a] - 1) ? dim[a] - 1 : (int)floorf(f1);
    }
    float full = s->p.shadow_c + s->p.shadow_a;
    for (int j = i0[1]; j <= i1[1]; j++)
        for (int k = i0[2]; k <= i1[2]; k++)
            for (int i = i0[0]; i <= i1[0]; i++) {
                float c[3] = {s->p.bounds_min[0] + ((float)i + 0.5f) * vox,
                              s->p.bounds_min[1] + ((float)j + 0.5f) * vox,
                              s->p.bounds_min[2] + ((float)k + 0.5f) * vox};
                if (!merp_inside_obstacle(o, c))
                    continue;
                int ijk[3] = {i, j, k};
                mer_shadow_add_voxel(s->shadow, ijk, sign > 0 ? full : -full);
                float up[3] = {c[0], c[1] + vox, c[2]};
                if (!merp_inside_obstacle(o, up))
                    mer_shadow_cast(s->shadow, ijk, sign, 1.0f);
            }
}

void merp_shadow_rebuild(mer_scene *s)
{
    if (s->shadow == NULL)
        return;
    mer_shadow_clear(s->shadow);
    for (uint32_t i = 0; i < s->n; i++) {
        if (!s->alive[i])
            continue;
        for (int k = 0; k < 3; k++)
            if (s->bud[3 * i + k] == MER_BUD_DORMANT) {
                float e[3];
                merp_node_end(s, i, e);
                mer_shadow_cast_at(s->shadow, e, 1);
            }
    }
    for (uint32_t o = 0; o < s->nobs; o++)
        merp_shadow_obstacle(s, &s->obs[o], 1);
}

void merp_side_next(const float side_prev[3], const float d[3], float divergence_deg,
                    float out[3])
{
    /* Carry the previous side vector onto the plane normal to d, then turn it. */
    float t[3];
    float dot = v3_dot(side_prev, d);
    for (int a = 0; a < 3; a++)
        t[a] = side_prev[a] - dot * d[a];
    if (!v3_normalize(t))
        v3_any_perp(d, t);
    v3_rotate(t, d, divergence_deg * MER_DEG2RAD, out);
    v3_normalize(out);
}
