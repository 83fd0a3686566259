/* meristem — interactive edits between steps (P09 §5): prune, bend, brush,
 * growth constraint.
 *
 * Choices where the paper is open (each is tested):
 *  - Pruning a node removes it and everything it supports; the bud that made it is
 *    gone too (a cut does not regrow), so growth passes to the buds below. Node
 *    ids of the removed nodes are never reused. Diameters below keep their size
 *    (pipe-model memory, P09 §4.5).
 *  - Bending rotates a node's subtree rigidly about the node's base point (or, with
 *    a spread, curves the first internodes of its axis); it is not blocked by
 *    obstacles (the user moves the branch).
 *  - A brush dab at pressure p in (0, 1] scatters round(1 + (max_count − 1)·p²)
 *    markers uniformly in a ball of radius radius·(0.1 + 0.9·p): light pressure
 *    gives a few markers on a tight line (a limb sketch), heavy pressure a wide
 *    cloud (a crown). The dab's points are drawn once, then copied by the symmetry:
 *    rotational n-fold about the vertical axis through `center`, then mirrored in
 *    the plane (if any), then translated over the tiling lattice.
 *  - The constraint names a bud (node, slot: 0 terminal, 1 or 2 lateral); while
 *    set, only that bud and the buds on the shoots it has made may grow, and only
 *    they compete for markers; all other buds stay dormant (they still clear
 *    markers in their occupancy zone and cast shadow).
 */
#ifndef MERISTEM_EDIT_H
#define MERISTEM_EDIT_H

#include <stddef.h>
#include <stdint.h>

#include <meristem/result.h>
#include <meristem/scene.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Prunes node `node` and its subtree. Field "node": MER_ERR_NOT_FOUND if the id
 * was never issued, MER_ERR_GONE if the node was pruned or shed, MER_ERR_ROOT
 * if it is a plant's first internode (nothing could grow again).
 * O(subtree + buds·q_max²). */
mer_result mer_scene_prune(mer_scene *s, uint32_t node, mer_error *err);

/* Rotates the subtree of `node` about its base by `angle` degrees about `axis`
 * (need not be unit; must not be zero): an elbow at the node's base. Errors as
 * prune, MER_ERR_RANGE for a zero axis. O(subtree + buds·q_max²). Same as
 * mer_scene_bend_spread with spread 1. */
mer_result mer_scene_bend(mer_scene *s, uint32_t node, const float axis[3], float angle,
                          mer_error *err);

#define MER_BEND_SPREAD_MAX 64u

/* Bends the axis from `node` up as a curve rather than an elbow: the first
 * `spread` internodes of the axis (node, its terminal child, ...; fewer where
 * the axis ends sooner, say n) each turn their own subtree about their own base
 * by angle / n, lowest first, so the axis's tip turns by `angle` in all and the
 * lateral branches on the way ride along. spread 1 is mer_scene_bend. Errors as
 * mer_scene_bend, MER_ERR_RANGE ("spread") outside 1..MER_BEND_SPREAD_MAX.
 * O(n · (subtree + buds·q_max²)). */
mer_result mer_scene_bend_spread(mer_scene *s, uint32_t node, const float axis[3], float angle,
                                 uint32_t spread, mer_error *err);

typedef struct mer_brush {
    float center[3];
    float radius;      /* ball radius at full pressure; (0, 1000] */
    float pressure;    /* (0, 1] */
    uint32_t max_count; /* markers at full pressure; 1..100000; 0 means 50 */
} mer_brush;

typedef struct mer_symmetry {
    uint32_t rotational;      /* n-fold copies about the vertical axis through center; 0 or 1: none; <= 64 */
    float center[3];          /* a point of that axis (the trunk) */
    uint32_t mirror;          /* 1: also mirror every copy in the plane below */
    float mirror_point[3];
    float mirror_normal[3];   /* need not be unit; not zero when mirror is 1 */
    uint32_t tiles[2];        /* copies along each lattice vector; 0 or 1: none; product <= 1024 */
    float tile_step[2][3];    /* lattice vectors */
} mer_symmetry;

#define MER_BRUSH_MARKERS_MAX 1000000u /* markers one dab may make, copies included */

/* One brush dab: adds markers (see above) to the scene, with symmetric copies when
 * `sym` is not NULL. Draws from the scene's generator. `*added` (may be NULL) gets
 * the number of markers kept (those inside obstacles or below ground are dropped).
 * MER_ERR_RANGE names the bad field; MER_ERR_LIMIT past MER_BRUSH_MARKERS_MAX.
 * O(count · copies). */
mer_result mer_scene_brush(mer_scene *s, const mer_brush *brush, const mer_symmetry *sym,
                           size_t *added, mer_error *err);

/* Constrains growth to bud `slot` (0 terminal, 1..buds_per_node lateral) of `node`
 * and its descendants, until mer_scene_unconstrain. The bud must be dormant or
 * already grown out (state NONE with a child). MER_ERR_RANGE otherwise. O(1). */
mer_result mer_scene_constrain(mer_scene *s, uint32_t node, uint32_t slot, mer_error *err);

/* Lifts the constraint (no-op when none). O(1). */
void mer_scene_unconstrain(mer_scene *s);

/* The growth constraint: returns 1 and fills `*node` and `*slot` (either may be
 * NULL) when growth is constrained to a bud, else 0 and leaves them. Pruning the
 * constrained node (or an ancestor) lifts the constraint. O(1). */
int mer_scene_constraint(const mer_scene *s, uint32_t *node, uint32_t *slot);

#ifdef __cplusplus
}
#endif

#endif
