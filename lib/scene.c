/* meristem — scenes: creation, environment set-up, read access (P09 §3, §4.1, §6). */
#include "config.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "scene_private.h"
#include "vec_private.h"

static mer_result make_grids(mer_scene *s, const mer_params *p, mer_markers **mk,
                             mer_shadow **sh, mer_error *err)
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
    (void)s;
    return rc;
}

mer_result mer_scene_new(const mer_params *params, uint64_t seed, mer_scene **out,
                         mer_error *err)
{
    *out = NULL;
    mer_result rc = mer_params_validate(params, err);
    if (rc != MER_OK)
        return rc;
    mer_scene *s = calloc(1, sizeof *s);
    if (s == NULL)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for a scene");
    mer_params_resolve(params, &s->p);
    mer_rng_seed(&s->rng, seed);
    s->cos_beta = cosf(s->p.branch_angle * MER_DEG2RAD);
    s->sin_beta = sinf(s->p.branch_angle * MER_DEG2RAD);
    s->con_node = MER_NO_NODE;
    s->pipe_n_used = s->p.pipe_n;
    rc = make_grids(s, &s->p, &s->markers, &s->shadow, err);
    if (rc != MER_OK) {
        free(s);
        return rc;
    }
    const mer_params *p = &s->p;
    for (uint32_t i = 0; i < p->seedlings && rc == MER_OK; i++) {
        float x = ((float)i - 0.5f * (float)(p->seedlings - 1)) * p->seedling_spacing;
        float base[3] = {x, p->ground_enabled ? p->ground : 0.0f, 0.0f};
        rc = mer_scene_add_plant(s, base, NULL, err);
    }
    if (rc == MER_OK && p->environment == MER_ENV_MARKERS && p->marker_count > 0 &&
        p->marker_volume != MER_VOLUME_NONE)
        rc = mer_scene_fill_markers(s, p->marker_volume, p->marker_center, p->marker_size,
                                    p->marker_count, err);
    if (rc != MER_OK) {
        mer_scene_free(s);
        return rc;
    }
    *out = s;
    return MER_OK;
}

void mer_scene_free(mer_scene *s)
{
    if (s == NULL)
        return;
    void *arrays[] = {s->parent, s->child, s->bud, s->slot, s->alive, s->plant, s->order,
                      s->born, s->pos, s->dir, s->side, s->len, s->dn, s->qsub, s->nbuds,
                      s->nint, s->vin, s->qb, s->vb, s->quiet, s->mark, s->roots, s->obs, s->bkey,
                      s->bpos, s->bdir, s->bq, s->bv, s->bquiet, s->pq, s->pv, s->pbuds, s->prank,
                      s->pscr, s->ptarget, s->stack};
    for (uint32_t o = 0; o < s->nobs; o++)
        merp_solid_free(s->obs[o].solid);
    for (size_t i = 0; i < sizeof arrays / sizeof arrays[0]; i++)
        free(arrays[i]);
    mer_markers_free(s->markers);
    mer_shadow_free(s->shadow);
    free(s);
}

const mer_params *mer_scene_params(const mer_scene *s) { return &s->p; }

uint32_t mer_scene_step_index(const mer_scene *s) { return s->step; }

static int same_grid(const mer_params *a, const mer_params *b)
{
    return memcmp(a->bounds_min, b->bounds_min, sizeof a->bounds_min) == 0 &&
           memcmp(a->bounds_max, b->bounds_max, sizeof a->bounds_max) == 0;
}

/* mer_markers_remove_if's test: a marker inside an obstacle or below the ground. */
static int blocked_ctx(const float p[3], void *ctx)
{
    const mer_scene *s = ctx;
    return merp_blocked(s, p);
}

mer_result mer_scene_set_params(mer_scene *s, const mer_params *params, mer_error *err)
{
    mer_result rc = mer_params_validate(params, err);
    if (rc != MER_OK)
        return rc;
    mer_params p;
    mer_params_resolve(params, &p);
    int markers_change = !same_grid(&p, &s->p) || p.marker_cell != s->p.marker_cell;
    int ground_change = p.ground_enabled != s->p.ground_enabled || p.ground != s->p.ground;
    int shadow_change = !same_grid(&p, &s->p) || p.voxel != s->p.voxel ||
                        p.shadow_a != s->p.shadow_a || p.shadow_b != s->p.shadow_b ||
                        p.q_max != s->p.q_max || p.environment != s->p.environment ||
                        p.shadow_c != s->p.shadow_c;
    mer_markers *mk = NULL;
    mer_shadow *sh = NULL;
    if (markers_change) {
        rc = mer_markers_new(p.bounds_min, p.bounds_max, p.marker_cell, &mk, err);
        if (rc != MER_OK)
            return rc;
        size_t cnt = mer_markers_count(s->markers);
        float *xyz = malloc((cnt ? cnt : 1) * 3 * sizeof *xyz);
        if (xyz == NULL) {
            mer_markers_free(mk);
            return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for markers");
        }
        mer_markers_positions(s->markers, xyz, cnt);
        rc = mer_markers_add(mk, xyz, cnt, err);
        free(xyz);
        if (rc != MER_OK) {
            mer_markers_free(mk);
            return rc;
        }
    }
    if (shadow_change && p.environment == MER_ENV_SHADOW) {
        rc = mer_shadow_new(p.bounds_min, p.bounds_max, p.voxel, p.shadow_a, p.shadow_b,
                            p.q_max, &sh, err);
        if (rc != MER_OK) {
            mer_markers_free(mk);
            return rc;
        }
    }
    /* Nothing can fail from here on. */
    if (p.pipe_n != s->pipe_n_used) {
        for (uint32_t i = 0; i < s->n; i++)
            if (s->dn[i] > 0.0f)
                s->dn[i] = powf(powf(s->dn[i], 1.0f / s->pipe_n_used), p.pipe_n);
        s->pipe_n_used = p.pipe_n;
    }
    s->p = p;
    s->cos_beta = cosf(p.branch_angle * MER_DEG2RAD);
    s->sin_beta = sinf(p.branch_angle * MER_DEG2RAD);
    s->env_epoch++; /* bud directions or the grid may have changed */
    if (markers_change) {
        mer_markers_free(s->markers);
        s->markers = mk;
    }
    if (shadow_change) {
        mer_shadow_free(s->shadow);
        s->shadow = sh;
        merp_shadow_rebuild(s);
    }
    // Markers the ground now covers go, as they would not have been added below it.
    if (ground_change)
        mer_markers_remove_if(s->markers, blocked_ctx, s);
    return MER_OK;
}

mer_result mer_scene_set_schedule(mer_scene *s, const mer_schedule *schedule, mer_error *err)
{
    mer_params p = s->p;
    p.schedule = *schedule;
    mer_result rc = mer_params_validate(&p, err);
    if (rc != MER_OK)
        return rc;
    s->p.schedule = *schedule; /* no grid depends on the schedule */
    return MER_OK;
}

mer_result mer_scene_add_plant(mer_scene *s, const float base[3], uint32_t *root, mer_error *err)
{
    if (s->nplants >= MER_PLANTS_MAX)
        return mer_error_set(err, MER_ERR_LIMIT, "plants", "a scene holds at most %u plants",
                             MER_PLANTS_MAX);
    float up_end[3] = {base[0], base[1] + s->p.internode_length, base[2]};
    if (merp_blocked(s, base) || merp_blocked(s, up_end))
        return mer_error_set(err, MER_ERR_RANGE, "base",
                             "a plant's base must be above the ground and outside obstacles");
    if (s->nplants == s->cap_plants) {
        uint32_t cap = s->cap_plants ? 2 * s->cap_plants : 8;
        uint32_t *r = realloc(s->roots, cap * sizeof *r);
        if (r == NULL)
            return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for plants");
        s->roots = r;
        s->cap_plants = cap;
    }
    uint32_t id;
    mer_result rc = merp_node_new(s, &id, err);
    if (rc != MER_OK)
        return rc;
    memcpy(s->pos + 3 * id, base, 3 * sizeof *base);
    s->dir[3 * id + 1] = 1.0f;
    /* The seedling's phyllotactic orientation is drawn from the scene's generator:
     * seeds give differently turned seedlings, hence different trees, under shadow
     * propagation too. */
    float az = mer_rng_float(&s->rng) * 6.2831853071795865f;
    s->side[3 * id] = cosf(az);
    s->side[3 * id + 2] = sinf(az);
    s->len[id] = s->p.internode_length;
    /* A seedling is a leaf-bearing tip: the pipe model's leaf diameter from the
     * start, not only after its first step. */
    s->dn[id] = powf(s->p.leaf_diameter, s->pipe_n_used);
    s->plant[id] = s->nplants;
    s->roots[s->nplants++] = id;
    merp_bud_set(s, id, 0, MER_BUD_DORMANT);
    for (uint32_t k = 1; k <= s->p.buds_per_node; k++)
        merp_bud_set(s, id, k, MER_BUD_DORMANT);
    if (root != NULL)
        *root = id;
    return MER_OK;
}

uint32_t mer_scene_plant_count(const mer_scene *s) { return s->nplants; }

/* mer_markers_remove_if's test: a marker inside the obstacle `ctx`. */
static int inside_ctx(const float p[3], void *ctx)
{
    return merp_inside_obstacle(ctx, p);
}

static mer_result add_obstacle(mer_scene *s, const merp_obstacle *o, mer_error *err)
{
    if (s->nobs >= MER_OBSTACLES_MAX)
        return mer_error_set(err, MER_ERR_LIMIT, "obstacles", "a scene holds at most %u obstacles",
                             MER_OBSTACLES_MAX);
    merp_obstacle *a = realloc(s->obs, (s->nobs + 1) * sizeof *a);
    if (a == NULL)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for obstacles");
    s->obs = a;
    s->obs[s->nobs++] = *o;
    merp_shadow_obstacle(s, o, 1);
    // The markers in earlier obstacles or below the ground are gone already: only the
    // new obstacle needs asking (O(markers), not O(markers × obstacles)).
    mer_markers_remove_if(s->markers, inside_ctx, &s->obs[s->nobs - 1]);
    return MER_OK;
}

static int finite3(const float v[3])
{
    return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

mer_result mer_scene_add_box(mer_scene *s, const float min[3], const float max[3], mer_error *err)
{
    // Not finite, a box's voxel range would be cast from ±inf or NaN to int.
    if (!finite3(min))
        return mer_error_set(err, MER_ERR_INVALID, "min", "a box's min must be 3 finite numbers");
    if (!finite3(max))
        return mer_error_set(err, MER_ERR_INVALID, "max", "a box's max must be 3 finite numbers");
    for (int a = 0; a < 3; a++)
        if (!(max[a] > min[a]))
            return mer_error_set(err, MER_ERR_RANGE, "max", "a box's max must exceed its min on every axis");
    merp_obstacle o;
    memset(&o, 0, sizeof o);
    o.kind = MERP_OBS_BOX;
    memcpy(o.a, min, sizeof o.a);
    memcpy(o.b, max, sizeof o.b);
    return add_obstacle(s, &o, err);
}

mer_result mer_scene_add_sphere(mer_scene *s, const float center[3], float radius, mer_error *err)
{
    if (!finite3(center))
        return mer_error_set(err, MER_ERR_INVALID, "center", "a sphere's center must be 3 finite numbers");
    if (!(radius > 0.0f) || !isfinite(radius))
        return mer_error_set(err, MER_ERR_RANGE, "radius", "radius must be finite and > 0, got %g",
                             (double)radius);
    merp_obstacle o;
    memset(&o, 0, sizeof o);
    o.kind = MERP_OBS_SPHERE;
    memcpy(o.a, center, sizeof o.a);
    o.r = radius;
    return add_obstacle(s, &o, err);
}

/* The checks mer_scene_add_mesh and mer_scene_fill_mesh_markers share. */
static mer_result check_mesh(const float *xyz, size_t triangles, mer_error *err)
{
    if (triangles == 0 || xyz == NULL)
        return mer_error_set(err, MER_ERR_INVALID, "triangles", "a mesh needs at least one triangle");
    if (triangles > MER_MESH_TRIANGLES_MAX)
        return mer_error_set(err, MER_ERR_LIMIT, "triangles",
                             "a mesh holds at most %u triangles, got %zu",
                             (unsigned)MER_MESH_TRIANGLES_MAX, triangles);
    float lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    for (size_t i = 0; i < 9 * triangles; i++) {
        float x = xyz[i];
        if (!isfinite(x))
            return mer_error_set(err, MER_ERR_INVALID, "xyz",
                                 "coordinate %zu of triangle %zu is not a finite number",
                                 i % 9, i / 9);
        if (!(fabsf(x) <= MER_MESH_COORD_MAX))
            return mer_error_set(err, MER_ERR_RANGE, "xyz",
                                 "mesh coordinates must lie in [-%g, %g]; triangle %zu has %g",
                                 (double)MER_MESH_COORD_MAX, (double)MER_MESH_COORD_MAX, i / 9,
                                 (double)x);
        int a = (int)(i % 3);
        if (i < 3 || x < lo[a])
            lo[a] = x;
        if (i < 3 || x > hi[a])
            hi[a] = x;
    }
    for (int a = 0; a < 3; a++)
        if (!(hi[a] > lo[a]))
            return mer_error_set(err, MER_ERR_RANGE, "xyz",
                                 "the mesh is flat along %c: it encloses no volume", "xyz"[a]);
    return MER_OK;
}

mer_result mer_scene_add_mesh(mer_scene *s, const float *xyz, size_t triangles, mer_error *err)
{
    mer_result rc = check_mesh(xyz, triangles, err);
    if (rc != MER_OK)
        return rc;
    if (s->nobs >= MER_OBSTACLES_MAX) /* before the voxelization, which costs */
        return mer_error_set(err, MER_ERR_LIMIT, "obstacles", "a scene holds at most %u obstacles",
                             MER_OBSTACLES_MAX);
    merp_obstacle o;
    memset(&o, 0, sizeof o);
    o.kind = MERP_OBS_MESH;
    rc = merp_solid_new(xyz, triangles, &o.solid, err);
    if (rc != MER_OK)
        return rc;
    merp_solid_bounds(o.solid, o.a, o.b);
    rc = add_obstacle(s, &o, err);
    if (rc != MER_OK)
        merp_solid_free(o.solid);
    return rc;
}

mer_result mer_scene_fill_mesh_markers(mer_scene *s, const float *xyz, size_t triangles,
                                       uint32_t count, mer_error *err)
{
    mer_result rc = check_mesh(xyz, triangles, err);
    if (rc != MER_OK)
        return rc;
    if (count > MER_MESH_FILL_MAX)
        return mer_error_set(err, MER_ERR_LIMIT, "count",
                             "a mesh volume takes at most %u markers, got %u",
                             (unsigned)MER_MESH_FILL_MAX, (unsigned)count);
    if (count == 0)
        return MER_OK;
    merp_solid *solid;
    rc = merp_solid_new(xyz, triangles, &solid, err);
    if (rc != MER_OK)
        return rc;
    size_t ncand = merp_solid_candidates(solid, NULL);
    uint32_t *cand = malloc((ncand ? ncand : 1) * sizeof *cand);
    float *pts = malloc((size_t)count * 3 * sizeof *pts);
    if (cand == NULL || pts == NULL) {
        rc = mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for mesh markers");
        goto done;
    }
    merp_solid_candidates(solid, cand);
    /* Rejection sampling: a cell drawn uniformly among those that may hold inside
     * points (equal volumes), a point uniform in it, kept if inside. Uniform over
     * the inside, and far fewer misses than drawing from the bounding box. */
    mer_rng saved = s->rng;
    uint64_t budget = (uint64_t)count * MER_MESH_FILL_TRIES + MER_MESH_FILL_TRIES_MIN;
    uint64_t tries = 0;
    for (uint32_t i = 0; i < count && rc == MER_OK; i++) {
        for (;;) {
            if (ncand == 0 || tries++ >= budget) {
                s->rng = saved;
                rc = mer_error_set(err, MER_ERR_RANGE, "xyz",
                                   "the mesh encloses too little volume: %u of %u markers "
                                   "placed in %llu draws",
                                   (unsigned)i, (unsigned)count, (unsigned long long)budget);
                break;
            }
            uint32_t c = cand[mer_rng_below(&s->rng, (uint32_t)ncand)];
            float f[3];
            for (int a = 0; a < 3; a++)
                f[a] = mer_rng_float(&s->rng);
            float *p = pts + 3 * (size_t)i;
            merp_solid_cell_point(solid, c, f, p);
            if (merp_solid_inside(solid, p))
                break;
        }
    }
    if (rc == MER_OK)
        rc = mer_scene_add_markers(s, pts, count, err);
done:
    free(cand);
    free(pts);
    merp_solid_free(solid);
    return rc;
}

mer_result mer_scene_add_markers(mer_scene *s, const float *xyz, size_t count, mer_error *err)
{
    float *keep = malloc((count ? count : 1) * 3 * sizeof *keep);
    if (keep == NULL)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for markers");
    size_t k = 0;
    for (size_t i = 0; i < count; i++) {
        const float *p = xyz + 3 * i;
        if (!finite3(p)) {
            free(keep);
            return mer_error_set(err, MER_ERR_INVALID, "points",
                                 "marker %zu is not 3 finite numbers", i);
        }
        if (merp_blocked(s, p))
            continue;
        memcpy(keep + 3 * k++, p, 3 * sizeof *p);
    }
    mer_result rc = MER_OK;
    if (k > 0) {
        rc = mer_markers_add(s->markers, keep, k, err);
        s->env_epoch++; /* quiet buds may see the new markers */
    }
    free(keep);
    return rc;
}

/* A point uniform in the unit ball, by rejection (deterministic: the same draws). */
static void unit_ball(mer_rng *rng, float out[3])
{
    do {
        for (int a = 0; a < 3; a++)
            out[a] = mer_rng_range(rng, -1.0f, 1.0f);
    } while (v3_dot(out, out) > 1.0f);
}

mer_result mer_scene_fill_markers(mer_scene *s, uint32_t kind, const float center[3],
                                  const float size[3], uint32_t count, mer_error *err)
{
    if (kind < MER_VOLUME_BOX || kind > MER_VOLUME_CONE)
        return mer_error_set(err, MER_ERR_RANGE, "marker_volume",
                             "marker_volume must be from 1 to 5, got %u", (unsigned)kind);
    for (int a = 0; a < 3; a++)
        if (!(size[a] >= 0.0f))
            return mer_error_set(err, MER_ERR_RANGE, "marker_size", "marker_size must be >= 0");
    float *xyz = malloc((count ? count : 1) * 3 * sizeof *xyz);
    if (xyz == NULL)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for markers");
    for (uint32_t i = 0; i < count; i++) {
        float u[3], *p = xyz + 3 * (size_t)i;
        switch (kind) {
        case MER_VOLUME_BOX:
            for (int a = 0; a < 3; a++)
                u[a] = mer_rng_range(&s->rng, -1.0f, 1.0f) * size[a];
            break;
        case MER_VOLUME_SPHERE:
            unit_ball(&s->rng, u);
            for (int a = 0; a < 3; a++)
                u[a] *= size[0];
            break;
        case MER_VOLUME_ELLIPSOID:
            unit_ball(&s->rng, u);
            for (int a = 0; a < 3; a++)
                u[a] *= size[a];
            break;
        case MER_VOLUME_CYLINDER:
            do {
                u[0] = mer_rng_range(&s->rng, -1.0f, 1.0f);
                u[2] = mer_rng_range(&s->rng, -1.0f, 1.0f);
            } while (u[0] * u[0] + u[2] * u[2] > 1.0f);
            u[0] *= size[0];
            u[2] *= size[0];
            u[1] = mer_rng_range(&s->rng, -1.0f, 1.0f) * size[1];
            break;
        default: /* MER_VOLUME_CONE: rejection from the bounding cylinder */
            for (;;) {
                u[0] = mer_rng_range(&s->rng, -1.0f, 1.0f);
                u[2] = mer_rng_range(&s->rng, -1.0f, 1.0f);
                float t = mer_rng_float(&s->rng); /* 0 at the base, 1 at the apex */
                float rr = 1.0f - t;
                if (u[0] * u[0] + u[2] * u[2] <= rr * rr) {
                    u[1] = (2.0f * t - 1.0f) * size[1];
                    break;
                }
            }
            u[0] *= size[0];
            u[2] *= size[0];
            break;
        }
        for (int a = 0; a < 3; a++)
            p[a] = center[a] + u[a];
    }
    mer_result rc = mer_scene_add_markers(s, xyz, count, err);
    free(xyz);
    return rc;
}

size_t mer_scene_marker_count(const mer_scene *s) { return mer_markers_count(s->markers); }

size_t mer_scene_markers(const mer_scene *s, float *out, size_t cap)
{
    return mer_markers_positions(s->markers, out, cap);
}

uint32_t mer_scene_node_bound(const mer_scene *s) { return s->n; }

mer_result mer_scene_node(const mer_scene *s, uint32_t id, mer_node *out, mer_error *err)
{
    if (id >= s->n)
        return mer_error_set(err, MER_ERR_RANGE, "node", "node must be from 0 to %u, got %u",
                             s->n ? (unsigned)(s->n - 1) : 0u, (unsigned)id);
    memset(out, 0, sizeof *out);
    out->id = id;
    out->parent = s->parent[id];
    out->plant = s->plant[id];
    out->order = s->order[id];
    out->alive = s->alive[id];
    out->born = s->born[id];
    out->main_child = s->child[3 * id];
    out->lateral_child[0] = s->child[3 * id + 1];
    out->lateral_child[1] = s->child[3 * id + 2];
    out->terminal_bud = s->bud[3 * id];
    out->lateral_bud[0] = s->bud[3 * id + 1];
    out->lateral_bud[1] = s->bud[3 * id + 2];
    memcpy(out->base, s->pos + 3 * id, sizeof out->base);
    memcpy(out->dir, s->dir + 3 * id, sizeof out->dir);
    merp_bud_dir(s, id, 1, out->bud_dir[0]);
    merp_bud_dir(s, id, 2, out->bud_dir[1]);
    out->length = s->len[id];
    out->diameter = s->dn[id] > 0.0f ? powf(s->dn[id], 1.0f / s->pipe_n_used) : 0.0f;
    out->q = s->qsub[id];
    return MER_OK;
}

void mer_scene_summary(const mer_scene *s, mer_summary *out)
{
    memset(out, 0, sizeof *out);
    out->step = s->step;
    out->plants = s->nplants;
    out->node_bound = s->n;
    out->markers = (uint32_t)mer_markers_count(s->markers);
    float lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    float base_y = 0.0f, crown = 0.0f;
    int any = 0, any_root = 0, any_branch = 0;
    for (uint32_t r = 0; r < s->nplants; r++) {
        float y = s->pos[3 * s->roots[r] + 1];
        if (!any_root || y < base_y)
            base_y = y;
        any_root = 1;
    }
    for (uint32_t i = 0; i < s->n; i++) {
        if (!s->alive[i])
            continue;
        out->internodes++;
        for (int k = 0; k < 3; k++) {
            out->buds += s->bud[3 * i + k] == MER_BUD_DORMANT;
            out->flowers += s->bud[3 * i + k] == MER_BUD_FLOWER;
        }
        float e[3];
        merp_node_end(s, i, e);
        const float *b = s->pos + 3 * i;
        for (int a = 0; a < 3; a++) {
            float mn = b[a] < e[a] ? b[a] : e[a], mx = b[a] < e[a] ? e[a] : b[a];
            if (!any || mn < lo[a])
                lo[a] = mn;
            if (!any || mx > hi[a])
                hi[a] = mx;
        }
        any = 1;
        if (s->slot[i] != 0 && (!any_branch || b[1] < crown)) {
            crown = b[1];
            any_branch = 1;
        }
    }
    memcpy(out->bbox_min, lo, sizeof lo);
    memcpy(out->bbox_max, hi, sizeof hi);
    if (any) {
        out->height = hi[1] - base_y;
        float wx = hi[0] - lo[0], wz = hi[2] - lo[2];
        out->crown_width = wx > wz ? wx : wz;
        out->crown_base = any_branch ? crown - base_y : out->height;
        out->crown_depth = out->height - out->crown_base;
    }
}

static uint64_t fnv(uint64_t h, const void *data, size_t n)
{
    const unsigned char *p = data;
    for (size_t i = 0; i < n; i++) {
        h ^= p[i];
        h *= UINT64_C(1099511628211);
    }
    return h;
}

uint64_t mer_scene_hash(const mer_scene *s)
{
    uint64_t h = UINT64_C(1469598103934665603);
    h = fnv(h, &s->step, sizeof s->step);
    h = fnv(h, &s->n, sizeof s->n);
    h = fnv(h, s->rng.s, sizeof s->rng.s);
    for (uint32_t i = 0; i < s->n; i++) {
        h = fnv(h, &s->alive[i], 1);
        h = fnv(h, &s->parent[i], 4);
        h = fnv(h, s->child + 3 * i, 12);
        h = fnv(h, s->bud + 3 * i, 3);
        h = fnv(h, &s->order[i], 4);
        h = fnv(h, &s->plant[i], 4);
        h = fnv(h, &s->born[i], 4);
        h = fnv(h, s->pos + 3 * i, 12);
        h = fnv(h, s->dir + 3 * i, 12);
        h = fnv(h, s->side + 3 * i, 12);
        h = fnv(h, &s->len[i], 4);
        h = fnv(h, &s->dn[i], 4);
    }
    /* Obstacles only when there are some, so obstacle-free scenes keep the
     * hashes they always had. */
    if (s->nobs > 0) {
        h = fnv(h, &s->nobs, sizeof s->nobs);
        for (uint32_t o = 0; o < s->nobs; o++) {
            const merp_obstacle *ob = &s->obs[o];
            h = fnv(h, &ob->kind, sizeof ob->kind);
            h = fnv(h, ob->a, sizeof ob->a);
            h = fnv(h, ob->b, sizeof ob->b);
            h = fnv(h, &ob->r, sizeof ob->r);
            if (ob->solid != NULL) {
                uint64_t d = merp_solid_digest(ob->solid);
                h = fnv(h, &d, sizeof d);
            }
        }
    }
    size_t m = mer_markers_count(s->markers);
    float *xyz = malloc((m ? m : 1) * 3 * sizeof *xyz);
    if (xyz != NULL) {
        mer_markers_positions(s->markers, xyz, m);
        h = fnv(h, xyz, m * 3 * sizeof *xyz);
        free(xyz);
    } else {
        h = fnv(h, &m, sizeof m);
    }
    return h;
}
