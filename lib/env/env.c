/* meristem — the environment: grids, perception, the ground (P09 §4.1). */
#include "config.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "core/hash.h"
#include "env/env.h"

static mer_result make_grids(const mer_params *p, mer_markers **mk, mer_shadow **sh,
                             mer_error *err)
{
    *mk = NULL;
    *sh = NULL;
    mer_result rc = mer_markers_new(p->bounds_min, p->bounds_max, p->marker_cell, mk, err);
    if (rc != MER_OK)
        return rc;
    if (p->environment == MER_ENV_SHADOW) {
        rc = mer_shadow_new(p->bounds_min, p->bounds_max, p->voxel, p->shadow_a, p->shadow_b,
                            p->q_max, sh, err);
        if (rc != MER_OK) {
            mer_markers_free(*mk);
            *mk = NULL;
        }
    }
    return rc;
}

mer_result merp_env_init(merp_env *e, const mer_params *p, mer_error *err)
{
    assert(e != NULL && p != NULL);
    memset(e, 0, sizeof *e);
    e->p = *p;
    return make_grids(p, &e->markers, &e->shadow, err);
}

void merp_env_free(merp_env *e)
{
    if (e == NULL)
        return;
    for (uint32_t o = 0; o < e->nobs; o++)
        merp_solid_free(e->obs[o].solid);
    merp_free(e->obs);
    mer_markers_free(e->markers);
    mer_shadow_free(e->shadow);
    merp_free(e->pend);
    merp_free(e->pend_tmp);
    merp_free(e->casts);
    memset(e, 0, sizeof *e);
}

mer_result merp_env_clone(const merp_env *src, merp_env *dst, mer_error *err)
{
    assert(src != NULL && dst != NULL);
    memset(dst, 0, sizeof *dst);
    dst->p = src->p;
    dst->epoch = src->epoch;
    mer_result rc = MER_OK;
    if (src->markers != NULL)
        rc = merp_markers_clone(src->markers, &dst->markers, err);
    if (rc == MER_OK && src->shadow != NULL)
        rc = merp_shadow_clone(src->shadow, &dst->shadow, err);
    if (rc == MER_OK && src->nobs > 0) {
        dst->obs = merp_calloc(src->nobs, sizeof *dst->obs);
        if (dst->obs == NULL)
            rc = mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for obstacles");
    }
    for (uint32_t o = 0; rc == MER_OK && o < src->nobs; o++) {
        dst->obs[o] = src->obs[o];
        dst->obs[o].solid = NULL;
        dst->nobs = o + 1;
        if (src->obs[o].solid != NULL)
            rc = merp_solid_clone(src->obs[o].solid, &dst->obs[o].solid, err);
    }
    if (rc != MER_OK)
        merp_env_free(dst);
    return rc;
}

static int same_grid(const mer_params *a, const mer_params *b)
{
    return memcmp(a->bounds_min, b->bounds_min, sizeof a->bounds_min) == 0 &&
           memcmp(a->bounds_max, b->bounds_max, sizeof a->bounds_max) == 0;
}

/* A new marker grid holding the markers of `old`. */
static mer_result regrid_markers(const mer_markers *old, const mer_params *p, mer_markers **out,
                                 mer_error *err)
{
    mer_markers *mk = NULL;
    mer_result rc = mer_markers_new(p->bounds_min, p->bounds_max, p->marker_cell, &mk, err);
    if (rc != MER_OK)
        return rc;
    size_t cnt = mer_markers_count(old);
    float *xyz = merp_malloc((cnt ? cnt : 1) * 3 * sizeof *xyz);
    if (xyz == NULL) {
        mer_markers_free(mk);
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for markers");
    }
    mer_markers_positions(old, xyz, cnt);
    rc = mer_markers_add(mk, xyz, cnt, err);
    merp_free(xyz);
    if (rc != MER_OK) {
        mer_markers_free(mk);
        return rc;
    }
    *out = mk;
    return MER_OK;
}

mer_result merp_env_prepare(const merp_env *e, const mer_params *p, merp_env_change *c,
                            mer_error *err)
{
    assert(e != NULL && p != NULL && c != NULL);
    const mer_params *o = &e->p;
    memset(c, 0, sizeof *c);
    c->markers_change = !same_grid(p, o) || p->marker_cell != o->marker_cell;
    c->ground_change = p->ground_enabled != o->ground_enabled || p->ground != o->ground;
    c->shadow_change = !same_grid(p, o) || p->voxel != o->voxel ||
                       p->shadow_a != o->shadow_a || p->shadow_b != o->shadow_b ||
                       p->q_max != o->q_max || p->environment != o->environment ||
                       p->shadow_c != o->shadow_c;
    // Finer voxels or wider bounds ask a mesh obstacle more: the same bound as
    // when it was added.
    for (uint32_t i = 0; i < e->nobs && (c->shadow_change || c->markers_change); i++) {
        if (e->obs[i].kind != MERP_OBS_MESH)
            continue;
        mer_result rc = merp_check_mesh_work(e->obs[i].solid, p, mer_markers_count(e->markers),
                                             "voxel", err);
        if (rc != MER_OK)
            return rc;
    }
    if (c->markers_change) {
        mer_result rc = regrid_markers(e->markers, p, &c->markers, err);
        if (rc != MER_OK)
            return rc;
    }
    if (c->shadow_change && p->environment == MER_ENV_SHADOW) {
        mer_result rc = mer_shadow_new(p->bounds_min, p->bounds_max, p->voxel, p->shadow_a,
                                       p->shadow_b, p->q_max, &c->shadow, err);
        if (rc != MER_OK) {
            mer_markers_free(c->markers);
            c->markers = NULL;
            return rc;
        }
    }
    return MER_OK;
}

int merp_env_commit(merp_env *e, const mer_params *p, merp_env_change *c)
{
    e->p = *p;
    e->epoch++; /* bud directions or the grid may have changed */
    if (c->markers_change) {
        mer_markers_free(e->markers);
        e->markers = c->markers;
        c->markers = NULL;
    }
    if (c->shadow_change) {
        mer_shadow_free(e->shadow);
        e->shadow = c->shadow;
        c->shadow = NULL;
        return e->shadow != NULL;
    }
    return 0;
}

/* mer_markers_remove_if's test: a marker inside an obstacle or below the ground. */
static int blocked_ctx(const float p[3], void *ctx)
{
    return merp_env_blocked(ctx, p);
}

void merp_env_drop_covered(merp_env *e, const merp_env_change *c)
{
    // Markers the ground now covers go, as they would not have been added below it.
    if (c->ground_change)
        mer_markers_remove_if(e->markers, blocked_ctx, e);
}

mer_result merp_env_perceive(merp_env *e, size_t n, const float *pos, const float *dir,
                             float *q, float *v, uint8_t *quiet, mer_error *err)
{
    assert(e != NULL && (n == 0 || (pos != NULL && dir != NULL && q != NULL && v != NULL)));
    const mer_params *p = &e->p;
    if (p->environment == MER_ENV_MARKERS) {
        assert(quiet != NULL || n == 0);
        return mer_markers_colonize(e->markers, n, pos, dir, p->rho, p->r, p->theta, q, v, NULL,
                                    quiet, err);
    }
    for (size_t b = 0; b < n; b++) {
        q[b] = mer_shadow_light(e->shadow, pos + 3 * b, p->shadow_c);
        merp_env_direction(e, pos + 3 * b, dir + 3 * b, v + 3 * b);
    }
    return MER_OK;
}

uint32_t merp_env_cell(const merp_env *e, const float pos[3])
{
    assert(e != NULL && e->shadow != NULL && pos != NULL);
    return merp_shadow_cell(e->shadow, pos);
}

void merp_env_light_cells(const merp_env *e, const uint32_t *cells, size_t n, float *q)
{
    assert(e != NULL && e->shadow != NULL && (n == 0 || (cells != NULL && q != NULL)));
    merp_shadow_light_cells(e->shadow, cells, n, e->p.shadow_c, q);
}

merp_light merp_env_light(const merp_env *e)
{
    assert(e != NULL && e->shadow != NULL);
    return merp_shadow_light_view(e->shadow, e->p.shadow_c);
}

void merp_env_direction(const merp_env *e, const float pos[3], const float dir[3], float v[3])
{
    assert(e != NULL && e->shadow != NULL);
    mer_shadow_direction(e->shadow, pos, dir, e->p.theta, e->p.shadow_dir, v);
}

float merp_env_cone(const merp_env *e)
{
    assert(e != NULL);
    return merp_shadow_cone(e->p.theta);
}

void merp_env_direction_cell(const merp_env *e, uint32_t cell, const float dir[3], float cone,
                             float v[3])
{
    assert(e != NULL && e->shadow != NULL);
    merp_shadow_direction_cell(e->shadow, cell, dir, cone, e->p.shadow_dir, v);
}

void merp_env_direction_ahead(const merp_env *e, uint32_t cell)
{
    assert(e != NULL && e->shadow != NULL);
    merp_shadow_prefetch_around(e->shadow, cell);
}

void merp_env_occupy(merp_env *e, const float p[3])
{
    if (e->p.environment == MER_ENV_MARKERS)
        mer_markers_remove_sphere(e->markers, p, e->p.rho);
}

int merp_env_blocked(const merp_env *e, const float p[3])
{
    if (e->p.ground_enabled && p[1] < e->p.ground)
        return 1;
    for (uint32_t o = 0; o < e->nobs; o++)
        if (merp_inside_obstacle(&e->obs[o], p))
            return 1;
    return 0;
}

void merp_env_bud_changed(void *env, const float p[3], int sign)
{
    merp_env *e = env;
    if (e->batching)
        merp_env_batch_cast(e, p, sign);
    else if (e->shadow != NULL)
        mer_shadow_cast_at(e->shadow, p, sign);
}

void merp_env_buds_moved(merp_env *e) { e->epoch++; }

uint32_t merp_env_epoch(const merp_env *e) { return e->epoch; }

static int finite3(const float v[3])
{
    return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

mer_result merp_env_add_markers(merp_env *e, const float *xyz, size_t count, mer_error *err)
{
    assert(e != NULL && (xyz != NULL || count == 0));
    float *keep = merp_malloc((count ? count : 1) * 3 * sizeof *keep);
    if (keep == NULL)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for markers");
    size_t k = 0;
    for (size_t i = 0; i < count; i++) {
        const float *p = xyz + 3 * i;
        if (!finite3(p)) {
            merp_free(keep);
            return mer_error_set(err, MER_ERR_INVALID, "points",
                                 "marker %zu is not 3 finite numbers", i);
        }
        if (merp_env_blocked(e, p))
            continue;
        memcpy(keep + 3 * k++, p, 3 * sizeof *p);
    }
    mer_result rc = MER_OK;
    if (k > 0) {
        rc = mer_markers_add(e->markers, keep, k, err);
        e->epoch++; /* quiet buds may see the new markers */
    }
    merp_free(keep);
    return rc;
}

uint64_t merp_env_hash(const merp_env *e, uint64_t h)
{
    /* Obstacles only when there are some, so obstacle-free scenes keep the
     * hashes they always had. */
    if (e->nobs > 0) {
        h = merp_fnv(h, &e->nobs, sizeof e->nobs);
        for (uint32_t o = 0; o < e->nobs; o++) {
            const merp_obstacle *ob = &e->obs[o];
            h = merp_fnv(h, &ob->kind, sizeof ob->kind);
            h = merp_fnv(h, ob->a, sizeof ob->a);
            h = merp_fnv(h, ob->b, sizeof ob->b);
            h = merp_fnv(h, &ob->r, sizeof ob->r);
            if (ob->solid != NULL) {
                uint64_t d = merp_solid_digest(ob->solid);
                h = merp_fnv(h, &d, sizeof d);
            }
        }
    }
    size_t m = mer_markers_count(e->markers);
    float *xyz = merp_malloc((m ? m : 1) * 3 * sizeof *xyz);
    if (xyz != NULL) {
        mer_markers_positions(e->markers, xyz, m);
        h = merp_fnv(h, xyz, m * 3 * sizeof *xyz);
        merp_free(xyz);
    } else {
        h = merp_fnv(h, &m, sizeof m);
    }
    return h;
}
