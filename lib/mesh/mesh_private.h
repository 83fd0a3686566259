/* meristem — what the geometry files of lib/mesh/ share: the builder that
 * mer_mesh_build fills, the axes it finds, and the cursors that write a part's
 * vertices, triangles and twig lines. See meristem/mesh.h for the choices.
 * Not installed. */
#ifndef MERISTEM_MESH_PRIVATE_H
#define MERISTEM_MESH_PRIVATE_H

#include <assert.h>
#include <stdbool.h>
#include <stdint.h>
#include <string.h>

#include <meristem/mesh.h>
#include <meristem/scene.h>

#include "core/vec.h"
#include "mesh/implicit/implicit.h"

#define MERP_MAX_SIDES 16 /* the sides of the thickest axis at MER_MESH_DETAIL_MAX */

enum merp_axis_end { MERP_END_TIP, MERP_END_CUT };

#define MERP_MESH_THREADS_MAX 64 /* mer_mesh_options.threads at most */

/* One generalized cylinder: an axis followed along its main continuations. */
typedef struct merp_axis {
    uint32_t first;   /* id of its first internode */
    uint32_t count;   /* internodes along it, >= 1 */
    uint32_t sides;   /* 3 .. MERP_MAX_SIDES */
    uint8_t end;      /* enum merp_axis_end */
    uint8_t base_cap; /* 1 for a plant's trunk and, with implicit junctions,
                         any axis that starts in no patch (a trunk whose base
                         a patch holds has none: merp_joint.base) */
    /* With implicit junctions: rings added (two cut rings) less rings dropped
     * (inside a patch, or folding against a cut: tube.c), and the quads
     * between rings dropped, on this axis;
     * ends_in when it ends inside a patch (a relayed fork's parent, whose
     * tip the patch covers): no cone or disk then. */
    int32_t extra_rings;
    int32_t lost_bands;
    uint8_t ends_in;
} merp_axis;

/* The cuts of an implicit junction (mesh.h, Junctions): the parent's shaft
 * below J, its continuation above (or, at a relayed fork, the lateral that
 * relays the axis), and each lateral in the patch (at a relayed fork, the
 * continuation, where it has one, among them). A run's in cut lies below
 * its first fork, its out cut above its last, and its laterals follow fork
 * by fork; the axis between its forks has no cut. */
enum { MERP_CUT_IN, MERP_CUT_OUT, MERP_CUT_LATERAL };

/* One fork meshed as an implicit patch (joints.c). */
typedef struct merp_joint {
    uint32_t start[MERP_PATCH_CUTS]; /* each shaft's internode at J: P, C (or
                                       the relay), L_k */
    uint32_t node[MERP_PATCH_CUTS]; /* the internode each cut lies in: P or an
                                       internode below it on its axis, C or one
                                       above it, L_k or one along its axis */
    uint32_t cuts;                  /* 2 + laterals in the patch */
    float d[MERP_PATCH_CUTS];       /* each cut's distance from J (straight) */
    float at[MERP_PATCH_CUTS];      /* ... and from its internode's base */
    float o[MERP_PATCH_CUTS][3], n[MERP_PATCH_CUTS][3]; /* its centre and plane
                                       normal, pointing away from J */
    float ring[MERP_PATCH_CUTS][3 * MERP_MAX_SIDES]; /* the tube's ring at each cut */
    float frame[MERP_PATCH_CUTS][2][3]; /* that ring's frame normal and binormal */
    float v[MERP_PATCH_CUTS];       /* that ring's UV v */
    float ring_normal[MERP_PATCH_CUTS][3 * MERP_MAX_SIDES]; /* the one normal the
                                       tube and the patch give each ring vertex */
    uint32_t sides[MERP_PATCH_CUTS];
    float cell;                     /* its grid spacing where a thin cut ring
                                       needs one finer than merp_joint_cell's
                                       rule (joints_plan.c); 0: none */
    bool relay;                     /* a single fork whose P has no living
                                       continuation, or a thinner one among
                                       the laterals: cut 1's shaft is a
                                       lateral axis going on from P
                                       (joints_plan.c; a run's relayed forks
                                       have no living continuation) */
    bool cap;                       /* its out and lateral shafts may end
                                       inside it (joints_plan.c: a single
                                       fork's and a run's) */
    bool base;                      /* its in shaft ends on the plant's base:
                                       its in cut would fall below the root
                                       internode's base or within BASE_GAP of
                                       it, and is the base's plane, whose flat
                                       cap the patch keeps (the trunk's base
                                       disk; no ring, sides 0; o, n and d the
                                       base's) */
    uint8_t capped[MERP_PATCH_CUTS]; /* shaft s ends inside the patch: its
                                       axis ends within the patch's reach of
                                       J, its field segment's round end closes
                                       it, and it has no cut ring (sides 0);
                                       o, n and d are its end's */
    bool ok;                        /* planned, and its patch built */
    bool smooth;                    /* ... by marching tetrahedra (no sharp crease) */
    merp_junction field[MERP_RUN_FORKS]; /* its forks' fields: field[0] a
                                       single fork's, a run's first */
    uint32_t forks;                 /* 1, or a run's forks (joints_plan.c) */
    uint64_t elbows;                /* bit i: fork i is a bend of a shaft's
                                       axis with no lateral (joints_plan.c,
                                       elbow): no fork, not counted as one */
    uint32_t fork_node[MERP_RUN_FORKS]; /* the internode each fork's J ends */
    merp_link link[MERP_RUN_FORKS]; /* how a run's forks go on from each
                                       other (merp_jprep_init_run) */
    uint32_t link_start[MERP_RUN_FORKS]; /* the first internode of the axis
                                       from fork link[i].from to fork i */
    uint8_t cut_fork[MERP_PATCH_CUTS], cut_slot[MERP_PATCH_CUTS]; /* each
                                       shaft's fork and which of its
                                       segments it is: MERP_SLOT_IN,
                                       MERP_LINK_OUT or a lateral */
    merp_trimesh mesh;              /* the patch, ring copies last */
    float *uvs, *ridge;             /* 2 and 1 per patch vertex */
    uint8_t *shaft;                 /* the cut whose shaft is nearest each vertex */
} merp_joint;

/* Where the next vertex and index of a part go, and the chunk being filled. */
typedef struct merp_cursor {
    mer_mesh_part *part;
    uint32_t v, i;
    uint32_t chunk_cap;
    uint32_t twig;     /* the `twig` flag of the chunks being made */
    uint32_t line_i;   /* next twig line index (bark only) */
    uint32_t merged_v, merged_i; /* not written: rings that repeat the last and their bands (tube.c) */
} merp_cursor;

typedef struct merp_builder {
    const mer_scene *scene;
    mer_node *nodes;        /* by id */
    uint32_t node_count;
    mer_mesh_options opt;   /* resolved: no zero left to mean a default */
    uint32_t step;
    uint32_t newest;        /* latest step in which a living internode was made */
    float max_diameter;
    float max_q;
    float twig_limit;       /* with twig_lines: the largest base diameter of a twig */
    merp_axis *axes;
    uint32_t axis_count;
    mer_mesh *mesh;
    uint32_t *chain;        /* scratch: one axis's node ids */
    float *radii;           /* scratch: its ring radii */
    uint32_t chain_cap;
    merp_cursor bark, leaves; /* write positions */
    /* Implicit junctions (joints.c); all NULL/0 without them. */
    merp_joint *joints;
    uint32_t joint_count;
    uint32_t joints_open;   /* chosen, but no patch closed: left as tubes */
    uint32_t joints_unfit;  /* candidates no patch was planned for: tubes */
    uint32_t *joint_at;     /* by node id: the joint at its tip, or UINT32_MAX */
    uint32_t *lateral_in;   /* by node id: joint · MERP_PATCH_CUTS + cut of a lateral
                               (or a relay: cut 1, or a run's relayed fork's)
                               whose shaft starts in a patch, or of a root
                               internode whose base a patch holds (cut 0,
                               merp_joint.base), or UINT32_MAX */
    uint32_t *cut_end;      /* by node id: joint · MERP_PATCH_CUTS + cut of the out
                               or lateral cut in it (a patch ends), or UINT32_MAX */
    uint32_t *cut_begin;    /* by node id: the joint whose in cut lies in it (a
                               patch begins), or UINT32_MAX */
    bool dry;               /* tube.c only records the cut rings, writes nothing */
} merp_builder;

static inline float merp_clampf(float x, float lo, float hi)
{
    return x < lo ? lo : x > hi ? hi : x;
}

/* The end point of internode `n`. */
static inline void merp_tip_of(const mer_node *n, float out[3])
{
    for (int k = 0; k < 3; k++)
        out[k] = n->base[k] + n->dir[k] * n->length;
}

/* ---------------------------------------------------------------- axes.c */

/* Finds every axis into b->axes (ascending ids of their first internode). */
mer_result merp_mesh_collect_axes(merp_builder *b, mer_error *err);
/* Fills b->chain with a's node ids and b->radii with its count + 1 ring radii. */
mer_result merp_mesh_chain(merp_builder *b, const merp_axis *a, mer_error *err);

/* A twig (mesh.h, Twig lines): a 3-sided axis no thicker than twig_limit. */
static inline bool merp_mesh_is_twig(const merp_builder *b, const merp_axis *a)
{
    return b->opt.twig_lines && a->sides == 3 && b->nodes[a->first].diameter <= b->twig_limit;
}

/* Exactly the vertices tube.c writes for `a`: its rings (with the seam vertex
 * when `seam`), then the apex of a tip or the disk of a cut (neither where it
 * ends inside a patch), and a trunk's base disk. */
static inline uint64_t merp_axis_vertices(const merp_axis *a, bool seam)
{
    const uint64_t ring = seam ? a->sides + 1 : a->sides, cap = a->sides + 1;  // cap: centre + rim
    const uint64_t end = a->ends_in ? 0 : a->end == MERP_END_TIP ? 1 : cap;
    const uint64_t v = a->end == MERP_END_TIP ? a->count * ring + end : (a->count + 1) * ring + end;
    return (uint64_t)((int64_t)(a->base_cap ? v + cap : v) + (int64_t)a->extra_rings * (int64_t)ring);
}

/* Exactly the indices tube.c writes for `a`: two triangles per side between
 * rings, one per side in the cone or disk at the end (unless it ends inside a
 * patch) and in a base disk. */
static inline uint64_t merp_axis_indices(const merp_axis *a)
{
    int64_t quads = (int64_t)(a->end == MERP_END_TIP ? a->count - 1 : a->count) - a->lost_bands;
    uint64_t i = (uint64_t)quads * a->sides * 6 + (a->ends_in ? 0 : (uint64_t)a->sides * 3);
    return a->base_cap ? i + (uint64_t)a->sides * 3 : i;
}

/* ---------------------------------------------------------------- tube.c */

/* Meshes every axis into the bark part, allocated to merp_axis_vertices and
 * merp_axis_indices (see build.c): with twig lines the thicker axes first. */
mer_result merp_mesh_bark(merp_builder *b, mer_error *err);

/* Walks axis a's rings as merp_mesh_bark does, writing nothing: sets a's
 * extra_rings, lost_bands and ends_in and, with `record`, records each cut ring's
 * positions, frame and UV v in its joint (for joints.c). */
mer_result merp_mesh_record_rings(merp_builder *b, merp_axis *a, bool record, mer_error *err);

/* -------------------------------------------------------------- joints.c */

/* The joint (a patched fork) at node id's tip, or NULL. */
static inline const merp_joint *merp_joint_at(const merp_builder *b, uint32_t id)
{
    if (b->joint_at == NULL || b->joint_at[id] == UINT32_MAX)
        return NULL;
    return &b->joints[b->joint_at[id]];
}

_Static_assert(MERP_RUN_FORKS <= 64, "merp_joint.elbows holds a bit per fork of a run");

/* Whether jt's fork at node id's tip is one of its elbows (no fork). */
static inline bool merp_joint_elbow(const merp_joint *jt, uint32_t id)
{
    for (uint32_t i = 0; i < jt->forks; i++)
        if (jt->fork_node[i] == id)
            return jt->elbows >> i & 1u;
    return false;
}

/* How many forks jt patches: its forks but its elbows. */
static inline uint32_t merp_joint_forks(const merp_joint *jt)
{
    uint32_t n = jt->forks;
    for (uint32_t i = 0; i < jt->forks; i++)
        n -= jt->elbows >> i & 1u;
    return n;
}

#define MERP_SLOT_IN 0xfe /* merp_joint.cut_slot: the first fork's in */

/* Shaft s of jt: its fork's field, and its segment there (*lane: the
 * segment's lane in jp's rows, when jp is not NULL). */
static inline const merp_seg *merp_joint_shaft(const merp_joint *jt, uint32_t s, const merp_jprep *jp,
                                               uint32_t *lane)
{
    assert(s < jt->cuts);
    uint32_t i = jt->cut_fork[s], k = jt->cut_slot[s];
    const merp_junction *f = &jt->field[i];
    if (jp != NULL)
        *lane = k == MERP_SLOT_IN ? jp->lanes.in_lane[i] : k == MERP_LINK_OUT ? jp->lanes.out_lane[i] : jp->lanes.lat_lane[i][k];
    return k == MERP_SLOT_IN ? &f->in : k == MERP_LINK_OUT ? &f->out : &f->lateral[k];
}

/* Whether shaft s of jt begins an axis in the patch (tube.c then starts
 * that axis at its cut ring): a lateral, or a relay; not the parent's own
 * axis going on (its continuation, also where a relay swapped it among the
 * laterals). */
static inline bool merp_joint_begins_axis(const mer_node *nodes, const merp_joint *jt, uint32_t s)
{
    uint32_t id = jt->start[s];
    return s != MERP_CUT_IN && nodes[nodes[id].parent].main_child != id;
}

#define MERP_JOINT_REACH 1.15f /* a cut acts within this × its shaft's radius (+ h) */

static inline float merp_node_radius(const merp_builder *b, uint32_t id)
{
    return 0.5f * b->nodes[id].diameter;
}

/* The radius at the end of internode id, as tube.c's next ring has it. */
static inline float merp_node_end_radius(const merp_builder *b, uint32_t id)
{
    uint32_t c = b->nodes[id].main_child;
    return c != MER_NO_NODE && b->nodes[c].alive ? merp_node_radius(b, c) : merp_node_radius(b, id);
}

/* The radius of the tube at jt's cut s: its internode's, linear from base to
 * end, as tube.c's cut ring and the shaft's field segment have it. A cut
 * across several internodes can lie where the axis is thicker than at J
 * (the parent below a dense whorl), so a cut's reach, shell and fade are
 * sized by this, not by the shaft's radius at J. */
static inline float merp_cut_radius(const merp_builder *b, const merp_joint *jt, uint32_t s)
{
    assert(s < jt->cuts);
    const uint32_t id = jt->node[s];
    const mer_node *n = &b->nodes[id];
    const float f = n->length > 0.0f ? jt->at[s] / n->length : 0.0f, r = merp_node_radius(b, id);
    return r + f * (merp_node_end_radius(b, id) - r);
}

/* Whether jt's cut s meets a tube's ring: not where its shaft ends inside
 * the patch (capped) or on the plant's base (base). */
static inline bool merp_cut_has_ring(const merp_joint *jt, uint32_t s)
{
    assert(s < jt->cuts);
    return !jt->capped[s] && !(s == MERP_CUT_IN && jt->base);
}

/* joints_plan.c: plans the forks to patch into b->joints, their cuts and
 * fields, and the node maps tube.c follows (joint_at, lateral_in, cut_end,
 * cut_begin). Errors: MER_ERR_NOMEM. */
mer_result merp_mesh_joints_plan(merp_builder *b, mer_error *err);
/* A patch's grid spacing (joints_plan.c). */
float merp_joint_cell(const merp_builder *b, const merp_joint *jt);
#define MERP_JOINT_SHELL 1.6f /* the surface stays within this × a shaft's radius of its axis */
/* A patch's grid at most: a run of eight forks up a thick trunk, or one
 * with a thin continuation, may need several million (the walk touches
 * only the cells the surface crosses: its per-cell and per-sample arrays,
 * some 50 bytes a cell, are reserved but cleared only for a bit a sample
 * and a cell, and the mesh's arrays are capped by MERP_PATCH_ROOM_VERTICES,
 * not sized for a surface through every cell); a fork that needs more
 * stays tubes. */
#define MERP_JOINT_MAX_CELLS 8000000u
/* The grid of jt's patch into *g (joints_plan.c): the box of every shaft
 * from its J to just past its cut, and of every fork's J, grown by the
 * shell its surface stays in, with cells of h on a lattice fixed to J (a
 * run's first; J a fifth of a cell off it), moved back by shift × h
 * (0 ≤ shift < 1) on every axis. False when it would have more than
 * MERP_JOINT_MAX_CELLS cells. */
bool merp_joint_grid(const merp_builder *b, const merp_joint *jt, float h, float shift, merp_grid *g);
/* Grades g, merp_joint_grid's grid of jt with cells of merp_joint_cell's
 * h (joints_plan.c), along its longest axis (a run's, up its trunk): each
 * level's cells as wide as the shafts whose boxes (merp_joint_grid's) span
 * it need — a third of an axis's radius, a lateral's radius over 1.25, the
 * finest of them where boxes overlap — up to MERP_GRADE_WIDEST × h, scaled
 * about the first fork's J (merp_grid_warp, merp_grade_levels). A run's
 * cells are its thinnest shaft's all over a regular grid; graded, only
 * at the levels about it. g->warp then points into *store (the caller
 * frees it). A thin cut's shaft (one whose ring sets jt->cell) keeps
 * cells of THIN_CELLS across its ring at the levels it spans. False (g
 * unchanged, *store NULL) where no level widens, where the levels outgrow
 * their room, or out of memory. */
#define MERP_GRADE_WIDEST 4.0f
bool merp_joint_grade(const merp_builder *b, const merp_joint *jt, merp_grid *g, void **store);
/* How far along n (unit) from J a cut of reach ρ must lie to be clear of a
 * primitive leaving J along m (unit) with support R (joints_plan.c): the
 * cut's disk at d, square to n (as a single fork's cuts are laid), comes
 * nearest that primitive's axis at its rim on m's side, d·sin φ − ρ·cos φ
 * from it (φ between n and m), so d = (R + ρ·cos φ) / sin φ; R when m
 * points back (cos φ ≤ 0: the disk is at least d from the ray); -1 when
 * they are too close to parallel (sin φ < 0.2). */
float merp_cut_clearance(const float n[3], const float m[3], float R, float rho);
/* An id and the key it is ranked by; merp_ranked_cmp orders them for qsort,
 * largest key first, ties by id (joints_plan.c: the forks planned thickest
 * lateral first; joints.c: the patches built costliest first). */
typedef struct merp_ranked {
    float key;
    uint32_t id;
} merp_ranked;
int merp_ranked_cmp(const void *x, const void *y);
/* jt's maps forgotten (joints_plan.c): its forks are tubes again, unless
 * another patch serves them (a run that took them in). */
void merp_joint_forget(merp_builder *b, merp_joint *jt);

/* With implicit junctions: plans the forks to patch (cut distances that fit
 * their internodes), records their rings (a dry run of tube.c), builds each
 * patch (a fork whose patch fails stays tubes), and sets every axis's
 * ring counts and lateral base caps. Errors: MER_ERR_NOMEM. */
mer_result merp_mesh_joints(merp_builder *b, mer_error *err);
/* The patch vertices and indices to add to the bark. */
void merp_mesh_joints_size(const merp_builder *b, uint64_t *vertices, uint64_t *indices);
/* Writes every patch into the bark (a group each, after the thicker axes). */
mer_result merp_mesh_joints_write(merp_builder *b, mer_error *err);
void merp_mesh_joints_free(merp_builder *b);

/* --------------------------------------------------------- joints_close.c */

/* Whether patch m (ring copies from ring_first on) can close the bark: no two
 * vertices at one position, no directed edge twice, and open only along its
 * rings. A patch that fails leaves its fork as tubes, so the bark stays a
 * 2-manifold whatever the polygonizer met there. False also when out of
 * memory. Cost O(vertices + triangles). */
bool merp_patch_closes(const merp_trimesh *m, uint32_t ring_first);

/* -------------------------------------------------------------- leaves.c */

/* Exactly the leaf cards merp_mesh_leaves writes (4 vertices, 6 indices each). */
uint64_t merp_mesh_leaf_count(const merp_builder *b);
mer_result merp_mesh_leaves(merp_builder *b, mer_error *err);

/* --------------------------------------------------------------- color.c */

/* With a colour mode: the COLOR_0 of the `count` vertices from `first` of
 * `part`, all of node `n`. Without one (part->colors NULL), nothing. Kept out of
 * merp_put_vertex so that the vertex loops make no call. */
void merp_mesh_color_run(const merp_builder *b, mer_mesh_part *part, uint32_t first,
                         uint32_t count, const mer_node *n);
static inline void merp_mesh_color(const merp_builder *b, mer_mesh_part *part, uint32_t first,
                                   uint32_t count, const mer_node *n)
{
    if (part->colors != NULL)
        merp_mesh_color_run(b, part, first, count, n);
}

/* --------------------------------------------------------------- build.c */

/* Makes room for a group of `vertices` that triangles will join: when the
 * current chunk cannot take them all under MER_MESH_CHUNK_VERTICES, or has
 * another `twig` flag than the cursor's, a new chunk starts here. */
mer_result merp_mesh_begin_group(merp_cursor *c, uint32_t vertices, mer_error *err);

/* The writers: vertices (their colours come from merp_mesh_color), a
 * triangle, a twig line segment, into the current chunk. The part was sized
 * beforehand (build.c, mesh_bound). */

/* Takes the next `n` vertices into the current chunk and returns the first,
 * for a loop that then writes them with merp_set_vertex. */
static inline uint32_t merp_take_vertices(merp_cursor *c, uint32_t n)
{
    uint32_t k = c->v;
    c->v += n;
    c->part->chunks[c->part->chunk_count - 1].vertex_count += n;
    return k;
}

/* Vertex k's position, normal, UV (when the part has UVs) and node id. */
static inline void merp_set_vertex(mer_mesh_part *part, uint32_t k, const float p[3],
                                   const float nrm[3], float u, float v, uint32_t node_id)
{
    memcpy(part->positions + 3 * k, p, 3 * sizeof(float));
    memcpy(part->normals + 3 * k, nrm, 3 * sizeof(float));
    if (part->uvs != NULL) {
        part->uvs[2 * k] = u;
        part->uvs[2 * k + 1] = v;
    }
    part->node_ids[k] = node_id;
}

static inline uint32_t merp_put_vertex(merp_cursor *c, const float p[3], const float nrm[3], float u,
                                       float v, const mer_node *node)
{
    uint32_t k = merp_take_vertices(c, 1);
    merp_set_vertex(c->part, k, p, nrm, u, v, node->id);
    return k;
}

/* Takes the next `n` indices into the current chunk and returns where they
 * go, for a loop that writes them relative to the chunk's first vertex
 * (*base): the counts bumped once for a run of triangles, not per triangle
 * (an index store may alias the chunk's count, so each would reload it). */
static inline uint32_t *merp_take_indices(merp_cursor *c, uint32_t n, uint32_t *base)
{
    mer_mesh_chunk *chunk = &c->part->chunks[c->part->chunk_count - 1];
    uint32_t *t = c->part->indices + c->i;
    *base = chunk->first_vertex;
    c->i += n;
    chunk->index_count += n;
    return t;
}

/* A triangle of absolute vertex numbers, stored relative to its chunk. */
static inline void merp_put_triangle(merp_cursor *c, uint32_t a, uint32_t a1, uint32_t a2)
{
    uint32_t base, *t = merp_take_indices(c, 3, &base);
    t[0] = a - base;
    t[1] = a1 - base;
    t[2] = a2 - base;
}

/* A twig line segment of absolute vertex numbers, stored relative to its chunk. */
static inline void merp_put_line(merp_cursor *c, uint32_t a, uint32_t a1)
{
    mer_mesh_part *part = c->part;
    mer_mesh_chunk *chunk = &part->chunks[part->chunk_count - 1];
    part->line_indices[c->line_i++] = a - chunk->first_vertex;
    part->line_indices[c->line_i++] = a1 - chunk->first_vertex;
    chunk->line_index_count += 2;
}

#endif
