/* meristem — implicit surfaces for branch junctions (G04 §3): skeletal
 * primitives, summation blending, precise contact modeling (PCM), generalized
 * bounded blending (GBB, eq. 4) and a polygonizer. Not installed.
 *
 * Conventions. A field f(p) is in [0, 1], largest on its skeleton, decreasing
 * outwards, and 0 beyond a finite support; a solid is {p : f(p) ≥ c} with the
 * iso value c = MERP_ISO. All fields are pure functions of p (no state), so a
 * junction can be evaluated on any thread. */
#ifndef MERISTEM_MESH_IMPLICIT_H
#define MERISTEM_MESH_IMPLICIT_H

#include <assert.h>
#include <stdbool.h>
#include <stdint.h>
#include <string.h>

#include <meristem/result.h>

#define MERP_ISO 0.5f /* c: the iso value of every field here */

/* ------------------------------------------------------------ segment.c */

/* A skeletal primitive for an internode: the line segment a→b with the pipe
 * radius ra at a and rb at b (a tapered capsule). Its field is Wyvill's soft
 * kernel g(x) = (1 − x²)³ (0 for x ≥ 1) of x = d / R(t), where d is the distance
 * from p to the segment, t ∈ [0, 1] the parameter of p's closest point and
 * R(t) = r(t) / x_c with r(t) = (1 − t)·ra + t·rb and g(x_c) = c. So the iso
 * surface f = c lies at distance r(t) from the segment: it matches the pipe
 * radius along the internode, and the support is R(t) ≈ 2.2·r(t). A segment of
 * length 0 is a ball. */
typedef struct merp_seg {
    float a[3], b[3];
    float ra, rb;
} merp_seg;

/* x_c: the x at which g(x) = MERP_ISO, i.e. sqrt(1 − c^(1/3)). */
float merp_seg_xc(void);

/* The distance from p to segment s; *t gets the parameter of the closest point
 * (may be NULL). Cost O(1). */
float merp_seg_distance(const merp_seg *s, const float p[3], float *t);

/* Its square, without the square root (what the fields compare). */
float merp_seg_distance2(const merp_seg *s, const float p[3], float *t);

/* x_c for c = 1/2: g(x_c) = (1 − x_c²)³ = c (test_implicit checks the iso). */
#define MERP_SEG_XC 0.45420201894740647f

/* The squared distance from p to s and the parameter of the closest point
 * into *t. Inline, as every field evaluation of a patch takes a few. */
static inline float merp_seg_d2(const merp_seg *s, const float p[3], float *t)
{
    float ab[3], ap[3];
    for (int k = 0; k < 3; k++)
        ab[k] = s->b[k] - s->a[k], ap[k] = p[k] - s->a[k];
    float len2 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2], u = 0.0f;
    if (len2 > 0.0f) {
        u = (ap[0] * ab[0] + ap[1] * ab[1] + ap[2] * ab[2]) / len2;
        u = u < 0.0f ? 0.0f : u > 1.0f ? 1.0f : u;
    }
    float q[3];
    for (int k = 0; k < 3; k++)
        q[k] = ap[k] - u * ab[k];
    *t = u;
    return q[0] * q[0] + q[1] * q[1] + q[2] * q[2];
}

/* f(p) of the tapered capsule s (see above), in [0, 1]. Requires ra, rb > 0. */
static inline float merp_seg_field(const merp_seg *s, const float p[3])
{
    assert(s->ra > 0.0f && s->rb > 0.0f);
    float t;
    float d2 = merp_seg_d2(s, p, &t);
    float R = ((1.0f - t) * s->ra + t * s->rb) / MERP_SEG_XC;
    float x2 = d2 / (R * R);
    if (x2 >= 1.0f)
        return 0.0f;
    float u = 1.0f - x2;
    return u * u * u;
}

/* The largest distance from the segment at which s's field is not 0. */
float merp_seg_support(const merp_seg *s);

/* ---------------------------------------------------------------- row.c */

#define MERP_ROW 4 /* lanes of a row: SSE2's four floats */

/* Up to MERP_ROW segments as a structure of arrays, lane by lane, with what
 * every sample of them needs precomputed once (b − a, |b − a|², ∇t): a point's
 * fields of all of them are then one pass of 4-wide loops, which GCC
 * vectorizes, where four scalar evaluations each recomputed the constants.
 * A lane's arithmetic is merp_seg_d2's, merp_seg_field's and
 * merp_bound_field's in their order, so it gives their values to the bit.
 * ra, rb are a segment's radii at a, b, or a bound's r_in, r_out. */
typedef struct merp_row {
    float a[3][MERP_ROW], ab[3][MERP_ROW];
    float len2[MERP_ROW], den[MERP_ROW]; /* |b − a|², and it or 1 where 0 */
    float dt[3][MERP_ROW];               /* ∇t = (b − a) / den where t is not clamped */
    float ra[MERP_ROW], rb[MERP_ROW], rb2[MERP_ROW]; /* rb2 = rb²: a bound's support */
    float span[MERP_ROW], dR[MERP_ROW];              /* rb − ra, and over x_c: a segment's R'(t) */
} merp_row;

/* A point's closest points on a row's segments: parameters t, offsets
 * q = p − s(t) and their squares d² = |q|². */
typedef struct merp_row_point {
    float t[MERP_ROW], q[3][MERP_ROW], d2[MERP_ROW];
} merp_row_point;

/* Each lane's value f and gradient g (by coordinate, then lane). */
typedef struct merp_row_grad {
    float f[MERP_ROW], g[3][MERP_ROW];
} merp_row_grad;

/* Fills every lane with a segment whose fields are 0 everywhere. */
void merp_row_clear(merp_row *r);

/* Lane l (< MERP_ROW) ← the segment a→b with ra, rb (see merp_row). */
void merp_row_set(merp_row *r, int l, const float a[3], const float b[3], float ra, float rb);

/* p's closest points on the row's segments into *c. */
void merp_row_closest(const merp_row *r, const float p[3], merp_row_point *c);

/* merp_seg_field of each lane at p (segments: ra, rb > 0). */
void merp_row_seg_field(const merp_row *r, const float p[3], float f[MERP_ROW]);

/* The same with each lane's gradient, as gradient.c's closed form: 0
 * outside the lane's support. */
void merp_row_seg_gradient(const merp_row *r, const float p[3], merp_row_grad *out);

/* merp_bound_field of each lane at p (bounds: ra = r_in < rb = r_out). */
void merp_row_bound_field(const merp_row *r, const float p[3], float F[MERP_ROW]);

/* The same with each lane's gradient (0 where F_b is 0 or 1). */
void merp_row_bound_gradient(const merp_row *r, const float p[3], merp_row_grad *out);

/* --------------------------------------------------------------- blend.c */

/* B2 of G04 §3.1: summation blending, Σ f_i (Blinn's and Wyvill's blend): two
 * solids closer than their supports melt into one smooth surface. */
float merp_blend_sum(const float *f, uint32_t n);

/* --------------------------------------------------------------- pcm.c */

/* Precise contact modeling (Gascuel 1993; Desbrun & Cani-Gascuel 1998, G04 §3),
 * the formulation we use. Two solids f1 ≥ c and f2 ≥ c that interpenetrate are
 * each deformed by the other:
 *     f1'(p) = f1(p) + Δ(c − f2(p)),   f2'(p) = f2(p) + Δ(c − f1(p)),
 *     Δ(x) = x                 for x < 0   (inside the other: compression),
 *     Δ(x) = x·(1 − x / w)²    for 0 ≤ x ≤ w (the bulge of the propagation zone),
 *     Δ(x) = 0                 for x > w.
 * Inside the other solid f1' = c ⟺ f1 = f2: both deformed surfaces meet on
 * the contact surface {f1 = f2} exactly, with no gap and no overlap. Δ is C¹
 * (Δ(0) = 0, Δ'(0⁻) = Δ'(0⁺) = 1, Δ(w) = Δ'(w) = 0), so each deformed surface
 * is C¹ where compression turns to bulge. The bulge's height, 4w/27 in field
 * units at x = w/3, follows from C¹ continuity; w (in field units, 0 < w ≤ c)
 * sets its width: the bulge spans c − w ≤ f2 < c. The contact pair as one solid is B1 = max(f1', f2'), whose
 * surface has a crease where the two deformed surfaces meet: the branch bark
 * ridge (G04 Figs. 4, 5). */
static inline float merp_pcm_delta(float x, float w) /* inline: a few per field sample */
{
    assert(w > 0.0f && w <= MERP_ISO);
    if (x < 0.0f)
        return x; /* interpenetration: compressed onto the contact surface */
    if (x > w)
        return 0.0f;
    float u = 1.0f - x / w;
    return x * u * u; /* propagation: the C¹ bulge */
}

/* f1' and f2' of the pair (f1, f2) with bulge width w (see above). */
void merp_pcm_pair(float f1, float f2, float w, float *f1d, float *f2d);

/* B1: the union max(f1', f2') of the pair deformed by PCM. */
float merp_pcm_union(float f1, float f2, float w);

/* ------------------------------------------------------------- bounded.c */

/* The bounding field's skeleton: a segment a→b, with F_b = 1 within distance
 * r_in of it and F_b = 0 beyond r_out (0 ≤ r_in < r_out). */
typedef struct merp_bound {
    float a[3], b[3];
    float r_in, r_out;
} merp_bound;

/* F_b(p) = ((1 − r)²)³ (G04 §3.1) with r = s², s = (d − r_in)/(r_out − r_in)
 * clamped to [0, 1] and d the distance from p to the bound's segment. r is
 * the SQUARED normalized distance, as Wyvill's kernels take r²: then F_b ∈
 * [0, 1] and ∇F_b = 0 where F_b = 1 (s = 0) and where F_b = 0 (s = 1), the two
 * criteria of §3.1 (with r the plain distance, ∇F_b would be 6/(r_out − r_in)
 * at F_b = 1). Cost O(1). */
float merp_bound_field(const merp_bound *bnd, const float p[3]);

/* Generalized bounded blending, G04 eq. (4): F_g = F_b·b1 + (1 − F_b)·b2, where
 * b1 = B1(f1..fn) (eq. 2) and b2 = B2(f1..fn) (eq. 3). */
static inline float merp_gbb(float F_b, float b1, float b2)
{
    return F_b * b1 + (1.0f - F_b) * b2;
}

/* --------------------------------------------------------------- mtet.c */

/* A field to polygonize: f(p) with user data; the solid is f ≥ MERP_ISO. */
typedef float (*merp_field_fn)(const float p[3], const void *data);

/* Its gradient: ∇f(p) into g (one side's where f is not differentiable);
 * returns f(p). */
typedef float (*merp_gradient_fn)(const float p[3], const void *data, float g[3]);

/* A graded grid's levels (merp_grid): the samples of level l (index l along
 * `axis`) lie at level[l] along it, and across it on the regular lattice
 * scaled about `center` by ratio[l] ≥ 1 (exactly 1: the lattice's own
 * floats), so the cells of level l are about ratio[l] × h across. The
 * cells between two levels of different ratios lean (their sides are not
 * square to the levels); `reach` bounds how far any corner of a cell lies
 * from its lowest, along each axis. */
typedef struct merp_grid_warp {
    int axis;
    const float *level, *ratio; /* n[axis] + 1 each */
    float center[3];
    float reach[3];
} merp_grid_warp;

/* A grid of (n[0]+1)·(n[1]+1)·(n[2]+1) samples: regular, from `origin` with
 * spacing h; or graded along one axis (warp), where a patch needs fine
 * cells only in part of it (a run's thin fork), h then the finest cell's. */
typedef struct merp_grid {
    float origin[3];
    float h;
    uint32_t n[3];               /* cells along x, y, z, each ≥ 1 */
    const merp_grid_warp *warp; /* NULL: regular */
} merp_grid;

/* Sample (i, j, k)'s position: on a regular grid origin + (i, j, k)·h, the
 * same floats wherever a graded grid's ratio is 1. */
static inline void merp_grid_point(const merp_grid *g, uint32_t i, uint32_t j, uint32_t k, float p[3])
{
    const uint32_t idx[3] = {i, j, k};
    for (int a = 0; a < 3; a++)
        p[a] = g->origin[a] + (float)idx[a] * g->h;
    const merp_grid_warp *w = g->warp;
    if (w == NULL)
        return;
    uint32_t l = idx[w->axis];
    float r = w->ratio[l];
    p[w->axis] = w->level[l];
    if (r != 1.0f)
        for (int a = 0; a < 3; a++)
            if (a != w->axis)
                p[a] = w->center[a] + (p[a] - w->center[a]) * r;
}

/* The cell that holds p, clamped into the grid. */
void merp_grid_locate(const merp_grid *g, const float p[3], uint32_t cell[3]);

/* Moves v into cell `cell` (its box on a regular grid; on a graded one,
 * between its levels and within its sides at v's height). */
void merp_grid_clamp(const merp_grid *g, const uint32_t cell[3], float v[3]);

/* How far along axis a any corner of a cell may lie from its lowest (h on
 * a regular grid, where none lies below it). */
static inline float merp_grid_reach(const merp_grid *g, int a)
{
    return g->warp != NULL ? g->warp->reach[a] : g->h;
}

/* Grades one axis of a regular lattice of n cells of h into levels:
 * fine[i] is the ratio (≥ 1) lattice cell i allows (overwritten: limited
 * to change gently along the axis). From lattice plane `anchor` the levels
 * step down to 0 or below and up to n or above, each step as wide as the
 * ratios where it begins and ends allow. Writes the levels' positions u (in
 * cells of h from the lattice's origin; whole numbers of cells from the
 * anchor while the ratio stays exactly 1) and each level's ratio (the step
 * above it), with room for `room` levels; returns the number of cells
 * (levels − 1), 0 when they do not fit. */
uint32_t merp_grade_levels(float *fine, uint32_t n, uint32_t anchor, uint32_t room, float *u, float *ratio);

/* A triangle mesh the polygonizer writes: positions and unit normals (3 floats
 * a vertex), triangles (3 indices), counter-clockwise seen from outside.
 * marching tetrahedra and merp_patch_build leave the normals out when
 * `normals` is NULL (a caller that shades from another field). */
typedef struct merp_trimesh {
    uint32_t vertex_count, triangle_count;
    float *positions, *normals;
    uint32_t *triangles;
    /* The arrays' room for a polygonizer: 0 where they hold its *_bound
     * (nothing to check); else it stops with MER_ERR_INVALID before its
     * counts would pass them (merp_patch_bound's caps). */
    uint32_t vertex_room, triangle_room;
} merp_trimesh;

/* Whether m's arrays have room for `vertices` and `triangles` more (always,
 * where its rooms are 0). */
static inline bool merp_trimesh_has_room(const merp_trimesh *m, uint32_t vertices, uint32_t triangles)
{
    return (m->vertex_room == 0 || m->vertex_count + vertices <= m->vertex_room) &&
           (m->triangle_room == 0 || m->triangle_count + triangles <= m->triangle_room);
}

/* The most vertices and triangles merp_mtet_polygonize can write for `g`: one
 * vertex per grid edge of the Freudenthal triangulation (7 a sample), two
 * triangles per tetrahedron (6 a cell). */
void merp_mtet_bound(const merp_grid *g, uint64_t *vertices, uint64_t *triangles);

/* Marching tetrahedra over the Freudenthal (Kuhn) triangulation of `g`: each
 * cell is 6 tetrahedra about its main diagonal, the same in every cell, so
 * neighbouring cells share faces and edges and one vertex per crossed edge
 * joins them: where the surface stays inside the grid the result is a closed
 * 2-manifold, oriented outwards (every triangle faces from the inside sample to
 * the outside one). Vertices are refined on their edge by regula falsi to
 * |f − c| small; normals are −∇f by central differences. Samples are
 * evaluated once; edges are only solved in cells whose corners differ in sign.
 * `out` must hold merp_mtet_bound's counts, or its rooms be set; its counts
 * are set. Errors: MER_ERR_NOMEM (scratch), MER_ERR_INVALID (past a room).
 * Cost O(samples) evaluations + O(crossed cells). */
mer_result merp_mtet_polygonize(const merp_grid *g, merp_field_fn f, const void *data,
                                merp_trimesh *out, mer_error *err);

/* As merp_mtet_polygonize, but only the surface reached from `seeds` (nseeds
 * ≥ 1 points, each inside the solid or on a row of cells along +x that meets
 * the surface): from the first crossed cell along +x of each seed, the walk
 * follows the surface cell to cell across the faces it crosses, so only the
 * samples of crossed cells are evaluated. The same mesh as
 * merp_mtet_polygonize's for every connected piece of surface a seed reaches
 * (vertices in another order); pieces no seed reaches are missing. Cost
 * O(crossed cells) evaluations, plus clearing O(samples) bytes. */
mer_result merp_mtet_polygonize_seeded(const merp_grid *g, merp_field_fn f, const void *data,
                                       const float (*seeds)[3], uint32_t nseeds, merp_trimesh *out,
                                       mer_error *err);

/* ----------------------------------------------------------------- dc.c */

/* The most sheets of surface dual contouring finds in one cell (a cell
 * whose eight corners alternate in sign has four). */
#define MERP_DC_SHEETS 4

/* The most vertices and triangles merp_dc_polygonize can write for `g`: a
 * vertex per sheet of each cell, two triangles per grid edge (3 a sample). */
void merp_dc_bound(const merp_grid *g, uint64_t *vertices, uint64_t *triangles);

/* Where a vertex of dual contouring comes from: its cell (i, j, k) and the
 * corners (bits x = 1, y = 2, z = 4) of the cell edges its sheet crosses. */
typedef struct merp_dc_source {
    uint32_t cell[3];
    uint8_t corners;
} merp_dc_source;

/* Dual contouring (Ju et al. 2002) of f ≥ MERP_ISO on `g`, for surfaces whose
 * creases must stay sharp (the branch bark ridge). The crossed edges of each
 * cell the surface crosses are grouped into sheets by the segments the
 * surface draws on the cell's faces (a face with four crossings decided by
 * the asymptotic decider, alike for both its cells); each sheet gets one
 * vertex, the minimum of the quadratic error function of its edge crossings
 * (refined onto the surface) and their normals −∇f, solved as a
 * least-squares problem regularised towards the crossings' mass point
 * (weight 0.02 a crossing) and clamped into the cell. Each grid edge the
 * surface crosses joins the vertices of its sheets in its four cells in a
 * quad, wound outwards (from the edge's inside end to its outside end),
 * split into two triangles along the diagonal that folds least. Where the
 * surface stays in the grid the result is closed and consistently wound,
 * and manifold (two sheets of a cell that both cross one face twice, on
 * both sides of it, are the exception). With `seeds` NULL every cell is
 * looked at; else only the surface reached from the seeds (as
 * merp_mtet_polygonize_seeded). Normals are −∇f at the vertices (one side's,
 * on a crease): from `grad` in closed form, or with `grad` NULL by forward
 * differences (three evaluations). `out` holds merp_dc_bound's counts, or
 * its rooms are set; `src` (NULL, or room for as many vertices) gets each
 * vertex's source. Errors: MER_ERR_NOMEM; MER_ERR_INVALID (past a room).
 * Cost: O(crossed cells) evaluations: each crossed edge is solved once. */
mer_result merp_dc_polygonize(const merp_grid *g, merp_field_fn f, merp_gradient_fn grad,
                              const void *data, const float (*seeds)[3], uint32_t nseeds,
                              merp_trimesh *out, merp_dc_source *src, mer_error *err);

/* ------------------------------------------------------------ junction.c */

#define MERP_JUNCTION_LATERALS 2 /* a node has at most two lateral children */

/* The field of one branch junction (G04 §3.2): the parent's axis through the
 * junction point J (the parent internode in, its continuation out, as one
 * solid A = max(f_in, f_out), so the axis does not bulge at its elbow) and the
 * laterals L_k leaving J. With B2 = A + Σ L_k (summation, eq. 3) and
 * B1 = max(A', L_k') (PCM, eq. 2: A' = A + Σ Δ(c − L_k), L_k' = L_k + Δ(c − A)),
 * F_g = F_b·B1 + (1 − F_b)·B2 (eq. 4) with F_b = max_k F_b,k: the crease of
 * contact (the branch bark ridge) in the crotch above each lateral, where its
 * bound sits, and the smooth blend elsewhere. */
typedef struct merp_junction {
    merp_seg in, out;        /* the parent's axis (out: its continuation, or a
                                lateral that relays it); out.ra = 0: none */
    merp_seg lateral[MERP_JUNCTION_LATERALS];
    merp_bound bound[MERP_JUNCTION_LATERALS];
    uint32_t laterals;       /* 0..MERP_JUNCTION_LATERALS (0: an elbow of the
                                axis, its scar alone, where a relay shoot
                                goes on from a tip) */
    float w;                 /* PCM's bulge width (field units) */
    /* The bud scale scar between the parent's last shoot (in) and this
     * year's (out): A = F_s·max(in', out') + (1 − F_s)·max(in, out) with F_s =
     * scar_weight·F_b,scar (PCM of in and out, bulge width MERP_ISO). All
     * zero (no scar) unless merp_junction_age sets them. */
    merp_bound scar;
    float scar_weight;
} merp_junction;

/* Places lateral k's bound at the crotch C between it and the parent's
 * continuation or relay (`up`, unit): where the parent's surface meets the lateral's
 * upper side in the plane of the two axes, reaching along the lateral, with
 * its extent and r_in, r_out proportional to the lateral's radius and grown by
 * `ridge` ∈ [0, 1] (the ridge's age, G04 Fig. 7; 0: no ridge, F_b = 0). */
void merp_junction_bound(merp_junction *j, uint32_t k, const float up[3], float ridge);

/* Ages the junction's bark to `years` (≥ 1; the years since the lateral's
 * shoot grew: 1 in the season it appears), after G04 §3.2 and Fig. 7: the
 * bud scale scar ring at the base of the parent's shoot (between in and out)
 * fades as bark grows over it, and each lateral's scar ring, a crease all
 * round its base at first, becomes its branch bark ridge in the crotch above
 * it. G04 gives no law; ours: the parent's scar weight is
 * σ(y) = merp_junction_scar_weight(y) = e^(−(y − 1)/3), 1, 0.37, 0.14, 0.05
 * at years 1, 4, 7, 10, and each lateral's bound moves from its ring
 * (around the lateral's axis where it meets the parent, F_b = 1 out to
 * 1.15 r_L) to merp_junction_bound's crotch bound at ridge 1, by 1 − σ(y)
 * (the bound's ends and radii interpolated). Sets scar, scar_weight and
 * every bound[k] (replacing merp_junction_bound's). */
void merp_junction_age(merp_junction *j, const float up[3], float years);

/* σ(y) of merp_junction_age: 1 up to year 1, e^(−(y − 1)/3) after. */
float merp_junction_scar_weight(float years);

/* A run: up to MERP_RUN_FORKS forks close enough that their patches would
 * overlap, polygonized as one patch (joints_plan.c plans them where single
 * patches do not fit). Each fork but the first goes on from an earlier one
 * (merp_link): up its continuation (fork[from].out and this fork's in are
 * the one segment J_from → J) or up one of its laterals (fork[from]'s
 * lateral[slot] and this fork's in are that segment: a fork near the base
 * of another's lateral). Forks linked up continuations form a group, one
 * axis; the first fork and each fork up a lateral begin one. A group's field
 * folds its axis up its forks: A_0 = f(in of its first fork), and at each
 * fork A_{i+1} = max(A_i, f_out) with the fork's bud scale scar blended in
 * as a single fork's (F_s·PCM(A_i, f_out) + (1 − F_s)·max), so a run of one
 * fork is that fork's field to the bit; every lateral of its forks joins A
 * as a single fork's laterals do (B2 = A + Σ L, B1 = max(A', L'), F_b the
 * largest of their bounds), where a lateral that another group goes on up
 * counts as that group's whole field. The run's field is its first group's.
 * Thirty-two forks held a bush's short axes with all their twig forks
 * (abop-1.24c's runs of 27, whose axes curl at every node: at seed 1, 21
 * forks left tubes with runs of at most 24, 11 with these; joints.c, the
 * cuts' depth); sixty-four hold the longer ones of abop-1.24d, 1.24a and
 * 1.27 (seeds 1-5: 110, 185 and 161 forks left tubes with 32; 35, 140 and
 * 131 with these). */
#define MERP_RUN_FORKS 64
/* Rows of four lanes for a run's segments (its first in, and each fork's
 * out and laterals: 3 K + 1) and for its bounds (each fork's scar and
 * laterals' bounds: 3 K): 4 K lanes hold either, each lane's index a byte
 * (merp_jlanes). */
#define MERP_JROWS MERP_RUN_FORKS
_Static_assert(MERP_JROWS * MERP_ROW <= 256, "merp_jlanes holds a lane's index in a byte");
#define MERP_LINK_OUT 0xff /* merp_link.slot: up the continuation (or the relay, where it has none living) */

typedef struct merp_link {
    uint8_t from, slot; /* the fork it goes on from, and up which: MERP_LINK_OUT or a lateral */
} merp_link;

/* A junction, or a run of them, made ready for many samples: its segments
 * (the first fork's in; then each fork's out and laterals, fork by fork)
 * and its bounds (the scars, fork by fork; then the laterals' bounds, fork
 * by fork) in rows, each lane that does not take part (no continuation, no
 * scar, a bound of no ridge, the rows' spare lanes) cleared to a field of
 * 0. Its fields and gradients are the junction's to the bit
 * (merp_junction_field and merp_junction_gradient prepare one on every
 * call); a patch prepares its junction once for all its samples. Where
 * F_b = 0 (beyond the ridge, most samples) F_g is B2 exactly, and B1 is not
 * evaluated. */
/* Where a run's values lie: each fork's lanes, its in (the lane of the
 * segment it goes on from), out and laterals in the segment rows, its
 * laterals' bounds in the bound rows (its scar's is its own index); the
 * group up each lateral; the groups' forks. */
typedef struct merp_jlanes {
    uint8_t in_lane[MERP_RUN_FORKS], out_lane[MERP_RUN_FORKS];
    uint8_t lat_lane[MERP_RUN_FORKS][MERP_JUNCTION_LATERALS], bnd_lane[MERP_RUN_FORKS][MERP_JUNCTION_LATERALS];
    uint8_t child[MERP_RUN_FORKS][MERP_JUNCTION_LATERALS]; /* 0: none (the first group is no one's) */
    uint8_t group_first[MERP_RUN_FORKS + 1]; /* group g: forks group_first[g] .. group_first[g + 1] − 1 */
    uint8_t groups;
} merp_jlanes;

/* A single fork's lanes (see MERP_JSEG_IN below), as constants each file
 * that evaluates a junction can fold. */
static const merp_jlanes MERP_JLANES_SINGLE = {.in_lane = {0},
                                               .out_lane = {1},
                                               .lat_lane = {{2, 3}},
                                               .bnd_lane = {{1, 2}},
                                               .group_first = {0, 1},
                                               .groups = 1};

typedef struct merp_jprep {
    const merp_junction *j; /* the run's forks, j[0 .. forks) */
    uint32_t forks, rows;
    merp_jlanes lanes;
    merp_row seg[MERP_JROWS];
    merp_row bound[MERP_JROWS];
    /* A run's segment rows each hold a few primitives near one fork: beyond
     * the box holding a row's supports (lo, hi; with a margin) its lanes
     * are +0, field and gradient, and the row is not evaluated. */
    float seg_box[MERP_JROWS][2][3];
    /* A ball about each bound that takes part (centre, squared radius),
     * holding its support with a margin: see merp_jprep_near_bounds. */
    float reach[MERP_JROWS * MERP_ROW][4];
    uint32_t reaches;
    /* The box of each bound row's balls: a run's rows beyond it are +0
     * (merp_jprep_bound_field), as a single fork's row beyond every ball. */
    float bound_box[MERP_JROWS][2][3];
} merp_jprep;

/* A single fork's lanes: seg's (in, out, the laterals) and bound's (the
 * scar, the laterals' bounds). */
enum { MERP_JSEG_IN, MERP_JSEG_OUT, MERP_JSEG_LATERAL };
enum { MERP_JBOUND_SCAR, MERP_JBOUND_LATERAL };

/* Whether p may lie in some bound's support. When not, every lane of
 * jp->bound is 0 at p, field and gradient (+0, as row.c gives them), so
 * callers skip the rows (most samples of a patch lie beyond every bound). */
static inline bool merp_jprep_near_bounds(const merp_jprep *jp, const float p[3])
{
    for (uint32_t i = 0; i < jp->reaches; i++) {
        const float *b = jp->reach[i];
        float d[3] = {p[0] - b[0], p[1] - b[1], p[2] - b[2]};
        if (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] <= b[3])
            return true;
    }
    return false;
}

/* Whether p lies within the box of jp's bound row r's balls (beyond it,
 * each of its lanes is +0 at p, field and gradient). */
static inline bool merp_jprep_in_bound_row(const merp_jprep *jp, uint32_t r, const float p[3])
{
    const float(*b)[3] = jp->bound_box[r];
    return p[0] >= b[0][0] && p[1] >= b[0][1] && p[2] >= b[0][2] && p[0] <= b[1][0] && p[1] <= b[1][1] &&
           p[2] <= b[1][2];
}

/* jp's bound lanes at p, row by row (F: MERP_ROW × jp->rows):
 * merp_row_bound_field (and merp_row_bound_gradient) of jp->bound, or +0 in
 * every lane, field and gradient, where p lies beyond every bound
 * (merp_jprep_near_bounds): the rows are only evaluated near one, and a
 * run's only within their boxes (on the 10k bench tree's runs of 8 and 14
 * forks, a sample near one fork's bounds evaluated every fork's). */
static inline void merp_jprep_bound_field(const merp_jprep *jp, const float p[3], float *F)
{
    bool near = merp_jprep_near_bounds(jp, p);
    for (uint32_t r = 0; r < jp->rows; r++) {
        if (near && (jp->rows == 1 || merp_jprep_in_bound_row(jp, r, p)))
            merp_row_bound_field(&jp->bound[r], p, F + MERP_ROW * r);
        else
            for (int l = 0; l < MERP_ROW; l++)
                F[MERP_ROW * r + (uint32_t)l] = 0.0f;
    }
}
static inline void merp_jprep_bound_gradient(const merp_jprep *jp, const float p[3], merp_row_grad *out)
{
    bool near = merp_jprep_near_bounds(jp, p);
    for (uint32_t r = 0; r < jp->rows; r++) {
        if (near && (jp->rows == 1 || merp_jprep_in_bound_row(jp, r, p)))
            merp_row_bound_gradient(&jp->bound[r], p, out + r);
        else
            memset(out + r, 0, sizeof *out); /* +0 */
    }
}

/* Whether p lies beyond the box of jp's segment row r (then each of its
 * lanes is +0 at p, field and gradient). A single fork's one row is always
 * evaluated. */
static inline bool merp_jprep_beyond_row(const merp_jprep *jp, uint32_t r, const float p[3])
{
    if (jp->rows == 1)
        return false;
    const float(*b)[3] = jp->seg_box[r];
    return p[0] < b[0][0] || p[1] < b[0][1] || p[2] < b[0][2] || p[0] > b[1][0] || p[1] > b[1][1] ||
           p[2] > b[1][2];
}

/* Prepares jp for the run of `forks` (1 .. MERP_RUN_FORKS) junctions at j,
 * fork i > 0 going on from link[i] (link NULL: each from the one before,
 * up its continuation), which must outlive it and not change meanwhile.
 * Requires each group's forks listed together, in order up its axis, and a
 * fork up a lateral after the fork it goes on from. */
void merp_jprep_init_run(merp_jprep *jp, const merp_junction *j, const merp_link *link, uint32_t forks);

/* Prepares jp for the single junction j (a run of one). */
void merp_jprep_init(merp_jprep *jp, const merp_junction *j);

/* merp_junction_field and merp_junction_gradient of jp's junction (or run). */
float merp_jprep_field(const merp_jprep *jp, const float p[3]);
float merp_jprep_gradient(const merp_jprep *jp, const float p[3], float g[3]);
/* merp_jprep_gradient, and the bound rows' values at p into `bounds`
 * (MERP_ROW × jp->rows), bit for bit as merp_jprep_bound_field gives them
 * (the gradient evaluates them anyway). */
float merp_jprep_gradient_bounds(const merp_jprep *jp, const float p[3], float g[3], float *bounds);

/* F_g(p) of the junction (see above); `data` is a const merp_junction *. */
float merp_junction_field(const float p[3], const void *data);

/* F_g(p) of the junction, as merp_junction_field, and its gradient ∇F_g into
 * g, in closed form (gradient.c): one pass over the primitives, for normals.
 * Where F_g is not differentiable (a max's tie, a crease) g is one side's.
 * Cost O(1), about two field evaluations. */
float merp_junction_gradient(const merp_junction *j, const float p[3], float g[3]);

/* F_b(p) of the junction: b, the ridge's weight at p. */
float merp_junction_ridge(const merp_junction *j, const float p[3]);

/* How much each bounded blend changes the field at p: *scar = F_s·|B1 − B2|
 * of the parent's scar (in and out), *ridge = F_b·|B1 − B2| of the laterals'
 * ridge (the strength of a scar or ridge there, in field units). */
void merp_junction_strength(const merp_junction *j, const float p[3], float *scar, float *ridge);

/* --------------------------------------------------------------- patch.c */

/* A cut plane of a junction's patch: the shaft beyond it (dot(p − o, n) > 0,
 * n unit, pointing away from the junction) stays a generalized cylinder, whose
 * ring of `sides` vertices `ring` lies in the plane (any rotation, any
 * direction around n). The cut acts only within `reach` of the line through o
 * along n (a few radii of its shaft), so it does not clip another shaft, and
 * at most `depth` beyond the plane (> 0; INFINITY: all the way), so that it
 * does not clip a primitive further out along that line: a run's axis that
 * curls back across a lateral's line, past the lateral's own segment. A
 * cut with no ring (sides 0) keeps the flat cap its clip makes: the patch
 * closes itself there (a trunk's base on the ground). */
typedef struct merp_cut {
    float o[3], n[3];
    float reach;
    const float *ring; /* 3 floats a vertex; NULL with sides 0 */
    uint32_t sides;    /* 0: no ring, the cap kept */
    float depth;
} merp_cut;

/* The parent in, out, and two laterals a fork (a run's middle segments
 * have no cut). */
#define MERP_PATCH_CUTS (2 + MERP_JUNCTION_LATERALS * MERP_RUN_FORKS)

/* A junction's patch: its field, the cuts, the grid it is polygonized on
 * (which must hold the surface between the cuts; the segments must reach
 * past their cuts, so the surface there is the plain tube), and the
 * polygonizer: marching tetrahedra (the crease rounded off within a cell)
 * or, with `sharp`, dual contouring (a vertex on the ridge's crease in every
 * cell it crosses). */
typedef struct merp_patch {
    const merp_junction *j; /* the run's forks, j[0 .. forks) */
    uint32_t forks;         /* 0 is read as 1: a single junction */
    const merp_link *link;  /* how they go on (merp_jprep_init_run); NULL: a chain */
    merp_cut cut[MERP_PATCH_CUTS];
    uint32_t cuts;
    merp_grid grid;
    uint32_t sharp; /* 1: dual contouring; 0: marching tetrahedra */
} merp_patch;

/* The most vertices and triangles merp_patch_build writes: the polygonizer's
 * bound for the grid, capped at MERP_PATCH_ROOM_VERTICES and twice as many
 * triangles, plus each cut's ring and its stitch (the loop's vertices are
 * the polygonizer's). The bound of a surface through every cell of the grid
 * would reserve gigabytes for a run's grid of millions of cells, whose
 * surface crosses a few per cent of them. */
#define MERP_PATCH_ROOM_VERTICES (1u << 20) /* far past any patch the mesh keeps (MER_MESH_CHUNK_VERTICES) */
void merp_patch_bound(const merp_patch *pt, uint64_t *vertices, uint64_t *triangles);

/* Polygonizes the junction between its cuts and stitches each cut's boundary
 * loop to that cut's ring: F_g is clipped beyond each cut's plane (within
 * its reach and depth, merp_cut), the flat caps the clip makes are dropped
 * (a ring-less cut's kept), and each loop left in a cut plane is zipped
 * to a copy of the ring (appended to `out`, positions exactly the ring's),
 * walking both by angle about n. With dual contouring, the vertex
 * of each cell the cap crosses is moved onto its cut plane (it lies on the
 * crease between cap and tube, up to the QEF's regularisation), so each loop
 * lies in its plane; each loop vertex is then moved in that plane, along
 * its ray from o, to just inside the ring's polygon (the surface at a cut is
 * the plain tube, so this undoes the polygonizer's error of about a cell,
 * which the zip would show as a ledge round the shaft), and the surface
 * within half a ring radius before the cut is drawn towards the ring's
 * polygon, fully at the loop and not at all half a radius in (the tube
 * beyond is a prism on that polygon, inside the round surface by up to
 * 1 − cos(π / sides) of the radius: a shoulder otherwise). The result's
 * only open edges are the rings' (so a tube that shares the ring closes
 * it), wound outwards.
 * `out` holds merp_patch_bound's counts; unused polygonizer vertices are
 * dropped. Errors: MER_ERR_NOMEM; MER_ERR_INVALID when a cut leaves no single
 * loop (the grid or cuts do not fit the junction), or the surface outgrows
 * the polygonizer's capped room. Cost: the polygonizer's,
 * plus O(vertices log vertices). */
mer_result merp_patch_build(const merp_patch *pt, merp_trimesh *out, mer_error *err);

#endif
