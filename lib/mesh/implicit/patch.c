/* meristem — a junction's local patch: the junction field polygonized
 * between cut planes, and its boundary loops stitched to the shafts' rings
 * (implicit.h; issue 18, item 2). */
#include "config.h"

#include <assert.h>
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "core/vec.h"
#include "mesh/implicit/implicit.h"

typedef struct clipped {
    const merp_patch *pt;
    float kappa;    /* the slope of each cut's half-space field, per unit length */
    merp_jprep jp;  /* pt->j, prepared once for the patch's samples */
    float slack[MERP_PATCH_CUTS]; /* cut_slack: for beyond_a_cut */
} clipped;

static float cut_distance(const merp_cut *c, const float p[3])
{
    return (p[0] - c->o[0]) * c->n[0] + (p[1] - c->o[1]) * c->n[1] + (p[2] - c->o[2]) * c->n[2];
}

/* Whether p is within the cut's reach of its axis and its depth beyond the
 * plane; *dist gets its signed distance to the plane. */
static bool in_reach(const merp_cut *c, const float p[3], float *dist)
{
    float q[3];
    *dist = cut_distance(c, p);
    for (int k = 0; k < 3; k++)
        q[k] = p[k] - c->o[k] - *dist * c->n[k];
    return v3_dot(q, q) <= c->reach * c->reach && *dist <= c->depth;
}

/* F_g ∩ the cuts' half-spaces: min(F_g, c − κ·dist_i). */
static float clipped_field(const float p[3], const void *data)
{
    const clipped *cl = data;
    float f = merp_jprep_field(&cl->jp, p);
    for (uint32_t i = 0; i < cl->pt->cuts; i++) {
        /* The plane first: the reach only matters where the cut would win. */
        float g = MERP_ISO - cl->kappa * cut_distance(&cl->pt->cut[i], p), dist;
        if (g < f && in_reach(&cl->pt->cut[i], p, &dist))
            f = g;
    }
    return f;
}

/* ∇ of clipped_field: ∇F_g in closed form, or −κ·n where cut i's term is
 * the smaller (as clipped_field picks it). */
static float clipped_gradient(const float p[3], const void *data, float g[3])
{
    const clipped *cl = data;
    float f = merp_jprep_gradient(&cl->jp, p, g);
    for (uint32_t i = 0; i < cl->pt->cuts; i++) {
        const merp_cut *c = &cl->pt->cut[i];
        float t = MERP_ISO - cl->kappa * cut_distance(c, p), dist;
        if (t < f && in_reach(c, p, &dist)) {
            f = t;
            for (int k = 0; k < 3; k++)
                g[k] = -cl->kappa * c->n[k];
        }
    }
    return f;
}

/* The polygonizer's room: its bound, capped (merp_patch_bound). */
static void polygonizer_room(const merp_patch *pt, uint64_t *vertices, uint64_t *triangles)
{
    if (pt->sharp)
        merp_dc_bound(&pt->grid, vertices, triangles);
    else
        merp_mtet_bound(&pt->grid, vertices, triangles);
    if (*vertices > MERP_PATCH_ROOM_VERTICES)
        *vertices = MERP_PATCH_ROOM_VERTICES;
    if (*triangles > 2 * (uint64_t)MERP_PATCH_ROOM_VERTICES)
        *triangles = 2 * (uint64_t)MERP_PATCH_ROOM_VERTICES;
}

/* merp_patch_bound from the polygonizer's room: each cut's ring and stitch added. */
static void add_stitches(const merp_patch *pt, uint64_t *vertices, uint64_t *triangles)
{
    for (uint32_t i = 0; i < pt->cuts; i++) {
        *vertices += pt->cut[i].sides;
        /* A stitch is a triangle per loop vertex and per ring vertex; the
         * loop's vertices are among the polygonizer's. */
        *triangles += pt->cut[i].sides;
    }
    *triangles += *vertices;
}

void merp_patch_bound(const merp_patch *pt, uint64_t *vertices, uint64_t *triangles)
{
    polygonizer_room(pt, vertices, triangles);
    add_stitches(pt, vertices, triangles);
}

typedef struct edge {
    uint32_t a, b;
} edge;

static int edge_cmp(const void *x, const void *y)
{
    const edge *p = x, *q = y;
    if (p->a != q->a)
        return p->a < q->a ? -1 : 1;
    return p->b < q->b ? -1 : p->b > q->b;
}

/* Drops the triangles of the clip's flat caps: all three corners on one cut. */
static void drop_caps(merp_trimesh *m, const int16_t *on_cut)
{
    uint32_t kept = 0;
    for (uint32_t t = 0; t < m->triangle_count; t++) {
        const uint32_t *v = m->triangles + 3 * (size_t)t;
        if (on_cut[v[0]] >= 0 && on_cut[v[0]] == on_cut[v[1]] && on_cut[v[0]] == on_cut[v[2]])
            continue;
        uint32_t *to = m->triangles + 3 * (size_t)kept++; /* to ≤ v: element by element, no libc call */
        to[0] = v[0], to[1] = v[1], to[2] = v[2];
    }
    m->triangle_count = kept;
}

/* next[a] = b for every directed edge a→b whose reverse no triangle has (a
 * boundary edge); UINT32_MAX elsewhere. MER_ERR_INVALID when a vertex starts
 * two boundary edges (the loops are not simple). Only edges with both ends
 * on a cut are looked at: the polygonizer's mesh is closed, so the open
 * edges are those the dropped caps had, all in the cut planes. */
static mer_result boundary_next(const merp_trimesh *m, const int16_t *on_cut, uint32_t *next, mer_error *err)
{
    size_t n = 0;
    edge *e = merp_malloc(((size_t)m->triangle_count * 3 + 1) * sizeof *e);
    if (e == NULL)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory stitching a junction");
    for (size_t t = 0; t < m->triangle_count; t++)
        for (int k = 0; k < 3; k++) {
            uint32_t a = m->triangles[3 * t + k], b = m->triangles[3 * t + (k + 1) % 3];
            if (on_cut[a] >= 0 && on_cut[b] >= 0)
                e[n++] = (edge){a, b};
        }
    qsort(e, n, sizeof *e, edge_cmp);
    for (uint32_t v = 0; v < m->vertex_count; v++)
        next[v] = UINT32_MAX;
    mer_result rc = MER_OK;
    for (size_t i = 0; i < n && rc == MER_OK; i++) {
        edge r = {e[i].b, e[i].a};
        if (bsearch(&r, e, n, sizeof *e, edge_cmp) != NULL)
            continue;
        if (next[e[i].a] != UINT32_MAX)
            rc = mer_error_set(err, MER_ERR_INVALID, NULL, "a junction patch's boundary is not simple");
        next[e[i].a] = e[i].b;
    }
    merp_free(e);
    return rc;
}

/* The angle of p about the cut's normal, in the frame (u, v). */
static float angle_about(const merp_cut *c, const float u[3], const float v[3], const float p[3])
{
    float d[3] = {p[0] - c->o[0], p[1] - c->o[1], p[2] - c->o[2]};
    return atan2f(v3_dot(d, v), v3_dot(d, u));
}

static float wrap_2pi(float a)
{
    while (a < 0.0f)
        a += MERP_TWO_PI;
    while (a >= MERP_TWO_PI)
        a -= MERP_TWO_PI;
    return a;
}

/* Moves each vertex of the loop L, in its cut's plane, along its ray from
 * the cut's centre onto the ring's polygon (the edge between the two ring
 * vertices whose angles φ, sorted by `order`, bracket its own angle α, both
 * measured as stitch measures them). The
 * polygonizer leaves a loop vertex about a cell off the surface, at worst a
 * cell's diagonal (a cell the cap crosses with no crossing of the tube in
 * it puts its vertex inside),
 * and the flat band zipped between loop and ring would show that as a ledge
 * round the shaft; seated on the ring's edges the band folds flat to
 * nothing and the shaft runs into the patch without a step. The surface at
 * a cut is the plain tube (the plan places cuts so), whose section the ring
 * is, so this moves a vertex by the polygonizer's error and the polygon's
 * sag, never across the shaft. Angles are unchanged, so the zip's order
 * stays. Each vertex stops SEAT_INSET of its distance short of the edge: a
 * loop vertex at a ring vertex's angle (the grid and the ring often share
 * a diagonal) would otherwise take that vertex's very position, which the
 * closure check, welding bit-equal positions, reads as one vertex. */
#define SEAT_INSET 1e-3f

/* The distance from the cut's centre to the ring's polygon along the unit
 * direction (x, y) in the frame (u, v), whose angle as stitch measures it is
 * a (the ring's angles φ sorted by `order`); 0 where the ray meets no edge
 * ahead (a ring that is no convex polygon about o). */
static float ring_polygon_at(const merp_cut *c, const float u[3], const float v[3], float x, float y, float a,
                             const float *phi, const uint32_t *order)
{
    uint32_t s = c->sides, k = 0; /* the last ring vertex at or before a, cyclically */
    while (k + 1 < s && phi[order[k + 1]] <= a)
        k++;
    if (phi[order[0]] > a)
        k = s - 1;
    const float *pa = c->ring + 3 * (size_t)order[k], *pb = c->ring + 3 * (size_t)order[(k + 1) % s];
    float da[3] = {pa[0] - c->o[0], pa[1] - c->o[1], pa[2] - c->o[2]};
    float db[3] = {pb[0] - c->o[0], pb[1] - c->o[1], pb[2] - c->o[2]};
    float ax = v3_dot(da, u), ay = v3_dot(da, v), ex = v3_dot(db, u) - ax, ey = v3_dot(db, v) - ay;
    /* The ray t·(x, y) meets a + σ·e where t = (a × e) / ((x, y) × e). */
    float den = x * ey - y * ex, t = (ax * ey - ay * ex) / den;
    return den != 0.0f && t > 0.0f ? t : 0.0f;
}

static void seat_loop(merp_trimesh *m, const merp_cut *c, const float u[3], const float v[3],
                      const uint32_t *L, uint32_t m_len, const float *alpha, const float *phi,
                      const uint32_t *order)
{
    for (uint32_t i = 0; i < m_len; i++) {
        float *p = m->positions + 3 * (size_t)L[i];
        float d[3] = {p[0] - c->o[0], p[1] - c->o[1], p[2] - c->o[2]};
        float x = v3_dot(d, u), y = v3_dot(d, v), len = sqrtf(x * x + y * y);
        if (!(len > 0.0f))
            continue; /* on the axis: no direction to seat it along */
        x /= len, y /= len;
        float t = ring_polygon_at(c, u, v, x, y, alpha[i], phi, order);
        if (!(t > 0.0f))
            continue;
        t *= 1.0f - SEAT_INSET;
        for (int q = 0; q < 3; q++)
            p[q] = c->o[q] + t * (x * u[q] + y * v[q]);
    }
}

/* The band of shaft before a cut, TAPER_BAND × the ring's radius long: the
 * patch's surface there is round (the field's capsule), the tube's beyond
 * the cut a prism on the ring's polygon, whose sides lie up to 1 − cos(π /
 * sides) of the radius inside the circle (13 % at six sides, 3 % at twelve).
 * Seated on the polygon, the loop meets the prism, but the round surface a
 * cell before it stood out from it by that much: a shoulder round the shaft
 * at every cut, plain in the page's close-up at detail 2. */
#define TAPER_BAND 0.5f

/* Moves the patch's vertices in cut c's band (the first `vertices`, but
 * those on a cut: the loops, seated already, and the caps, dropped) towards
 * the ring's polygon, each about the cut's axis along its own ray, by the
 * weight w = 1 − smoothstep of its distance from the plane over the band:
 * the outline goes from the polygon's at the cut to the round one at the
 * band's end with no step and no kink (w and its slope are continuous at
 * both ends). Only vertices within the cut's reach of its axis move: the
 * plan keeps the other primitives' supports off the cut's disk, so what
 * moves is this shaft's surface (half a radius in, at most the foot of a
 * blend, by a few per cent of the radius). `a0`, `sgn`: stitch's angle
 * measure. */
static void taper_band(merp_trimesh *m, const merp_cut *c, const float u[3], const float v[3], float a0, float sgn,
                       const float *phi, const uint32_t *order, const int16_t *on_cut, uint32_t vertices)
{
    float r = 0.0f; /* the ring's radius: the largest of its vertices' */
    for (uint32_t j = 0; j < c->sides; j++) {
        const float *q = c->ring + 3 * (size_t)j;
        float d[3] = {q[0] - c->o[0], q[1] - c->o[1], q[2] - c->o[2]};
        r = fmaxf(r, v3_len(d));
    }
    const float band = TAPER_BAND * r;
    if (!(band > 0.0f))
        return;
    for (uint32_t i = 0; i < vertices; i++) {
        if (on_cut[i] >= 0)
            continue;
        float *p = m->positions + 3 * (size_t)i, before = -cut_distance(c, p);
        if (!(before > 0.0f && before < band))
            continue;
        float d[3] = {p[0] - c->o[0], p[1] - c->o[1], p[2] - c->o[2]};
        float x = v3_dot(d, u), y = v3_dot(d, v), len = sqrtf(x * x + y * y);
        if (!(len > 0.0f && len <= c->reach))
            continue;
        x /= len, y /= len;
        float rho = ring_polygon_at(c, u, v, x, y, wrap_2pi(sgn * (angle_about(c, u, v, p) - a0)), phi, order);
        if (!(rho > 0.0f && rho < r))
            continue;
        float f = before / band, w = 1.0f - f * f * (3.0f - 2.0f * f), move = len * w * (1.0f - rho / r);
        for (int q = 0; q < 3; q++)
            p[q] -= move * (x * u[q] + y * v[q]);
    }
}

/* Appends cut c's ring to m (normals radial) and zips the loop L (m_len
 * vertices in the patch's direction) to it by angle about n: a triangle
 * (L_{i+1}, L_i, R_j) when the loop's next vertex comes first, (R_j, R_{j+1},
 * L_i) when the ring's does, so the band runs each loop edge backwards. */
static mer_result stitch(merp_trimesh *m, const merp_cut *c, const uint32_t *L, uint32_t m_len,
                         const int16_t *on_cut, uint32_t vertices, float *scratch, uint32_t *order, mer_error *err)
{
    float u[3], v[3];
    v3_any_perp(c->n, u);
    v3_cross(c->n, u, v);
    /* θ: the loop's angles for the zip; φ: the ring's; α: the loop's as
     * measured, before θ is smoothed (seat_loop's rays). */
    float *theta = scratch, *phi = scratch + m_len + 1, *alpha = phi + c->sides;
    float turn = 0.0f, a0 = angle_about(c, u, v, m->positions + 3 * (size_t)L[0]), prev = a0;
    for (uint32_t i = 1; i <= m_len; i++) {
        float a = angle_about(c, u, v, m->positions + 3 * (size_t)L[i % m_len]);
        float d = wrap_2pi(a - prev + MERP_TWO_PI * 0.5f) - MERP_TWO_PI * 0.5f;
        turn += d, prev = a;
    }
    if (fabsf(fabsf(turn) - MERP_TWO_PI) > 0.5f)
        return mer_error_set(err, MER_ERR_INVALID, NULL, "a junction's loop does not go round its cut");
    float sgn = turn > 0.0f ? 1.0f : -1.0f;
    for (uint32_t i = 0; i < m_len; i++)
        alpha[i] = wrap_2pi(sgn * (angle_about(c, u, v, m->positions + 3 * (size_t)L[i]) - a0));
    for (uint32_t i = 0; i <= m_len; i++) /* unwrapped, increasing, θ_0 = 0, θ_m = 2π */
        theta[i] = i == m_len ? MERP_TWO_PI : alpha[i];
    /* A loop that wiggles about its start: a vertex just before L_0 (the
     * loop's second, θ near 2π) or one just past it at the end (θ near 0)
     * takes the angle of the vertex before it. Left near 2π, the second
     * would zip the whole ring to L_0 and the rest of the loop to the
     * ring's last vertex: that spoke twice, an edge of two triangles
     * either way. */
    for (uint32_t i = 1; i < m_len; i++)
        if (theta[i] > theta[i - 1] + MERP_TWO_PI * 0.5f || theta[i] < theta[i - 1] - 1.0f)
            theta[i] = theta[i - 1];
    uint32_t base = m->vertex_count;
    for (uint32_t j = 0; j < c->sides; j++) {
        const float *p = c->ring + 3 * (size_t)j;
        memcpy(m->positions + 3 * (size_t)(base + j), p, 3 * sizeof(float));
        float *nr = m->normals != NULL ? m->normals + 3 * (size_t)(base + j) : NULL;
        for (int k = 0; nr != NULL && k < 3; k++)
            nr[k] = p[k] - c->o[k];
        if (nr != NULL)
            v3_normalize(nr);
        phi[j] = wrap_2pi(sgn * (angle_about(c, u, v, p) - a0));
        order[j] = j;
    }
    m->vertex_count += c->sides;
    for (uint32_t j = 1; j < c->sides; j++) /* insertion sort by φ: rings are small */
        for (uint32_t k = j; k > 0 && phi[order[k]] < phi[order[k - 1]]; k--) {
            uint32_t t = order[k];
            order[k] = order[k - 1], order[k - 1] = t;
        }
    seat_loop(m, c, u, v, L, m_len, alpha, phi, order);
    taper_band(m, c, u, v, a0, sgn, phi, order, on_cut, vertices);
    uint32_t i = 0, j = 0, s = c->sides;
    while (i < m_len || j < s) {
        float next_ring = j + 1 < s ? phi[order[j + 1]] : phi[order[0]] + MERP_TWO_PI;
        uint32_t *t = m->triangles + 3 * (size_t)m->triangle_count++;
        if (j == s || (i < m_len && theta[i + 1] <= next_ring)) {
            t[0] = L[(i + 1) % m_len], t[1] = L[i], t[2] = base + order[j % s];
            i++;
        } else {
            t[0] = base + order[j], t[1] = base + order[(j + 1) % s], t[2] = L[i % m_len];
            j++;
        }
    }
    return MER_OK;
}

/* Removes the vertices no triangle uses (the caps' insides), keeping order. */
static void compact(merp_trimesh *m, uint32_t *remap)
{
    for (uint32_t v = 0; v < m->vertex_count; v++)
        remap[v] = UINT32_MAX;
    for (size_t k = 0; k < 3 * (size_t)m->triangle_count; k++)
        remap[m->triangles[k]] = 0;
    uint32_t n = 0;
    for (uint32_t v = 0; v < m->vertex_count; v++) {
        if (remap[v] == UINT32_MAX)
            continue;
        for (int k = 0; k < 3; k++) /* n ≤ v: element by element, no libc call */
            m->positions[3 * (size_t)n + k] = m->positions[3 * (size_t)v + k];
        for (int k = 0; m->normals != NULL && k < 3; k++)
            m->normals[3 * (size_t)n + k] = m->normals[3 * (size_t)v + k];
        remap[v] = n++;
    }
    for (size_t k = 0; k < 3 * (size_t)m->triangle_count; k++)
        m->triangles[k] = remap[m->triangles[k]];
    m->vertex_count = n;
}

/* Walks cut i's one boundary loop into L (its length in *len), marking its
 * vertices used (next[] set to UINT32_MAX − 1). Only the polygonizer's
 * first `vertices` have next[] and on_cut[]: the ring copies appended
 * after them by the cuts stitched so far have neither. */
static mer_result take_loop(const int16_t *on_cut, uint32_t *next, uint32_t vertices, uint32_t i, uint32_t *L,
                            uint32_t *len, mer_error *err)
{
    uint32_t start = UINT32_MAX;
    for (uint32_t v = 0; v < vertices && start == UINT32_MAX; v++)
        if (next[v] < UINT32_MAX - 1 && on_cut[v] == (int16_t)i)
            start = v;
    if (start == UINT32_MAX)
        return mer_error_set(err, MER_ERR_INVALID, NULL, "a junction's cut %u has no loop", i);
    uint32_t n = 0, v = start;
    do {
        if (next[v] >= UINT32_MAX - 1 || on_cut[v] != (int16_t)i || n == vertices)
            return mer_error_set(err, MER_ERR_INVALID, NULL, "a junction's loop at cut %u is broken", i);
        L[n++] = v;
        uint32_t w = next[v];
        next[v] = UINT32_MAX - 1;
        v = w;
    } while (v != start);
    *len = n;
    return MER_OK;
}

/* Marks each vertex of marching tetrahedra's mesh with the cut whose cap it
 * lies on, -1 for none, and moves it onto that cut's plane. A vertex is on a
 * cap where that cut's term is what the clipped field takes there (at most
 * F_g, the smallest of the cuts' in reach), as cap_of_sheet decides for dual
 * contouring: a crossing solved on a grid edge from inside the solid to
 * beyond a cut lies on the plane only to the solver's tolerance where F_g
 * takes over along the edge (near the rim), and a test by distance to the
 * plane alone left such cap vertices on the side, their cap triangles kept:
 * loops that pinch or miss their cut. */
static void mark_cuts(merp_trimesh *m, const clipped *cl, int16_t *on_cut)
{
    const merp_patch *pt = cl->pt;
    for (uint32_t v = 0; v < m->vertex_count; v++) {
        float *p = m->positions + 3 * (size_t)v, clip = INFINITY;
        int by = -1;
        for (uint32_t i = 0; i < pt->cuts; i++) {
            /* Within a cell's hundredth of the plane: the solver's
             * tolerance is far below it, a cell's width far above. */
            float dist;
            if (in_reach(&pt->cut[i], p, &dist) && fabsf(dist) * cl->kappa < 0.01f &&
                MERP_ISO - cl->kappa * dist < clip)
                clip = MERP_ISO - cl->kappa * dist, by = (int)i;
        }
        if (by >= 0 && !(clip <= merp_jprep_field(&cl->jp, p)))
            by = -1; /* F_g is the smaller: the side's, near the rim */
        on_cut[v] = (int16_t)by;
        if (by < 0)
            continue;
        const merp_cut *c = &pt->cut[by];
        float dist = cut_distance(c, p);
        for (int k = 0; k < 3; k++)
            p[k] -= dist * c->n[k];
    }
}

/* Whether a corner of cell ijk may lie beyond a cut (dist > 0, below): the
 * lowest corner's distance plus each cut's slack (clipped.slack), so that a
 * cell it rules out has no corner cap_of_sheet would find beyond. Most
 * sheets lie on the junction's side of every cut, and then their eight
 * corners need no distances. */
static bool beyond_a_cut(const clipped *cl, const uint32_t ijk[3])
{
    const merp_grid *g = &cl->pt->grid;
    float p[3];
    merp_grid_point(g, ijk[0], ijk[1], ijk[2], p);
    for (uint32_t i = 0; i < cl->pt->cuts; i++)
        if (cut_distance(&cl->pt->cut[i], p) > -cl->slack[i])
            return true;
    return false;
}

/* Cut i's slack: how much further than a cell's lowest corner any of its
 * corners can lie along n (h·Σ max(n_k, 0) on a regular grid; on a graded
 * one, whose cells lean, Σ |n_k| × its reach), plus a margin far above the
 * rounding of the distances in the grid's span (1e-4 of the coordinates'
 * magnitude; float rounding is ~1e-7 of it). */
static void cut_slack(clipped *cl)
{
    const merp_grid *g = &cl->pt->grid;
    float size = g->h, far[3]; /* far: the grid's far corner */
    merp_grid_point(g, g->n[0], g->n[1], g->n[2], far);
    for (int a = 0; a < 3; a++) {
        float lo = fabsf(g->origin[a]), hi = fabsf(far[a]);
        if (g->warp != NULL) /* a graded grid's levels spread about its center */
            lo = hi = fabsf(g->warp->center[a]) + (float)g->n[a] * merp_grid_reach(g, a) + fmaxf(lo, hi);
        size += lo > hi ? lo : hi;
    }
    for (uint32_t i = 0; i < cl->pt->cuts; i++) {
        const merp_cut *c = &cl->pt->cut[i];
        float up = 0.0f, scale = size;
        for (int a = 0; a < 3; a++) {
            float n = g->warp != NULL ? fabsf(c->n[a]) : c->n[a] > 0.0f ? c->n[a] : 0.0f;
            up += n * merp_grid_reach(g, a), scale += fabsf(c->o[a]);
        }
        cl->slack[i] = up + 1e-4f * scale;
    }
}

/* The cut whose cap a sheet of dual contouring lies on: one of the corners
 * of its crossed edges is outside the clipped solid only because it lies
 * beyond that cut (F_g ≥ c there). Its other corners are those edges' inside
 * ends, so only a corner beyond a cut (where the cut is the smaller term)
 * needs F_g. -1 for none. */
static int cap_of_sheet(const clipped *cl, merp_dc_source src)
{
    const merp_grid *g = &cl->pt->grid;
    const uint32_t *ijk = src.cell;
    if (!beyond_a_cut(cl, ijk))
        return -1;
    int cap = -1;
    for (uint8_t k = 0; k < 8; k++) {
        if (!(src.corners >> k & 1))
            continue;
        float p[3];
        merp_grid_point(g, ijk[0] + (k & 1), ijk[1] + (k >> 1 & 1), ijk[2] + (k >> 2 & 1), p);
        float clip = INFINITY;
        int by = -1;
        for (uint32_t i = 0; i < cl->pt->cuts; i++) {
            /* On the junction's side of its plane a cut's term is at least
             * c, so it clips nothing: the plane first, the reach after. */
            float dist = cut_distance(&cl->pt->cut[i], p);
            if (dist > 0.0f && in_reach(&cl->pt->cut[i], p, &dist) && MERP_ISO - cl->kappa * dist < clip)
                clip = MERP_ISO - cl->kappa * dist, by = (int)i;
        }
        if (clip >= MERP_ISO)
            continue; /* no cut clips it: inside or outside by F_g alone */
        float f = merp_jprep_field(&cl->jp, p);
        if (clip < f && f >= MERP_ISO)
            cap = by;
    }
    return cap;
}

/* Moves the vertex of each sheet on a cap onto that cap's plane and marks
 * it with its cut (-1 for the others). */
static void snap_cuts(merp_trimesh *m, const clipped *cl, const merp_dc_source *src, int16_t *on_cut)
{
    for (uint32_t v = 0; v < m->vertex_count; v++) {
        int i = cap_of_sheet(cl, src[v]);
        on_cut[v] = (int16_t)i;
        if (i < 0)
            continue;
        const merp_cut *c = &cl->pt->cut[i];
        float *p = m->positions + 3 * (size_t)v, dist = cut_distance(c, p);
        for (int k = 0; k < 3; k++)
            p[k] -= dist * c->n[k];
    }
}

/* Drops the caps marked in on_cut and zips each cut's loop to its ring; a
 * cut with no ring keeps its cap (its vertices unmarked). */
static mer_result stitch_all(merp_trimesh *m, const merp_patch *pt, int16_t *on_cut, mer_error *err)
{
    for (uint32_t v = 0; v < m->vertex_count; v++)
        if (on_cut[v] >= 0 && pt->cut[on_cut[v]].sides == 0)
            on_cut[v] = -1;
    size_t all = m->vertex_count + 2;
    for (uint32_t i = 0; i < pt->cuts; i++)
        all += pt->cut[i].sides;
    uint32_t *next = merp_malloc(all * sizeof *next), *L = merp_malloc(all * sizeof *L);
    uint32_t *order = merp_malloc(all * sizeof *order);
    float *scratch = merp_malloc(2 * all * sizeof *scratch);
    mer_result rc = MER_OK;
    if (next == NULL || L == NULL || order == NULL || scratch == NULL)
        rc = mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory stitching a junction");
    if (rc == MER_OK) {
        drop_caps(m, on_cut);
        rc = boundary_next(m, on_cut, next, err);
    }
    uint32_t vertices = m->vertex_count;
    for (uint32_t i = 0; i < pt->cuts && rc == MER_OK; i++) {
        uint32_t len = 0;
        if (pt->cut[i].sides == 0)
            continue;
        rc = take_loop(on_cut, next, vertices, i, L, &len, err);
        if (rc == MER_OK)
            rc = stitch(m, &pt->cut[i], L, len, on_cut, vertices, scratch, order, err);
    }
    for (uint32_t v = 0; v < vertices && rc == MER_OK; v++)
        if (next[v] < UINT32_MAX - 1)
            rc = mer_error_set(err, MER_ERR_INVALID, NULL, "a junction patch has a loop on no cut");
    if (rc == MER_OK)
        compact(m, next);
    merp_free(next), merp_free(L), merp_free(order), merp_free(scratch);
    return rc;
}

mer_result merp_patch_build(const merp_patch *pt, merp_trimesh *out, mer_error *err)
{
    assert(pt->cuts >= 1 && pt->cuts <= MERP_PATCH_CUTS);
    for (uint32_t i = 0; i < pt->cuts; i++)
        assert(pt->cut[i].depth > 0.0f);
    clipped cl = {.pt = pt, .kappa = 1.0f / pt->grid.h};
    merp_jprep_init_run(&cl.jp, pt->j, pt->link, pt->forks ? pt->forks : 1);
    cut_slack(&cl);
    /* Seeds inside the solid: the junction point and each shaft halfway to
     * its cut; the clipped surface is one piece, so the walk finds it all. */
    float seeds[1 + MERP_PATCH_CUTS][3];
    const float *J = pt->j->in.b;
    for (uint32_t i = 0; i <= pt->cuts; i++)
        for (int k = 0; k < 3; k++)
            seeds[i][k] = i == 0 ? J[k] : 0.5f * (J[k] + pt->cut[i - 1].o[k]);
    uint64_t vmax, tmax;
    polygonizer_room(pt, &vmax, &tmax);
    out->vertex_room = (uint32_t)vmax, out->triangle_room = (uint32_t)tmax;
    add_stitches(pt, &vmax, &tmax);
    /* Each vertex's cut, -1 for none: a run's cuts pass a byte's 127. */
    _Static_assert(MERP_PATCH_CUTS <= INT16_MAX, "on_cut holds a cut's index");
    int16_t *on_cut = merp_malloc((size_t)vmax * sizeof *on_cut);
    merp_dc_source *cells = pt->sharp ? merp_malloc((size_t)vmax * sizeof *cells) : NULL;
    if (on_cut == NULL || (pt->sharp && cells == NULL)) {
        merp_free(on_cut), merp_free(cells);
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory stitching a junction");
    }
    const float(*s)[3] = (const float(*)[3])seeds;
    uint32_t nseeds = 1 + pt->cuts;
    mer_result rc =
        pt->sharp
            ? merp_dc_polygonize(&pt->grid, clipped_field, clipped_gradient, &cl, s, nseeds, out, cells, err)
            : merp_mtet_polygonize_seeded(&pt->grid, clipped_field, &cl, s, nseeds, out, err);
    if (rc == MER_OK) {
        if (pt->sharp)
            snap_cuts(out, &cl, cells, on_cut);
        else
            mark_cuts(out, &cl, on_cut);
        rc = stitch_all(out, pt, on_cut, err);
    }
    merp_free(on_cut), merp_free(cells);
    return rc;
}
