/* meristem — the scene's full struct and the helpers scene.c, tree.c, grow.c, solid.c and
 * edit.c share. Not installed. Helpers use the `merp_` prefix: they are not part
 * of the API, and the library's version script (mer_*) keeps them unexported. */
#ifndef MERISTEM_SCENE_PRIVATE_H
#define MERISTEM_SCENE_PRIVATE_H

#include <stddef.h>
#include <stdint.h>

#include <meristem/markers.h>
#include <meristem/params.h>
#include <meristem/rng.h>
#include <meristem/scene.h>
#include <meristem/shadow.h>

#define MERP_BRANCH_FLAG UINT32_C(0x80000000)

enum { MERP_OBS_BOX = 1, MERP_OBS_SPHERE = 2, MERP_OBS_MESH = 3 };

/* A triangle mesh's solid inside, voxelized once (solid.c). */
typedef struct merp_solid merp_solid;

typedef struct merp_obstacle {
    uint32_t kind;
    float a[3]; /* box min, sphere centre, or mesh bounding-box min */
    float b[3]; /* box max, or mesh bounding-box max */
    float r;    /* sphere radius */
    merp_solid *solid; /* mesh only; owned by the scene's obstacle array */
} merp_obstacle;

struct mer_scene {
    mer_params p;
    mer_rng rng;
    uint32_t step;

    /* Nodes (metamers), struct of arrays indexed by id. Slot k of a node: 0 is the
     * main continuation / terminal bud, 1 and 2 the lateral ones. */
    uint32_t n, cap;
    uint32_t *parent;
    uint32_t *child;   /* 3 per node: main, lateral 1, lateral 2 (MER_NO_NODE) */
    uint8_t *bud;      /* 3 per node: mer_bud_state of terminal, lateral 1, lateral 2 */
    uint8_t *slot;     /* which slot of the parent this node grew from */
    uint8_t *alive;
    uint32_t *plant, *order, *born;
    float *pos, *dir, *side; /* 3 per node: base, unit direction, phyllotactic side */
    float *len;
    float *dn;         /* d^n of the pipe model, never decreasing (memory) */
    float *qsub;       /* light of the subtree's eligible buds, last pass */
    uint32_t *nbuds;   /* eligible buds in the subtree, last pass */
    uint32_t *nint;    /* live internodes in the subtree, last pass */
    float *vin;        /* resource entering the node, last pass */
    float *qb, *vb;    /* 3 per node: Q and v of each bud, last pass */
    uint32_t *quiet;   /* 3 per node: env_epoch + 1 when the bud's marker neighbourhood was empty */
    uint32_t env_epoch; /* bumped whenever markers are added or buds move (bend, new grid) */
    float cos_beta, sin_beta; /* of the branch angle */
    uint8_t *mark;     /* scratch */
    float pipe_n_used; /* the n that dn was computed with */

    uint32_t nplants, cap_plants;
    uint32_t *roots;

    mer_markers *markers;
    mer_shadow *shadow; /* NULL unless environment == MER_ENV_SHADOW */
    merp_obstacle *obs;
    uint32_t nobs;

    uint32_t con_node, con_slot; /* growth constraint, con_node == MER_NO_NODE: none */

    /* per-round scratch: eligible buds */
    uint32_t *bkey;            /* 3·node + slot */
    float *bpos, *bdir, *bq, *bv;
    uint8_t *bquiet;
    size_t bn, bcap;
    /* priority scratch */
    float *pq, *pv;
    uint32_t *pbuds, *prank, *pscr, *ptarget;
    size_t pcap;
    uint32_t *stack;
    size_t stack_cap;
};

/* tree.c */
mer_result merp_node_new(mer_scene *s, uint32_t *id, mer_error *err);
void merp_node_end(const mer_scene *s, uint32_t i, float out[3]);
void merp_bud_dir(const mer_scene *s, uint32_t i, uint32_t k, float out[3]);
void merp_bud_set(mer_scene *s, uint32_t i, uint32_t k, uint8_t state);
mer_result merp_subtree(mer_scene *s, uint32_t root, size_t *count, mer_error *err);
mer_result merp_kill(mer_scene *s, uint32_t root, mer_error *err);
void merp_shadow_rebuild(mer_scene *s);
void merp_shadow_obstacle(mer_scene *s, const merp_obstacle *o, int sign);
int merp_blocked(const mer_scene *s, const float p[3]);
/* Whether p is inside obstacle o. */
int merp_inside_obstacle(const merp_obstacle *o, const float *p);
void merp_side_next(const float side_prev[3], const float d[3], float divergence_deg,
                    float out[3]);

/* solid.c: the inside of a triangle soup (9 floats per triangle, finite, not
 * empty; checked by the caller). The definition, its robustness and costs are at
 * the top of solid.c. merp_solid_new copies the triangles; O(triangles + cells +
 * triangle-cell pairs), the pairs bounded there. */
mer_result merp_solid_new(const float *xyz, size_t triangles, merp_solid **out, mer_error *err);
void merp_solid_free(merp_solid *s);
/* 1 inside, 0 outside. O(1) away from the surface, else O(the triangles listed
 * in the few cells each axis walks). */
int merp_solid_inside(const merp_solid *s, const float p[3]);
void merp_solid_bounds(const merp_solid *s, float lo[3], float hi[3]);
/* FNV-1a of the triangles' bytes, computed once. */
uint64_t merp_solid_digest(const merp_solid *s);
/* The cells that may hold inside points (IN or SURFACE), by index, into `out`
 * (NULL: count only). Returns their number. O(cells). */
size_t merp_solid_candidates(const merp_solid *s, uint32_t *out);
/* The point at fractions f (each in [0, 1)) across cell `cell`. */
void merp_solid_cell_point(const merp_solid *s, uint32_t cell, const float f[3], float out[3]);

#endif
