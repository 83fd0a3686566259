/* meristem — the environment every growth model may query: the markers of space
 * colonization, the shadow grid, obstacles (box, sphere, mesh), the ground (P09
 * §4.1, §6). Not installed. A model asks what light Q and direction V a bud at p
 * facing d perceives (merp_env_perceive) and whether a point is blocked; the
 * skeleton tells it when a dormant bud appears or goes (merp_env_bud_changed). */
#ifndef MERISTEM_ENV_H
#define MERISTEM_ENV_H

#include <assert.h>
#include <stddef.h>
#include <stdint.h>

#include <meristem/markers.h>
#include <meristem/params.h>
#include <meristem/result.h>
#include <meristem/rng.h>
#include <meristem/shadow.h>

enum { MERP_OBS_BOX = 1, MERP_OBS_SPHERE = 2, MERP_OBS_MESH = 3 };

/* `count` casts of a bud's shadow pyramid at voxel (i, j, k) (negative: lifted). */
typedef struct merp_shadow_cast {
    int32_t i, j, k, count;
} merp_shadow_cast;

/* A triangle mesh's solid inside, voxelized once (solid.c). */
typedef struct merp_solid merp_solid;

typedef struct merp_obstacle {
    uint32_t kind;
    float a[3]; /* box min, sphere centre, or mesh bounding-box min */
    float b[3]; /* box max, or mesh bounding-box max */
    float r;    /* sphere radius */
    merp_solid *solid; /* mesh only; owned by the environment's obstacle array */
} merp_obstacle;

typedef struct merp_env {
    mer_params p;       /* the scene's parameters, resolved: ground, grids, perception */
    mer_markers *markers;
    mer_shadow *shadow; /* NULL unless environment == MER_ENV_SHADOW */
    merp_obstacle *obs;
    uint32_t nobs;
    uint32_t epoch;     /* bumped whenever markers are added or buds move: see merp_env_epoch */
    /* bud casts held back between merp_env_batch_begin and _end (shadow_batch.c) */
    int batching;
    uint64_t *pend, *pend_tmp;
    size_t npend, pend_cap;
    merp_shadow_cast *casts; /* the held-back casts merged by voxel */
    size_t casts_cap;
} merp_env;

/* Grids built ahead of a parameter change, so that a failure leaves the old ones. */
typedef struct merp_env_change {
    mer_markers *markers; /* new marker grid (markers copied in), or NULL: keep */
    mer_shadow *shadow;   /* new shadow grid, or NULL */
    int markers_change, shadow_change, ground_change;
} merp_env_change;

/* env.c */
/* Builds the grids of resolved parameters `p`. MER_ERR_NOMEM. */
mer_result merp_env_init(merp_env *e, const mer_params *p, mer_error *err);
void merp_env_free(merp_env *e);
/* A deep copy of `src` into `dst` (whose old contents are ignored): markers,
 * shadow grid and obstacles, bit for bit. MER_ERR_NOMEM (dst is empty then).
 * O(markers + voxels + mesh obstacles' triangles and cells). */
mer_result merp_env_clone(const merp_env *src, merp_env *dst, mer_error *err);
/* Prepares the grids `p` needs (O(markers) when the marker grid changes); nothing
 * of `e` changes. Then merp_env_commit, which cannot fail, swaps them in; when it
 * returns 1 the shadow grid is new and empty: the caller casts its buds and then
 * calls merp_env_cast_obstacles. */
mer_result merp_env_prepare(const merp_env *e, const mer_params *p, merp_env_change *c,
                            mer_error *err);
int merp_env_commit(merp_env *e, const mer_params *p, merp_env_change *c);
/* Removes markers the ground now covers (after a commit that changed the ground). */
void merp_env_drop_covered(merp_env *e, const merp_env_change *c);
/* Light Q and optimal direction V (3 floats each) of `n` buds at `pos` facing
 * `dir` (3 floats each): space colonization or shadow propagation, P09 §4.1. Under
 * markers, quiet[b] is set to 1 when bud b has no marker in its perception volume
 * (`quiet` may not be NULL then). O(n · neighbourhood). */
mer_result merp_env_perceive(merp_env *e, size_t n, const float *pos, const float *dir,
                             float *q, float *v, uint8_t *quiet, mer_error *err);
/* Under shadow propagation, merp_env_perceive in parts, so that V can be
 * computed for the buds that grow only: the voxel of a bud at `pos`, which a
 * model may keep while merp_env_epoch stays (the grid and the buds' places are
 * the same then); the light Q of buds in the voxels cells[0, n) into q[0, n)
 * (O(n), the voxels read ahead: a big tree's buds are spread over a grid far
 * larger than the cache); and the optimal direction V of one bud at `pos`
 * facing `dir` (O(26)). */
uint32_t merp_env_cell(const merp_env *e, const float pos[3]);
void merp_env_light_cells(const merp_env *e, const uint32_t *cells, size_t n, float *q);
/* The shadow grid read in place, for a walk over every bud that reads each
 * voxel itself (P09's environment input), with no call per voxel: Q = max(C − s
 * + a, 0) as merp_shadow_light_cell gives it, bit for bit. Valid until the grid
 * changes or is rebuilt. */
typedef struct merp_light {
    const uint32_t *s; /* the voxels' shade, in units of `unit` */
    size_t n;          /* voxels */
    float unit, c, a;  /* a/4096; the light C of an unshaded voxel; a */
} merp_light;
merp_light merp_env_light(const merp_env *e);
static inline float merp_light_at(const merp_light *l, uint32_t cell)
{
    assert(cell < l->n);
    float s = (float)(int32_t)l->s[cell] * l->unit;
    float q = l->c - s + l->a;
    return q > 0.0f ? q : 0.0f;
}
/* Asks the memory for voxel `cell` ahead of its read: a big tree's buds are
 * spread over a grid far larger than the cache. */
static inline void merp_light_prefetch(const merp_light *l, uint32_t cell)
{
#if defined(__GNUC__)
    __builtin_prefetch(l->s + cell);
#else
    (void)l;
    (void)cell;
#endif
}
void merp_env_direction(const merp_env *e, const float pos[3], const float dir[3], float v[3]);
/* merp_env_direction of a bud in voxel `cell` (merp_env_cell of its place), bit
 * for bit, the perception cone's cos(θ/2) given (merp_env_cone): a walk over many
 * buds computes neither the voxel nor the cone again. O(26). */
float merp_env_cone(const merp_env *e);
void merp_env_direction_cell(const merp_env *e, uint32_t cell, const float dir[3], float cone,
                             float v[3]);
/* Asks the memory ahead for what merp_env_direction of a bud in voxel `cell`
 * reads: nine rows of the grid, far apart. */
void merp_env_direction_ahead(const merp_env *e, uint32_t cell);
/* A bud at p that may not grow still clears its occupancy zone of markers. */
void merp_env_occupy(merp_env *e, const float p[3]);
/* 1 if p is below the ground or inside an obstacle. O(obstacles). */
int merp_env_blocked(const merp_env *e, const float p[3]);
/* A dormant bud appeared (+1) or went (-1) at p: its shadow follows (merp_bud_fn). */
void merp_env_bud_changed(void *env, const float p[3], int sign);
/* Buds moved (bend, new branch angle): perception results cached against the
 * epoch are stale. */
void merp_env_buds_moved(merp_env *e);
/* A counter that changes whenever what a bud perceives may have changed other than
 * by growth: markers added, buds moved. */
uint32_t merp_env_epoch(const merp_env *e);
/* Adds the points of `xyz` that are finite and not blocked. MER_ERR_INVALID names
 * the first non-finite one (nothing added then). */
mer_result merp_env_add_markers(merp_env *e, const float *xyz, size_t count, mer_error *err);
/* Folds obstacles (only when there are some) and marker positions into `h`. */
uint64_t merp_env_hash(const merp_env *e, uint64_t h);

/* shadow_batch.c: between begin and end the shadows of buds that appear or go
 * (merp_env_bud_changed) are held back, and end casts them all, sorted by voxel:
 * the grid ends exactly as if each had been cast at once, but nothing may read
 * it in between. O(casts + pyramids' voxels). */
void merp_env_batch_begin(merp_env *e);
void merp_env_batch_cast(merp_env *e, const float p[3], int sign);
void merp_env_batch_end(merp_env *e);

/* shadow.c: the voxel index of p (clamped into the grid, as mer_shadow_cast_at
 * does), the number of voxels, and `count` casts of a bud's pyramid at a voxel
 * (negative: lifted). */
uint32_t merp_shadow_cell(const mer_shadow *sh, const float p[3]);
/* mer_shadow_light of a bud in voxel `cell`; of buds in cells[0, n) into q; the
 * grid read in place under light C (merp_env_light). */
float merp_shadow_light_cell(const mer_shadow *sh, uint32_t cell, float c);
merp_light merp_shadow_light_view(const mer_shadow *sh, float c);
/* Asks the memory for the 3 × 3 rows about voxel `cell` that
 * mer_shadow_direction reads. */
void merp_shadow_prefetch_around(const mer_shadow *sh, uint32_t cell);
/* cos(θ/2) of a perception cone of θ degrees (−1 from 360°), and
 * mer_shadow_direction of a bud in voxel `cell` under that cone. */
float merp_shadow_cone(float theta);
void merp_shadow_direction_cell(const mer_shadow *sh, uint32_t cell, const float dir[3],
                                float cos_half, uint32_t mode, float out[3]);
void merp_shadow_light_cells(const mer_shadow *sh, const uint32_t *cells, size_t n, float c,
                             float *q);
size_t merp_shadow_cells(const mer_shadow *sh);
void merp_shadow_cast_cell(mer_shadow *sh, uint32_t cell, int32_t count);
/* The voxel (i, j, k) of index `cell`, as a cast. */
merp_shadow_cast merp_shadow_cast_of(const mer_shadow *sh, uint32_t cell, int32_t count);
/* Casts c[0, n), given by non-decreasing j, layer by layer: every pyramid's
 * square in one layer of the grid is added before the next layer, so a layer
 * is brought into the cache once rather than once per pyramid that reaches it.
 * The same grid as casting each. O(n · q_max + pyramids' voxels + layers). */
void merp_shadow_cast_layers(mer_shadow *sh, const merp_shadow_cast *c, size_t n);

/* markers.c, shadow.c: deep copies, grids and scratch included. MER_ERR_NOMEM. */
mer_result merp_markers_clone(const mer_markers *m, mer_markers **out, mer_error *err);
mer_result merp_shadow_clone(const mer_shadow *sh, mer_shadow **out, mer_error *err);
/* The markers by index, dead ones too, for a checkpoint (scene_io.c), and back
 * into an empty set `m`: MER_ERR_FORMAT for damaged input, MER_ERR_NOMEM. */
typedef struct merp_bytes_out merp_bytes_out;
typedef struct merp_bytes_in merp_bytes_in;
void merp_markers_save(const mer_markers *m, merp_bytes_out *out);
mer_result merp_markers_load(mer_markers *m, merp_bytes_in *in, mer_error *err);
/* The shadow grid's voxels, and back into a grid of the same size. */
void merp_shadow_save(const mer_shadow *sh, merp_bytes_out *out);
mer_result merp_shadow_load(mer_shadow *sh, merp_bytes_in *in, mer_error *err);

/* obstacles.c */
/* Whether p is inside obstacle o. */
int merp_inside_obstacle(const merp_obstacle *o, const float *p);
/* Adds an obstacle (its shadow, and removes the markers inside it). The
 * environment takes the solid of a mesh obstacle on success. MER_ERR_LIMIT. */
mer_result merp_env_add_obstacle(merp_env *e, const merp_obstacle *o, mer_error *err);
/* Casts every obstacle's shadow (after the grid was rebuilt). */
void merp_env_cast_obstacles(merp_env *e);
/* The checks of a triangle soup (9 floats per triangle) for a mesh obstacle or a
 * mesh volume of markers: count, finite, in range, not flat. */
mer_result merp_check_mesh(const float *xyz, size_t triangles, mer_error *err);
/* Refuses (MER_ERR_RANGE naming `field`) a mesh whose inside tests would cost a
 * scene of parameters `p` holding `markers` markers more than
 * MERP_SOLID_WORK_MAX: the shadow cast asks two per voxel, the marker sweep one
 * per marker, both within the bounds. O(the solid's cells). */
mer_result merp_check_mesh_work(const merp_solid *solid, const mer_params *p, size_t markers,
                                const char *field, mer_error *err);
mer_result merp_env_add_box(merp_env *e, const float min[3], const float max[3], mer_error *err);
mer_result merp_env_add_sphere(merp_env *e, const float center[3], float radius, mer_error *err);
mer_result merp_env_add_mesh(merp_env *e, const float *xyz, size_t triangles, mer_error *err);

/* volumes.c: markers drawn from `rng` in a volume (P09 §6). */
/* A point uniform in the unit ball, by rejection (deterministic: the same draws). */
void merp_unit_ball(mer_rng *rng, float out[3]);
/* `count` points drawn from `rng` in volume `kind` (a mer_volume_kind, checked)
 * of half-extents `size` about `center`, into xyz (3 floats each): what
 * merp_env_fill_volume adds, for a caller that clips them first. O(count). */
void merp_volume_points(mer_rng *rng, uint32_t kind, const float center[3], const float size[3],
                        uint32_t count, float *xyz);
mer_result merp_env_fill_volume(merp_env *e, mer_rng *rng, uint32_t kind, const float center[3],
                                const float size[3], uint32_t count, mer_error *err);
mer_result merp_env_fill_mesh(merp_env *e, mer_rng *rng, const float *xyz, size_t triangles,
                              uint32_t count, mer_error *err);

/* solid.c: the inside of a triangle soup (9 floats per triangle, finite, not
 * empty; checked by the caller). The definition, its robustness and costs are at
 * the top of solid.c. merp_solid_new copies the triangles; O(triangles + cells +
 * triangle-cell pairs), the pairs bounded there. */
mer_result merp_solid_new(const float *xyz, size_t triangles, merp_solid **out, mer_error *err);
void merp_solid_free(merp_solid *s);
/* A solid of the same triangles. As merp_solid_new. */
mer_result merp_solid_clone(const merp_solid *s, merp_solid **out, mer_error *err);
/* Its triangles (9 floats each), as given to merp_solid_new. */
const float *merp_solid_triangles(const merp_solid *s, size_t *count);
/* 1 inside, 0 outside. O(1) away from the surface, else O(the triangles listed
 * in the few cells each axis walks). */
int merp_solid_inside(const merp_solid *s, const float p[3]);
void merp_solid_bounds(const merp_solid *s, float lo[3], float hi[3]);
/* FNV-1a of the triangles' bytes, computed once. */
uint64_t merp_solid_digest(const merp_solid *s);
/* The crossing tests that queries spread at `density` per unit volume over the
 * box [lo, hi] cost in all (the O(1) answers off the surface aside): the work a
 * mesh puts on a scene whose grids fill that box. O(cells). */
double merp_solid_work(const merp_solid *s, const float lo[3], const float hi[3], double density);
/* The most that work may be: a mesh whose cells are coarse where the scene
 * queries it (a mesh in raw quantized units, say, thousands of voxels across
 * one cell) is refused rather than left to cost seconds on every cast. */
#define MERP_SOLID_WORK_MAX 5e7
/* The cells that may hold inside points (IN or SURFACE), by index, into `out`
 * (NULL: count only). Returns their number. O(cells). */
size_t merp_solid_candidates(const merp_solid *s, uint32_t *out);
/* The volume of one cell. */
double merp_solid_cell_volume(const merp_solid *s);
/* The point at fractions f (each in [0, 1)) across cell `cell`. */
void merp_solid_cell_point(const merp_solid *s, uint32_t cell, const float f[3], float out[3]);

#endif
