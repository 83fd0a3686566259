/* meristem — implicit junctions in the bark (meristem/mesh.h, Junctions; G04
 * §3, issue 18): the patches of the forks joints_plan.c planned, built
 * (lib/mesh/implicit/) with their UVs and ridge values, and written into the
 * bark part. tube.c writes the cut rings. */
#include "config.h"

#include <math.h>
#include <stdlib.h>

#include "core/alloc.h"
#include "core/atan2.h"
#include "core/parallel.h"
#include "mesh_private.h"


/* Each axis's ring counts and, for an axis that starts in no patch, its
 * base disk; with `record`, the cut rings of the axes that have any. */
static mer_result walk_axes(merp_builder *b, bool record, mer_error *err)
{
    for (uint32_t i = 0; i < b->axis_count; i++) {
        merp_axis *a = &b->axes[i];
        bool starts_in = b->lateral_in[a->first] != UINT32_MAX, cuts = starts_in;
        a->base_cap = !starts_in; /* a root's, unless a patch holds the base (merp_joint.base) */
        a->extra_rings = 0, a->lost_bands = 0, a->ends_in = 0;
        uint32_t id = a->first;
        for (uint32_t k = 0; k < a->count && !cuts; k++, id = b->nodes[id].main_child)
            cuts = b->cut_begin[id] != UINT32_MAX || b->cut_end[id] != UINT32_MAX;
        if (cuts) {
            mer_result rc = merp_mesh_record_rings(b, a, record, err);
            if (rc != MER_OK)
                return rc;
        }
    }
    return MER_OK;
}

/* The shaft nearest p: the smallest distance in units of the shaft's radius
 * (a run's axis between its forks counts as none: a point there goes to the
 * nearer of its in and out shafts). */
static uint32_t nearest_shaft(const merp_joint *jt, const merp_jprep *jp, const float p[3])
{
    merp_row_point c[MERP_JROWS];
    for (uint32_t r = 0; r < jp->rows; r++)
        merp_row_closest(&jp->seg[r], p, &c[r]);
    uint32_t best = 0;
    float best_x = INFINITY;
    for (uint32_t s = 0; s < jt->cuts; s++) {
        uint32_t l;
        const merp_seg *g = merp_joint_shaft(jt, s, jp, &l);
        const merp_row_point *q = &c[l / MERP_ROW];
        float t = q->t[l % MERP_ROW], d = sqrtf(q->d2[l % MERP_ROW]), x = d / ((1.0f - t) * g->ra + t * g->rb);
        if (x < best_x)
            best_x = x, best = s;
    }
    return best;
}

/* Vertex k's UV on shaft s: u by angle in the cut ring's frame, v by arc
 * length from the cut along the shaft (mesh.h, UVs). */
static void shaft_uv(const merp_builder *b, const merp_joint *jt, uint32_t s, const float p[3],
                     float uv[2])
{
    float q[3];
    for (int k = 0; k < 3; k++)
        q[k] = p[k] - jt->o[s][k];
    float r = merp_node_radius(b, jt->node[s]) + merp_node_end_radius(b, jt->node[s]);
    float u = merp_atan2f(v3_dot(q, jt->frame[s][1]), v3_dot(q, jt->frame[s][0])) / MERP_TWO_PI;
    uv[0] = u < 0.0f ? u + 1.0f : u;
    uv[1] = jt->v[s] + (s == MERP_CUT_IN ? -1.0f : 1.0f) * v3_dot(q, jt->n[s]) / (MERP_TWO_PI * 0.5f * r);
}

/* The UV frame and v (shaft_uv) of an in shaft that ends on the plant's
 * base (jt->base), which no tube ring records: v 0 there, as a trunk's tube
 * starts, and a frame as tube.c starts one (its normal level, up × the
 * shaft's axis from the base to J; no ring at the base has to match it). */
static void base_frame(merp_joint *jt)
{
    const float *n = jt->n[MERP_CUT_IN], up[3] = {0.0f, 1.0f, 0.0f};
    const float t[3] = {-n[0], -n[1], -n[2]}; /* the trunk's axis, up */
    float *e = jt->frame[MERP_CUT_IN][0];
    v3_cross(up, t, e);
    if (!v3_normalize(e))
        v3_any_perp(t, e);
    v3_cross(t, e, jt->frame[MERP_CUT_IN][1]);
    jt->v[MERP_CUT_IN] = 0.0f;
}

/* A capped shaft's UV frame and v (shaft_uv), which no tube ring records:
 * u by angle from the in cut's frame laid square to the shaft, and v
 * running on from the in shaft's at J, so the bark's texture goes on up
 * the shaft as it would along a tube. */
static void capped_frames(const merp_builder *b, merp_joint *jt)
{
    if (jt->base)
        base_frame(jt);
    const float *e0 = jt->frame[MERP_CUT_IN][0];
    float r0 = merp_node_radius(b, jt->node[MERP_CUT_IN]) + merp_node_end_radius(b, jt->node[MERP_CUT_IN]);
    float v_J = jt->v[MERP_CUT_IN] + jt->d[MERP_CUT_IN] / (MERP_TWO_PI * 0.5f * r0);
    for (uint32_t s = 1; s < jt->cuts; s++) {
        if (!jt->capped[s])
            continue;
        const float *n = jt->n[s];
        float *e = jt->frame[s][0], *f = jt->frame[s][1], c = v3_dot(e0, n);
        for (int k = 0; k < 3; k++)
            e[k] = e0[k] - c * n[k];
        if (!v3_normalize(e))
            v3_any_perp(n, e);
        v3_cross(n, e, f); /* as tube.c's in cut has it: (−n0) × e0, −n0 the axis up */
        float r = merp_node_radius(b, jt->node[s]) + merp_node_end_radius(b, jt->node[s]);
        jt->v[s] = v_J + jt->d[s] / (MERP_TWO_PI * 0.5f * r);
    }
}

/* Whether triangle c's u spans the seam (jumps over 1 → 0: more than ½). */
static bool spans_seam(const merp_joint *jt, const uint32_t *c)
{
    float lo = 2.0f, hi = -1.0f;
    for (int k = 0; k < 3; k++) { /* no fminf, fmaxf: u is never NaN, and they are calls in libm */
        float u = jt->uvs[2 * c[k]];
        lo = u < lo ? u : lo, hi = u > hi ? u : hi;
    }
    return hi - lo > 0.5f;
}

/* Gives a vertex of u < ½ in every triangle that spans the seam (u jumps
 * over 1 → 0) a copy at u + 1, as the tube's seam vertex; a vertex whose
 * every triangle spans it is moved to u + 1 itself instead, so no vertex is
 * left that no triangle uses (an importer drops those: assimp counted
 * fewer vertices than the GLB holds). `scratch` has room for twice the
 * patch's vertices. */
static void split_seam(merp_joint *jt, uint32_t *scratch)
{
    merp_trimesh *m = &jt->mesh;
    uint32_t n = m->vertex_count, *copy = scratch, *kept = scratch + n;
    for (uint32_t v = 0; v < n; v++)
        copy[v] = UINT32_MAX, kept[v] = 0;
    /* kept[v]: v's corners that stay v (a triangle that does not span the seam) */
    for (uint32_t t = 0; t < m->triangle_count; t++) {
        const uint32_t *c = m->triangles + 3 * (size_t)t;
        if (!spans_seam(jt, c))
            for (int k = 0; k < 3; k++)
                kept[c[k]]++;
    }
    for (uint32_t t = 0; t < m->triangle_count; t++) {
        uint32_t *c = m->triangles + 3 * (size_t)t;
        if (!spans_seam(jt, c))
            continue;
        for (int k = 0; k < 3; k++) {
            uint32_t v = c[k];
            assert(v < n); /* each corner is looked at once, before it is replaced */
            if (jt->uvs[2 * v] >= 0.5f || v == copy[v])
                continue; /* its high side, or v itself moved across */
            if (copy[v] == UINT32_MAX && kept[v] == 0) {
                jt->uvs[2 * v] += 1.0f; /* every triangle of v spans the seam */
                copy[v] = v;
                continue;
            }
            if (copy[v] == UINT32_MAX) {
                uint32_t w = copy[v] = m->vertex_count++;
                memcpy(m->positions + 3 * (size_t)w, m->positions + 3 * (size_t)v, 3 * sizeof(float));
                memcpy(m->normals + 3 * (size_t)w, m->normals + 3 * (size_t)v, 3 * sizeof(float));
                jt->uvs[2 * w] = jt->uvs[2 * v] + 1.0f;
                jt->uvs[2 * w + 1] = jt->uvs[2 * v + 1];
                jt->ridge[w] = jt->ridge[v];
                jt->shaft[w] = jt->shaft[v];
            }
            c[k] = copy[v];
        }
    }
}

/* b of the bark at a point where the bound rows' values are F
 * (merp_jprep_bound_field; a bound left out is 0; mesh.h, Junctions): the
 * laterals' F_b and the parent's bud scale scars, σ(y)·F_b of each band (G04
 * §3.2: the bounding field marks the PCM region's texture, Fig. 7: the scar
 * fades). */
static float bark_mark(const merp_jprep *jp, const float *F)
{
    float b = 0.0f;
    for (uint32_t i = 0; i < jp->forks; i++)
        for (uint32_t k = 0; k < jp->j[i].laterals; k++) /* merp_junction_ridge */
            b = F[jp->lanes.bnd_lane[i][k]] > b ? F[jp->lanes.bnd_lane[i][k]] : b;
    for (uint32_t i = 0; i < jp->forks; i++) {
        const merp_junction *f = &jp->j[i];
        if (f->scar_weight > 0.0f && f->out.ra > 0.0f)
            b = fmaxf(b, f->scar_weight * F[i]);
    }
    return b;
}

/* How much of the bark's mark shows at p: 1 in the patch, falling smoothly
 * to 0 over the last radius before each cut, so that b (0 on the tubes)
 * and with it the bark's colour are continuous across the cut rings. */
static float mark_fade(const merp_builder *b, const merp_joint *jt, const float p[3])
{
    float w = 1.0f;
    for (uint32_t s = 0; s < jt->cuts; s++) {
        if (!merp_cut_has_ring(jt, s))
            continue; /* no tube beyond it */
        float q[3], r = merp_cut_radius(b, jt, s);
        for (int k = 0; k < 3; k++)
            q[k] = jt->o[s][k] - p[k];
        float x = v3_dot(q, jt->n[s]) / r;
        if (x < 1.0f && v3_dot(q, q) - x * x * r * r <= MERP_JOINT_SHELL * MERP_JOINT_SHELL * r * r) {
            x = fmaxf(x, 0.0f);
            w = fminf(w, x * x * (3.0f - 2.0f * x));
        }
    }
    return w;
}

/* Where a vertex's normal −∇F_g points into the surface its triangles make
 * (their area-weighted normals' sum `facing` points the other way), their
 * mean instead. F_g is no smooth function at a crease: its gradient there is
 * one side's, and in PCM's compression, where each solid is deformed by the
 * other (f1' = f1 + c − f2), that side's is ∇f1 − ∇f2, which can point
 * inwards; such a vertex shaded black (fork_ages' fork in its first year, a
 * vertex on the bud scale scar's crease). Not the ring copies: at a cut the
 * field is the plain tube's, and their normals are the tube's ring's. At a
 * crease turning more than 90°, a vertex's one-sided normal may also be
 * replaced where the other side's triangles are larger: it then shades as
 * the mean, which such a crease is drawn with anyway. */
static void face_outwards(const merp_trimesh *m, uint32_t ring_first, float *facing)
{
    memset(facing, 0, 3 * (size_t)m->vertex_count * sizeof *facing);
    for (uint32_t t = 0; t < m->triangle_count; t++) {
        const uint32_t *c = m->triangles + 3 * (size_t)t;
        const float *a = m->positions + 3 * (size_t)c[0], *p1 = m->positions + 3 * (size_t)c[1],
                    *p2 = m->positions + 3 * (size_t)c[2];
        float e1[3], e2[3], n[3];
        for (int k = 0; k < 3; k++)
            e1[k] = p1[k] - a[k], e2[k] = p2[k] - a[k];
        v3_cross(e1, e2, n);
        for (int i = 0; i < 3; i++)
            for (int k = 0; k < 3; k++)
                facing[3 * (size_t)c[i] + k] += n[k];
    }
    for (uint32_t v = 0; v < ring_first; v++) {
        float *nr = m->normals + 3 * (size_t)v, *f = facing + 3 * (size_t)v;
        if (v3_dot(nr, f) < 0.0f && v3_normalize(f))
            memcpy(nr, f, 3 * sizeof *nr);
    }
}

/* The flat cap a patch keeps on the plant's base (jt->base), as tube.c's
 * base disk has it: its vertices' normal the plane's, down (−∇F_g there is
 * the bark's beside it), UVs by place on the disk (a shaft's would give
 * the cap no area in UV space), no ridge; a rim vertex, which the bark's
 * triangles share, keeps the bark's. The cap's vertices lie on the plane
 * (moved onto it, patch.c) to the rounding of their coordinates, which a
 * plant far from the origin makes more than a thin trunk's radius: a
 * vertex within a millionth of the coordinates' size (or a hundred-
 * thousandth of the radius) counts as on it. `on` has a word a vertex. */
static void base_cap(const merp_builder *b, merp_joint *jt, uint32_t *on)
{
    merp_trimesh *m = &jt->mesh;
    const float *o = jt->o[MERP_CUT_IN], *n = jt->n[MERP_CUT_IN];
    const float *e0 = jt->frame[MERP_CUT_IN][0], *e1 = jt->frame[MERP_CUT_IN][1];
    const float r = merp_cut_radius(b, jt, MERP_CUT_IN);
    const float tol = fmaxf(1e-5f * r, 1e-6f * (fabsf(o[0]) + fabsf(o[1]) + fabsf(o[2]) + r));
    for (uint32_t v = 0; v < m->vertex_count; v++) {
        const float *p = m->positions + 3 * (size_t)v;
        const float q[3] = {p[0] - o[0], p[1] - o[1], p[2] - o[2]};
        on[v] = fabsf(v3_dot(q, n)) <= tol; /* 1: on the plane, 2: on its rim */
    }
    for (uint32_t t = 0; t < m->triangle_count; t++) {
        const uint32_t *c = m->triangles + 3 * (size_t)t;
        if (!on[c[0]] || !on[c[1]] || !on[c[2]])
            for (int k = 0; k < 3; k++)
                on[c[k]] = on[c[k]] ? 2u : 0u;
    }
    for (uint32_t v = 0; v < m->vertex_count; v++) {
        if (on[v] != 1)
            continue;
        const float *p = m->positions + 3 * (size_t)v;
        const float q[3] = {p[0] - o[0], p[1] - o[1], p[2] - o[2]};
        memcpy(m->normals + 3 * (size_t)v, n, 3 * sizeof(float));
        jt->uvs[2 * v] = 0.5f + 0.5f * v3_dot(q, e0) / r; /* seen from below, as tube.c's disk */
        jt->uvs[2 * v + 1] = 0.5f - 0.5f * v3_dot(q, e1) / r;
        jt->ridge[v] = 0.0f;
    }
}

/* The patch's vertex attributes: normals −∇F_g (the unclipped field, so the
 * rings shade as the tubes; face_outwards where it points inwards), shafts,
 * ridge b = F_b, UVs (ring copies exactly the ring's), the base's cap
 * (base_cap), then the seam split. `facing`: room for 3 floats a vertex. */
static void patch_attributes(const merp_builder *b, merp_joint *jt, uint32_t *scratch, float *facing)
{
    merp_trimesh *m = &jt->mesh;
    uint32_t ring_first = m->vertex_count;
    for (uint32_t s = 0; s < jt->cuts; s++)
        ring_first -= jt->sides[s];
    merp_jprep jp;
    merp_jprep_init_run(&jp, jt->field, jt->link, jt->forks);
    for (uint32_t v = 0; v < m->vertex_count; v++) {
        float *p = m->positions + 3 * (size_t)v, *nr = m->normals + 3 * (size_t)v;
        float F[MERP_JROWS * MERP_ROW]; /* the bound rows' values at p: bark_mark's */
        merp_jprep_gradient_bounds(&jp, p, nr, F);
        for (int k = 0; k < 3; k++)
            nr[k] = -nr[k];
        if (!v3_normalize(nr))
            nr[0] = 0.0f, nr[1] = 1.0f, nr[2] = 0.0f;
        jt->ridge[v] = bark_mark(&jp, F) * mark_fade(b, jt, p);
        if (v < ring_first) {
            uint32_t s = nearest_shaft(jt, &jp, p);
            jt->shaft[v] = (uint8_t)s;
            shaft_uv(b, jt, s, p, jt->uvs + 2 * (size_t)v);
            continue;
        }
        uint32_t s = 0, j = v - ring_first; /* a ring copy: its cut and place on the ring */
        for (; j >= jt->sides[s]; s++)
            j -= jt->sides[s];
        jt->shaft[v] = (uint8_t)s;
        jt->uvs[2 * v] = (float)j / (float)jt->sides[s];
        jt->uvs[2 * v + 1] = jt->v[s];
        memcpy(jt->ring_normal[s] + 3 * j, nr, 3 * sizeof(float)); /* face_outwards keeps it */
    }
    if (jt->base)
        base_cap(b, jt, scratch);
    face_outwards(m, ring_first, facing);
    if (!b->opt.no_uvs)
        split_seam(jt, scratch);
}

/* jt's patch into m (room for pt->sharp's polygonizer). *ring_first: the
 * first of the ring copies. MER_ERR_INVALID when it does not close. */
static mer_result polygonize_patch(const merp_patch *pt, const merp_joint *jt, merp_trimesh *m,
                                   uint32_t *ring_first, mer_error *err)
{
    mer_result rc = merp_patch_build(pt, m, err);
    if (rc != MER_OK)
        return rc;
    *ring_first = m->vertex_count;
    for (uint32_t s = 0; s < jt->cuts; s++)
        *ring_first -= jt->sides[s];
    if (!merp_patch_closes(m, *ring_first))
        rc = mer_error_set(err, MER_ERR_INVALID, NULL, "a junction's patch does not close");
    return rc;
}

/* Builds jt's patch on a grid of cells h (graded: fine only where its
 * shafts need them, merp_joint_grade) by dual contouring (sharp) or
 * marching tetrahedra into exact arrays of its own. MER_ERR_INVALID when the
 * patch does not close on its cuts, or its grid could not be graded (no
 * level wider, or no memory for the levels: the regular grid's tries
 * follow, and report running out themselves). */
static mer_result build_patch_at(merp_builder *b, merp_joint *jt, float h, float shift, uint32_t sharp,
                                bool graded, mer_error *err)
{
    merp_patch pt = {.j = jt->field, .forks = jt->forks, .link = jt->link, .sharp = sharp};
    if (!merp_joint_grid(b, jt, h, shift, &pt.grid))
        return mer_error_set(err, MER_ERR_INVALID, NULL, "a junction's grid is too large");
    void *coords = NULL; /* a graded grid's levels */
    if (graded && !merp_joint_grade(b, jt, &pt.grid, &coords))
        return mer_error_set(err, MER_ERR_INVALID, NULL, "a junction's grid is not graded");
    for (uint32_t s = 0; s < jt->cuts; s++) {
        if (jt->capped[s])
            continue; /* no cut: its segment's round end closes the shaft */
        merp_cut *c = &pt.cut[pt.cuts++];
        memcpy(c->o, jt->o[s], sizeof c->o);
        memcpy(c->n, jt->n[s], sizeof c->n);
        c->reach = MERP_JOINT_REACH * merp_cut_radius(b, jt, s) + h; /* the tube's there (plan_one) */
        /* Past the far end of the shaft's segment, and its round end, by two
         * cells: the cut clips all of the shaft beyond it, and nothing past
         * that (within its reach and this depth it clips any primitive). In a
         * bush whose axes curl at every node (abop-1.24c, seed 1), a run's
         * axis crossed a lateral's line further out; clipped away there, it
         * left that axis's out shaft a piece of surface apart, which no seed
         * reached: its cut had no loop on any grid (runs of 27 forks, 72
         * forks open). */
        uint32_t l;
        const merp_seg *g = merp_joint_shaft(jt, s, NULL, &l);
        const float *far = s == MERP_CUT_IN ? g->a : g->b;
        float beyond[3];
        for (int k = 0; k < 3; k++)
            beyond[k] = far[k] - c->o[k];
        c->depth = v3_dot(beyond, c->n) + (s == MERP_CUT_IN ? g->ra : g->rb) + 2.0f * h;
        c->ring = jt->ring[s];
        c->sides = jt->sides[s]; /* 0 on the base: the patch keeps its cap */
        assert((c->sides == 0) == (s == MERP_CUT_IN && jt->base));
    }
    uint64_t vmax, tmax;
    merp_patch_bound(&pt, &vmax, &tmax);
    merp_trimesh m = {0};
    m.positions = merp_malloc(vmax * 3 * sizeof(float));
    /* No normals: patch_attributes takes them from the unclipped field. */
    m.triangles = merp_malloc(tmax * 3 * sizeof(uint32_t));
    mer_result rc = MER_OK;
    if (m.positions == NULL || m.triangles == NULL)
        rc = mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for a junction");
    uint32_t ring_first = 0;
    if (rc == MER_OK)
        rc = polygonize_patch(&pt, jt, &m, &ring_first, err);
    /* Exact arrays, with room for the seam's copies (at most one a vertex). */
    size_t room = 2 * (size_t)m.vertex_count;
    if (rc == MER_OK) {
        jt->mesh = (merp_trimesh){.vertex_count = m.vertex_count,
                                  .triangle_count = m.triangle_count,
                                  .positions = merp_malloc(room * 3 * sizeof(float)),
                                  .normals = merp_malloc(room * 3 * sizeof(float)),
                                  .triangles = merp_malloc((size_t)m.triangle_count * 3 * sizeof(uint32_t))};
        jt->uvs = merp_malloc(room * 2 * sizeof(float));
        jt->ridge = merp_malloc(room * sizeof(float));
        jt->shaft = merp_malloc(room);
        uint32_t *scratch = merp_malloc(room * sizeof(uint32_t));
        float *facing = merp_malloc(3 * (size_t)m.vertex_count * sizeof(float) + 1);
        if (!jt->mesh.positions || !jt->mesh.normals || !jt->mesh.triangles || !jt->uvs ||
            !jt->ridge || !jt->shaft || !scratch || !facing) {
            rc = mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for a junction");
        } else {
            memcpy(jt->mesh.positions, m.positions, (size_t)m.vertex_count * 3 * sizeof(float));
            memcpy(jt->mesh.triangles, m.triangles, (size_t)m.triangle_count * 3 * sizeof(uint32_t));
            patch_attributes(b, jt, scratch, facing);
            if (jt->mesh.vertex_count > MER_MESH_CHUNK_VERTICES)
                rc = mer_error_set(err, MER_ERR_INVALID, NULL, "a junction has too many vertices");
        }
        merp_free(scratch), merp_free(facing);
    }
    merp_free(m.positions), merp_free(m.normals), merp_free(m.triangles), merp_free(coords);
    return rc;
}

static void free_patch(merp_joint *jt)
{
    merp_free(jt->mesh.positions), merp_free(jt->mesh.normals), merp_free(jt->mesh.triangles);
    merp_free(jt->uvs), merp_free(jt->ridge), merp_free(jt->shaft);
    jt->mesh = (merp_trimesh){0};
    jt->uvs = jt->ridge = NULL;
    jt->shaft = NULL;
}

/* A patch's finer grids: these × the first's cell. The first is set by
 * the parent's and the laterals' radii, not the continuation's; where the
 * continuation is far thinner (a sylleptic fork's), its cut ring may span
 * too few cells for the patch to close on the fork's grid, moved or not,
 * or on the finer one, and closes on the finest. */
#define FINER 0.7f
#define FINEST 0.5f
/* The fork's grid moved back by this × its cell on every axis: where two
 * of dual contouring's vertices fall at one position, or a thin cut's loop
 * goes astray, that is an accident of where the grid's corners fall, and
 * half a cell over they fall elsewhere, at the first grid's cost. Of the
 * 3,220 patches (a run's forks share one) of 56 presets (seed 1, 14
 * steps), 3,163 close on the first grid, 20 on this one, 28 on the finer
 * and 9 on the finest; 3,107, 60, 38 and 15 before dc.c reversed the
 * decider's choice on faces that a sheet crosses twice on both sides (the
 * two cells' vertices then shared the quads of all four of the face's
 * edges). */
#define SHIFT 0.5f

/* Builds jt's patch (build_patch_at), trying in turn: dual contouring, which
 * keeps the branch bark ridge's crease sharp (G04 §3.2), on the fork's grid,
 * on it moved by SHIFT, on a finer one and on the finest (FINEST: a thin
 * continuation's); then marching tetrahedra on the first and the finer,
 * whose crease is rounded off within a cell (before the finest grid, it
 * made 29 of 3,246 patches on 25 trees; now 2 of 3,264). Dual contouring's
 * patch may not close where two vertices fall at one position (SHIFT), or
 * where the thinnest laterals (a little over a cell per radius) leave a
 * cut's cap so few cells near its rim that the side cuts a piece of it off,
 * a second loop on that cut. A run is tried first by dual contouring on
 * its graded grid (merp_joint_grade: a run's regular grid has its thinnest
 * shaft's cells all over, a graded one only at the levels that shaft
 * spans; the 10k bench tree's trunk runs of 14 and 8 forks keep 7,689 and
 * 6,043 vertices on it, 11,637 and 11,416 on the regular one); a single
 * fork's grid, a few of its shafts' radii long, would gain little, and
 * stays regular. The first patch that closes is kept. MER_ERR_INVALID (and
 * the caller unplans the fork) when none does. */
static mer_result build_patch(merp_builder *b, merp_joint *jt, mer_error *err)
{
    static const struct {
        float scale, shift;
        uint32_t sharp;
        bool graded;
    } tries[] = {{1.0f, 0.0f, 1, true},   {1.0f, 0.0f, 1, false},  {1.0f, SHIFT, 1, false},
                 {FINER, 0.0f, 1, false}, {FINEST, 0.0f, 1, false}, {1.0f, 0.0f, 0, false},
                 {FINER, 0.0f, 0, false}};
    float h = merp_joint_cell(b, jt);
    mer_result rc = MER_ERR_INVALID;
    capped_frames(b, jt);
    for (size_t t = jt->forks > 1 ? 0 : 1; t < sizeof tries / sizeof *tries && rc == MER_ERR_INVALID; t++) {
        free_patch(jt);
        rc = build_patch_at(b, jt, tries[t].scale * h, tries[t].shift, tries[t].sharp, tries[t].graded, err);
        jt->smooth = !tries[t].sharp;
    }
    return rc;
}

/* The patches to build: each item writes only its joint and its result;
 * item k builds joint order[k]. */
typedef struct patch_run {
    merp_builder *b;
    mer_result *rc;
    uint32_t *order;
} patch_run;

static void patch_item(void *ctx, uint32_t k)
{
    patch_run *r = ctx;
    uint32_t i = r->order[k];
    mer_error e;
    r->rc[i] = MER_OK;
    if (!r->b->joints[i].ok)
        return; /* a fork a run took in (joints_plan.c) */
    r->rc[i] = build_patch(r->b, &r->b->joints[i], &e);
    if (r->rc[i] != MER_OK)
        free_patch(&r->b->joints[i]);
}

/* A patch's cost, roughly: the cells its surface crosses, each shaft's
 * side (its length in the patch by its radius) over a cell's face. */
static float patch_cost(const merp_builder *b, const merp_joint *jt)
{
    if (!jt->ok)
        return 0.0f;
    float h = merp_joint_cell(b, jt), area = 0.0f;
    for (uint32_t s = 0; s < jt->cuts; s++)
        area += jt->d[s] * merp_node_radius(b, jt->start[s]);
    return area / (h * h);
}

/* The joints in the order the threads take them: the costliest first, so
 * that no thread is left with a large patch while the others idle (on the
 * 10k bench tree the trunk's run of five forks, a tenth of the work, came
 * late). One thread takes them in joint order. */
static bool patch_order(const merp_builder *b, uint32_t *order)
{
    if (b->opt.threads <= 1) {
        for (uint32_t i = 0; i < b->joint_count; i++)
            order[i] = i;
        return true;
    }
    merp_ranked *c = merp_malloc((b->joint_count ? b->joint_count : 1) * sizeof *c);
    if (c == NULL)
        return false;
    for (uint32_t i = 0; i < b->joint_count; i++)
        c[i] = (merp_ranked){patch_cost(b, &b->joints[i]), i};
    qsort(c, b->joint_count, sizeof *c, merp_ranked_cmp);
    for (uint32_t i = 0; i < b->joint_count; i++)
        order[i] = c[i].id;
    merp_free(c);
    return true;
}

/* Every patch, on opt.threads threads: patches are pure functions of their
 * joint and each lands in its joint's own arrays, so the bytes are the same
 * whatever the thread count and the order they are taken and finish in;
 * failures are then handled in joint order (*failed: how many joints failed,
 * their forks tubes again). */
static mer_result build_patches(merp_builder *b, uint32_t *failed, mer_error *err)
{
    *failed = 0;
    size_t n = b->joint_count ? b->joint_count : 1;
    patch_run r = {b, merp_malloc(n * sizeof *r.rc), merp_malloc(n * sizeof *r.order)};
    if (r.rc == NULL || r.order == NULL || !patch_order(b, r.order)) {
        merp_free(r.rc), merp_free(r.order);
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the junctions");
    }
    merp_parallel_for(b->joint_count, b->opt.threads, patch_item, &r);
    mer_result rc = MER_OK;
    for (uint32_t i = 0; i < b->joint_count && rc == MER_OK; i++) {
        if (r.rc[i] == MER_ERR_INVALID) {
            merp_joint_forget(b, &b->joints[i]); /* this fork (or run) stays tubes */
            b->joints_open += merp_joint_forks(&b->joints[i]);
            ++*failed;
        } else if (r.rc[i] != MER_OK) {
            rc = mer_error_set(err, r.rc[i], NULL, "out of memory for a junction");
        }
    }
    merp_free(r.rc), merp_free(r.order);
    return rc;
}

mer_result merp_mesh_joints(merp_builder *b, mer_error *err)
{
    mer_result rc = merp_mesh_joints_plan(b, err);
    if (rc == MER_OK)
        rc = walk_axes(b, true, err);
    uint32_t failed = 0;
    if (rc == MER_OK)
        rc = build_patches(b, &failed, err);
    /* Counted again only where a patch failed and its forks are tubes again:
     * the counts depend on the cuts alone, which are otherwise as they were. */
    if (rc == MER_OK && failed > 0)
        rc = walk_axes(b, false, err);
    return rc;
}

void merp_mesh_joints_size(const merp_builder *b, uint64_t *vertices, uint64_t *indices)
{
    *vertices = *indices = 0;
    for (uint32_t i = 0; i < b->joint_count; i++)
        if (b->joints[i].ok) {
            *vertices += b->joints[i].mesh.vertex_count;
            *indices += 3 * (uint64_t)b->joints[i].mesh.triangle_count;
        }
}

#define RIDGE_DARKEN 0.55f /* a colour on the ridge (b = 1) keeps this much of itself */

/* The patches' vertices and triangles into the bark, array by array: the
 * positions, normals, UVs and ridge values as one copy each, the triangles
 * offset to the patch's place in its chunk. */
mer_result merp_mesh_joints_write(merp_builder *b, mer_error *err)
{
    merp_cursor *c = &b->bark;
    for (uint32_t i = 0; i < b->joint_count; i++) {
        const merp_joint *jt = &b->joints[i];
        if (!jt->ok)
            continue;
        const merp_trimesh *m = &jt->mesh;
        const size_t n = m->vertex_count;
        mer_result rc = merp_mesh_begin_group(c, m->vertex_count, err);
        if (rc != MER_OK)
            return rc;
        mer_mesh_part *part = c->part;
        const uint32_t first = merp_take_vertices(c, m->vertex_count);
        memcpy(part->positions + 3 * (size_t)first, m->positions, 3 * n * sizeof(float));
        memcpy(part->normals + 3 * (size_t)first, m->normals, 3 * n * sizeof(float));
        if (part->uvs != NULL)
            memcpy(part->uvs + 2 * (size_t)first, jt->uvs, 2 * n * sizeof(float));
        memcpy(part->ridge + first, jt->ridge, n * sizeof(float));
        for (uint32_t v = 0; v < m->vertex_count; v++)
            part->node_ids[first + v] = b->nodes[jt->start[jt->shaft[v]]].id;
        if (part->colors != NULL)
            for (uint32_t v = 0; v < m->vertex_count; v++) {
                merp_mesh_color(b, part, first + v, 1, &b->nodes[jt->start[jt->shaft[v]]]);
                for (int k = 0; k < 3; k++)
                    part->colors[4 * (size_t)(first + v) + k] *= 1.0f - (1.0f - RIDGE_DARKEN) * jt->ridge[v];
            }
        const uint32_t count = 3 * m->triangle_count;
        uint32_t base, *out = merp_take_indices(c, count, &base);
        for (uint32_t k = 0; k < count; k++)
            out[k] = m->triangles[k] + (first - base);
    }
    return MER_OK;
}

void merp_mesh_joints_free(merp_builder *b)
{
    for (uint32_t i = 0; i < b->joint_count; i++)
        free_patch(&b->joints[i]);
    merp_free(b->joints);
    merp_free(b->joint_at);
    merp_free(b->lateral_in);
    merp_free(b->cut_end);
    merp_free(b->cut_begin);
}
