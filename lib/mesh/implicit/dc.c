/* meristem — dual contouring (Ju, Losasso, Schaefer & Warren 2002) over a
 * grid, regular or graded (implicit.h): a vertex per sheet of surface in
 * each crossed cell, placed by the quadratic error function of the sheet's
 * edge crossings and normals (Hermite data), so that a crease through the
 * cell (the branch bark ridge) keeps its vertex on it; one quad per crossed
 * edge. */
#include "config.h"

#include <assert.h>
#include <math.h>
#include <string.h>

#include "core/alloc.h"
#include "core/vec.h"
#include "mesh/implicit/implicit.h"
#include "mesh/implicit/walk.h"

/* The QEF's pull towards the crossings' mass point, relative to one plane's
 * weight: small, so it only decides the directions no plane constrains (along
 * a crease, across a flat face). */
#define QEF_LAMBDA 0.02f

/* The two cube corners of each of a cell's 12 edges (bits x = 1, y = 2,
 * z = 4): edges 0–3 along x, 4–7 along y, 8–11 along z (edge e's axis is
 * e / 4). */
static const uint8_t cube_edge[12][2] = {
    {0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3}, {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7},
};

void merp_dc_bound(const merp_grid *g, uint64_t *vertices, uint64_t *triangles)
{
    uint64_t samples = (uint64_t)(g->n[0] + 1) * (g->n[1] + 1) * (g->n[2] + 1);
    *vertices = (uint64_t)MERP_DC_SHEETS * g->n[0] * g->n[1] * g->n[2];
    *triangles = samples * 3 * 2;
}

typedef struct qef {
    float ata[6]; /* AᵀA: xx, xy, xz, yy, yz, zz */
    float atb[3];
    float mass[3];
    int count;
} qef;

static void qef_add(qef *q, const float p[3], const float n[3])
{
    float d = v3_dot(n, p);
    q->ata[0] += n[0] * n[0], q->ata[1] += n[0] * n[1], q->ata[2] += n[0] * n[2];
    q->ata[3] += n[1] * n[1], q->ata[4] += n[1] * n[2], q->ata[5] += n[2] * n[2];
    for (int k = 0; k < 3; k++) {
        q->atb[k] += n[k] * d;
        q->mass[k] += p[k];
    }
    q->count++;
}

/* argmin Σ (n·x − n·p)² + λ|x − m|² (m the mass point): (AᵀA + λI) y =
 * Aᵀb − AᵀA m with x = m + y, by Cramer's rule (the matrix is positive
 * definite). */
static void qef_solve(const qef *q, float x[3])
{
    float m[3] = {q->mass[0] / (float)q->count, q->mass[1] / (float)q->count, q->mass[2] / (float)q->count};
    float l = QEF_LAMBDA * (float)q->count;
    float a = q->ata[0] + l, b = q->ata[1], c = q->ata[2];
    float d = q->ata[3] + l, e = q->ata[4], f = q->ata[5] + l;
    float r[3] = {q->atb[0] - (q->ata[0] * m[0] + b * m[1] + c * m[2]),
                  q->atb[1] - (b * m[0] + q->ata[3] * m[1] + e * m[2]),
                  q->atb[2] - (c * m[0] + e * m[1] + q->ata[5] * m[2])};
    float c00 = d * f - e * e, c01 = c * e - b * f, c02 = b * e - c * d;
    float det = a * c00 + b * c01 + c * c02;
    float c11 = a * f - c * c, c12 = b * c - a * e, c22 = a * d - b * b;
    x[0] = m[0] + (c00 * r[0] + c01 * r[1] + c02 * r[2]) / det;
    x[1] = m[1] + (c01 * r[0] + c11 * r[1] + c12 * r[2]) / det;
    x[2] = m[2] + (c02 * r[0] + c12 * r[1] + c22 * r[2]) / det;
}

/* The Hermite datum of a crossed grid edge: the surface point on it and the
 * normal there, solved once for the four cells around the edge. */
typedef struct crossing {
    float p[3], n[3];
} crossing;

/* A crossed cell's sheets: its first vertex and, per cell edge, the sheet
 * (so the vertex first + sheet) that crosses it. */
typedef struct cell_sheets {
    uint32_t cell[3], first; /* the cell (i, j, k), its first vertex */
    uint8_t mask;            /* its corners inside (merp_walk_corners) */
    uint8_t sheet[12];
} cell_sheets;

/* The crossings found so far, by grid edge (3 × its lower sample + its
 * axis): open addressing over a power-of-two table at most half full, so a
 * patch touches memory in the surface's area, not the grid's volume. */
typedef struct edge_map {
    uint32_t *slot; /* per slot: key + 1 (0: empty) */
    uint32_t *value;
    uint32_t mask, n;
} edge_map;

static uint32_t map_home(uint32_t key, uint32_t mask)
{
    return (key * 0x9e3779b1u >> 7) & mask;
}

/* The slot of `key`: its own or the empty one it would take. */
static uint32_t map_find(const edge_map *m, uint32_t key)
{
    uint32_t i = map_home(key, m->mask);
    while (m->slot[i] != 0 && m->slot[i] != key + 1)
        i = (i + 1) & m->mask;
    return i;
}

/* Room for `more` keys: doubles the table while they would fill it over half. */
static bool map_room(edge_map *m, uint32_t more)
{
    if (m->slot != NULL && 2 * (m->n + more) <= m->mask + 1)
        return true;
    uint32_t size = m->slot == NULL ? 1024 : 2 * (m->mask + 1);
    while (2 * (m->n + more) > size)
        size *= 2;
    edge_map g = {merp_calloc(size, sizeof(uint32_t)), merp_malloc(size * sizeof(uint32_t)), size - 1, m->n};
    if (g.slot == NULL || g.value == NULL) {
        merp_free(g.slot), merp_free(g.value);
        return false;
    }
    for (uint32_t i = 0; m->slot != NULL && i <= m->mask; i++)
        if (m->slot[i] != 0) {
            uint32_t j = map_find(&g, m->slot[i] - 1);
            g.slot[j] = m->slot[i], g.value[j] = m->value[i];
        }
    merp_free(m->slot), merp_free(m->value);
    *m = g;
    return true;
}

/* A mask's sheets where no face of the cell is ambiguous: they follow
 * from the mask alone, so a patch splits each such mask once. */
typedef struct mask_split {
    uint8_t sheet[12], n, cached; /* cached: 1 once split */
} mask_split;

typedef struct dc {
    merp_walk *w;
    mask_split split[256]; /* by mask */
    uint32_t cell_step[3]; /* a cell's index less its neighbour's below along x, y, z (cell_index) */
    uint32_t *cell_v;      /* per crossed cell: its cell_sheets + 1 (others not set) */
    cell_sheets *sheets; /* per crossed cell, in the walk's order */
    edge_map edges;      /* grid edge → its crossing in x */
    edge_map faces;      /* cell face with four crossed edges → 1 where its choice is reversed, else 0 */
    crossing *x;         /* the crossings solved so far */
    uint32_t nx, xcap, nsheets;
    merp_trimesh *out;
    merp_dc_source *src; /* per vertex: where it comes from, or NULL */
} dc;

/* Room in d->x for `more` crossings. A cell takes every crossing it needs
 * (at most 12) before it uses any, so its pointers into d->x stay valid. */
static bool crossing_room(dc *d, uint32_t more)
{
    if (d->nx + more <= d->xcap)
        return true;
    uint32_t cap = d->xcap ? 2 * d->xcap : 1024;
    crossing *x = merp_realloc(d->x, (size_t)cap * sizeof *x);
    if (x == NULL)
        return false;
    d->x = x, d->xcap = cap;
    return true;
}

/* Cell (i, j, k)'s index, x fastest: the index cell_v and merp_walk_queued take. */
static uint32_t cell_index(const dc *d, const uint32_t cell[3])
{
    return cell[0] + d->cell_step[1] * cell[1] + d->cell_step[2] * cell[2];
}

/* The crossing on edge e of the cell whose lowest sample is s0 (corners
 * differ in sign): solved on first use. Needs room for one more crossing
 * (crossing_room) and one more key in the edge map (map_room). */
static const crossing *edge_crossing(dc *d, const uint32_t cell[3], uint32_t s0, const float cf[8], int e)
{
    const merp_grid *g = d->w->g;
    uint8_t c1 = cube_edge[e][0], c2 = cube_edge[e][1];
    uint32_t key = 3 * (s0 + d->w->corner[c1]) + (uint32_t)(e >> 2);
    uint32_t slot = map_find(&d->edges, key);
    if (d->edges.slot[slot] != 0)
        return &d->x[d->edges.value[slot]];
    assert(d->nx < d->xcap);
    crossing *x = &d->x[d->nx];
    float p1[3], p2[3];
    merp_grid_point(g, cell[0] + (c1 & 1), cell[1] + (c1 >> 1 & 1), cell[2] + (c1 >> 2 & 1), p1);
    merp_grid_point(g, cell[0] + (c2 & 1), cell[1] + (c2 >> 1 & 1), cell[2] + (c2 >> 2 & 1), p2);
    if (cf[c1] >= MERP_ISO)
        merp_walk_crossing(d->w, p1, cf[c1], p2, cf[c2], x->p, x->n);
    else
        merp_walk_crossing(d->w, p2, cf[c2], p1, cf[c1], x->p, x->n);
    d->edges.slot[slot] = key + 1, d->edges.value[slot] = d->nx++, d->edges.n++;
    return x;
}

/* A cell's six faces (−x, +x, −y, +y, −z, +z): their corners in order
 * round the face, and the edge from each corner to the next (cube_edge's). */
static const uint8_t face_corner[6][4] = {
    {0, 2, 6, 4}, {1, 3, 7, 5}, {0, 4, 5, 1}, {2, 6, 7, 3}, {0, 1, 3, 2}, {4, 5, 7, 6},
};
static const uint8_t face_edge[6][4] = {
    {4, 10, 6, 8}, {5, 11, 7, 9}, {8, 2, 9, 0}, {10, 3, 11, 1}, {0, 5, 1, 4}, {2, 7, 3, 6},
};

/* The cell edges whose corners differ in sign under `mask`, as bits: the
 * corners one step along an axis apart, XORed, then each axis's four bits
 * gathered in cube_edge's order (x: corners 0, 2, 4, 6 to their +x
 * neighbours; y: 0, 1, 4, 5; z: 0–3). */
static uint16_t crossed_edges(uint8_t mask)
{
    unsigned m = mask, x = m ^ m >> 1, y = m ^ m >> 2, z = (m ^ m >> 4) & 0xfu;
    x = (x & 1u) | (x >> 1 & 2u) | (x >> 2 & 4u) | (x >> 3 & 8u);
    y = (y & 3u) | (y >> 2 & 0xcu);
    return (uint16_t)(x | y << 4 | z << 8);
}

/* Links crossed edges a and b of one face: each crossed edge has one
 * partner on each of its two faces. */
static void pair_edges(uint8_t (*partner)[2], uint8_t *links, int a, int b)
{
    partner[a][links[a]++] = (uint8_t)b;
    partner[b][links[b]++] = (uint8_t)a;
}

/* The cell's sheets: its crossed edges (`x`, as crossed_edges gives them)
 * grouped by the segments the surface draws on each face. A face with four
 * crossed edges (corners alternating in sign) is decided by the asymptotic
 * decider (Nielson & Hamann 1991): the inside corners are joined across the
 * face when the bilinear interpolant's saddle is inside, and the other way
 * on the faces in `flip` (cell_sheets_chosen). Both cells of a face see its four
 * values and its choice alike, so they agree on its segments and their
 * sheets meet edge to edge: the dual mesh is a manifold where no sheet
 * crosses one face twice on both sides (cell_sheets_chosen). A face has zero,
 * two or four crossed edges, each in one segment, and an edge lies on two
 * faces: so each crossed edge has two partners and each sheet is a cycle of
 * edges, walked round from its lowest edge. Returns the number of sheets;
 * sheet[e] for each crossed edge e (0 for the others), numbered by their
 * lowest edge; *ambiguous: the faces with four crossed edges, as bits (none:
 * the split depends on the mask alone). */
static int cell_sheet_split(const float cf[8], uint8_t mask, uint16_t x, uint8_t flip, uint8_t sheet[12],
                            uint8_t *ambiguous)
{
    uint8_t partner[12][2], links[12] = {0};
    memset(sheet, 0, 12);
    *ambiguous = 0;
    for (int face = 0; face < 6; face++) {
        const uint8_t *k = face_corner[face], *fe = face_edge[face];
        int at[4], crossed = 0;
        for (int t = 0; t < 4; t++)
            if (x >> fe[t] & 1)
                at[crossed++] = t;
        if (crossed == 2) {
            pair_edges(partner, links, fe[at[0]], fe[at[1]]);
        } else if (crossed == 4) {
            *ambiguous |= (uint8_t)(1u << face);
            float v[4];
            for (int t = 0; t < 4; t++)
                v[t] = cf[k[t]] - MERP_ISO;
            float num = v[0] * v[2] - v[1] * v[3], den = v[0] + v[2] - v[1] - v[3];
            bool saddle_in = den > 0.0f ? num >= 0.0f : num <= 0.0f;
            /* Cut off each corner of the side that is not joined: corner
             * t's edges are fe[t − 1] and fe[t]. */
            bool cut_in = !saddle_in != (bool)(flip >> face & 1);
            for (int t = 0; t < 4; t++)
                if ((bool)(mask >> k[t] & 1) == cut_in)
                    pair_edges(partner, links, fe[(t + 3) % 4], fe[t]);
        }
    }
    int n = 0;
    uint16_t left = x;
    for (int e = 0; e < 12; e++) {
        if (!(left >> e & 1))
            continue;
        assert(links[e] == 2);
        int prev = -1, at = e;
        do { /* round the cycle: the partner we did not come from */
            sheet[at] = (uint8_t)n;
            left &= (uint16_t)~(1u << at);
            int next = partner[at][0] != prev ? partner[at][0] : partner[at][1];
            prev = at, at = next;
        } while (at != e);
        n++;
    }
    return n;
}

/* Whether one sheet of the cell crosses all four edges of `face` (both of
 * its segments there). */
static bool tunnel(const uint8_t sheet[12], int face)
{
    const uint8_t *fe = face_edge[face];
    return sheet[fe[0]] == sheet[fe[1]] && sheet[fe[1]] == sheet[fe[2]] && sheet[fe[2]] == sheet[fe[3]];
}

/* Face `face` of the cell: its key in d->faces (3 × the index of the cell
 * on its lower side + its axis), or UINT32_MAX on the grid's boundary (no
 * cell beyond). */
static uint32_t face_key(const dc *d, const uint32_t cell[3], int face)
{
    int a = face / 2;
    if (face % 2 ? cell[a] + 1 >= d->w->g->n[a] : cell[a] == 0)
        return UINT32_MAX;
    return 3 * (cell_index(d, cell) - (face % 2 ? 0 : d->cell_step[a])) + (uint32_t)a;
}

/* The faces of `ambiguous` whose choice is recorded reversed, as bits;
 * *open: those with none recorded yet. */
static uint8_t recorded_flips(const dc *d, const uint32_t cell[3], uint8_t ambiguous, uint8_t *open)
{
    uint8_t flip = 0;
    *open = 0;
    for (int face = 0; face < 6; face++) {
        if (!(ambiguous >> face & 1))
            continue;
        uint32_t key = face_key(d, cell, face);
        if (key == UINT32_MAX)
            continue; /* no quad crosses it */
        uint32_t slot = map_find(&d->faces, key);
        if (d->faces.slot[slot] == 0)
            *open |= (uint8_t)(1u << face);
        else
            flip |= (uint8_t)(d->faces.value[slot] << face);
    }
    return flip;
}

/* The cell's sheets (cell_sheet_split) with each face's choice: where one
 * sheet crosses a face twice in this cell and one sheet in the cell beyond,
 * the dual edge between the two cells' vertices would be a side of all four
 * of the face's edges' quads (a directed edge twice: no manifold, and a
 * patch does not close). Reversing the decider's choice there pairs each
 * segment's edges with the other's, which splits both sheets in two (a
 * sheet is wound one way round, so it crosses the two segments the same
 * way round the face, and the other pairing closes each half), and the
 * four quads meet at two dual edges, two each; it merges no sheets, since
 * a sheet that does not cross the face keeps its edges. Each face is
 * chosen once, by the first of its two cells the walk reaches, from both
 * cells' sheets as the choices so far make them, and recorded in d->faces
 * for the other; the cell's open faces in turn, its sheets split again
 * after each reversal. So every reversal splits sheets and none merges
 * them: a face not reversed when chosen never becomes a tunnel on both
 * sides later. The choices follow the walk's order, which is the patch's
 * own: the bytes do not depend on the threads. (Such tunnels kept 56 of
 * the 3,220 junction patches of 56 presets from closing on their first
 * grid: joints.c, SHIFT.) Returns the number of sheets, as cell_sheet_split;
 * *ambiguous: the faces with four crossed edges, as bits. Needs room in
 * d->faces for six more keys. */
static int cell_sheets_chosen(dc *d, const uint32_t cell[3], const float cf[8], uint8_t mask, uint16_t x,
                              uint8_t sheet[12], uint8_t *ambiguous)
{
    int n = cell_sheet_split(cf, mask, x, 0, sheet, ambiguous);
    if (*ambiguous == 0)
        return n;
    uint8_t open, flip = recorded_flips(d, cell, *ambiguous, &open);
    if (flip)
        n = cell_sheet_split(cf, mask, x, flip, sheet, ambiguous);
    for (int face = 0; face < 6; face++) {
        if (!(open >> face & 1))
            continue;
        uint32_t reverse = 0;
        if (tunnel(sheet, face)) { /* and the cell beyond, as the choices so far make it? */
            int a = face / 2;
            uint32_t q[3] = {cell[0], cell[1], cell[2]};
            q[a] = face % 2 ? q[a] + 1 : q[a] - 1;
            float qf[8];
            uint8_t qmask = merp_walk_corners(d->w, q, qf), qsheet[12], qamb, qopen;
            uint16_t qx = crossed_edges(qmask);
            cell_sheet_split(qf, qmask, qx, 0, qsheet, &qamb);
            uint8_t qflip = recorded_flips(d, q, qamb, &qopen);
            if (qflip)
                cell_sheet_split(qf, qmask, qx, qflip, qsheet, &qamb);
            reverse = tunnel(qsheet, face ^ 1);
        }
        uint32_t key = face_key(d, cell, face), slot = map_find(&d->faces, key);
        d->faces.slot[slot] = key + 1, d->faces.value[slot] = reverse, d->faces.n++;
        if (reverse) {
            flip |= (uint8_t)(1u << face);
            n = cell_sheet_split(cf, mask, x, flip, sheet, ambiguous);
        }
    }
    return n;
}

/* The vertex of one sheet: its crossings' QEF minimum, clamped into the cell. */
static void sheet_vertex(dc *d, const uint32_t cell[3], const crossing *const *x, int nx, uint8_t corners)
{
    const merp_grid *g = d->w->g;
    qef q;
    memset(&q, 0, sizeof q);
    for (int i = 0; i < nx; i++)
        qef_add(&q, x[i]->p, x[i]->n);
    float v_[3];
    qef_solve(&q, v_);
    merp_grid_clamp(g, cell, v_);
    merp_trimesh *o = d->out;
    uint32_t v = o->vertex_count++;
    memcpy(o->positions + 3 * (size_t)v, v_, sizeof v_);
    if (o->normals != NULL) { /* a caller may shade from another field */
        float fallback[3] = {v_[0] - q.mass[0] / (float)q.count, v_[1] - q.mass[1] / (float)q.count,
                             v_[2] - q.mass[2] / (float)q.count};
        if (!v3_normalize(fallback))
            fallback[0] = 1.0f;
        /* f(v) only for the differences: the gradient, where there is one, needs none */
        float fv = d->w->grad != NULL ? 0.0f : d->w->f(v_, d->w->data);
        merp_walk_normal(d->w, v_, fv, fallback, o->normals + 3 * (size_t)v);
    }
    if (d->src != NULL)
        d->src[v] = (merp_dc_source){{cell[0], cell[1], cell[2]}, corners};
}

/* The cell's vertices, one per sheet. MER_ERR_NOMEM when a crossing finds no room. */
static mer_result cell_vertices(dc *d, const uint32_t cell[3], const float cf[8], uint8_t mask)
{
    cell_sheets *cs = &d->sheets[d->nsheets];
    uint16_t crossed = crossed_edges(mask);
    mask_split *split = &d->split[mask];
    int n = split->n;
    if (split->cached) {
        memcpy(cs->sheet, split->sheet, sizeof cs->sheet);
    } else {
        uint8_t ambiguous;
        if (!map_room(&d->faces, 6))
            return MER_ERR_NOMEM;
        n = cell_sheets_chosen(d, cell, cf, mask, crossed, cs->sheet, &ambiguous);
        if (!ambiguous) {
            memcpy(split->sheet, cs->sheet, sizeof split->sheet);
            split->n = (uint8_t)n, split->cached = 1;
        }
    }
    cs->first = d->out->vertex_count;
    cs->mask = mask;
    if (!crossing_room(d, 12) || !map_room(&d->edges, 12))
        return MER_ERR_NOMEM;
    const uint32_t s0 = merp_walk_sample(d->w, cell[0], cell[1], cell[2]);
    for (int s = 0; s < n; s++) {
        const crossing *x[12];
        int nx = 0;
        uint8_t corners = 0;
        for (int e = 0; e < 12; e++) {
            if (!(crossed >> e & 1) || cs->sheet[e] != s)
                continue;
            x[nx++] = edge_crossing(d, cell, s0, cf, e);
            corners |= (uint8_t)(1u << cube_edge[e][0] | 1u << cube_edge[e][1]);
        }
        sheet_vertex(d, cell, x, nx, corners);
    }
    memcpy(cs->cell, cell, sizeof cs->cell);
    d->cell_v[cell_index(d, cell)] = ++d->nsheets;
    return MER_OK;
}

/* The vertex of the sheet through edge e of cell c (its index, x fastest);
 * 0 when the walk did not reach c, else the vertex + 1. */
static uint32_t vertex_of(const dc *d, uint32_t c, int e)
{
    /* A queued cell around a crossed edge is crossed, so the walk gave it
     * its vertices and its cell_v (which is not cleared). */
    if (!merp_walk_queued(d->w, c))
        return 0;
    uint32_t r = d->cell_v[c];
    assert(r >= 1 && r <= d->nsheets);
    return d->sheets[r - 1].first + d->sheets[r - 1].sheet[e] + 1;
}

/* Which diagonal a quad is split along, 0 (0–2) or 1 (1–3), from the
 * normals n[t] (not normalized) of the triangles at its corners t: split
 * 0–2 makes the triangles at corners 1 and 3, and the split whose two
 * normals agree more is taken (the cosines compared in float). The cosines
 * in double first, with two square roots and two divisions where the float
 * path takes four and twelve: where they differ by more than 1e-5 (the
 * float path's rounding is ~1e-6), that path's answer is theirs. */
static int split_of(float n[4][3])
{
    double c[4][3], l[4];
    for (int t = 0; t < 4; t++) {
        for (int k = 0; k < 3; k++)
            c[t][k] = (double)n[t][k];
        l[t] = c[t][0] * c[t][0] + c[t][1] * c[t][1] + c[t][2] * c[t][2];
    }
    if (l[0] > 1e-30 && l[1] > 1e-30 && l[2] > 1e-30 && l[3] > 1e-30) {
        double c13 = (c[1][0] * c[3][0] + c[1][1] * c[3][1] + c[1][2] * c[3][2]) / sqrt(l[1] * l[3]);
        double c02 = (c[0][0] * c[2][0] + c[0][1] * c[2][1] + c[0][2] * c[2][2]) / sqrt(l[0] * l[2]);
        if (fabs(c13 - c02) > 1e-5)
            return c13 >= c02 ? 0 : 1;
    }
    for (int t = 0; t < 4; t++)
        v3_normalize(n[t]);
    return v3_dot(n[1], n[3]) >= v3_dot(n[0], n[2]) ? 0 : 1;
}

/* The quads of the cell's three edges from its corner 0 (each interior
 * crossed edge is corner 0's edge of exactly one cell): the sheets through
 * the edge in the four cells around it, counter-clockwise about +axis,
 * reversed when the edge's far end is the inside one, split along the
 * diagonal that folds least. */
static void cell_quads(dc *d, const uint32_t cell[3], uint8_t mask)
{
    /* (−, −), (0, −), (0, 0), (−, 0) in the (b, c) plane of axis a (b =
     * a + 1, c = a + 2, mod 3); in each cell the edge starts at the corner
     * opposite the offset: for axis a, that cell's edge quad_edge[a][t]
     * (cube_edge's from that corner to the next along a). */
    static const uint8_t off[4][2] = {{1, 1}, {0, 1}, {0, 0}, {1, 0}};
    static const uint8_t quad_edge[3][4] = {{3, 2, 0, 1}, {7, 5, 4, 6}, {11, 10, 8, 9}};
    const float *pos = d->out->positions;
    const uint32_t *step = d->cell_step;
    const uint32_t at = cell_index(d, cell);
    for (int a = 0; a < 3; a++) {
        uint8_t far = (uint8_t)(1u << a);
        if ((mask & 1) == (mask >> far & 1))
            continue;
        int b = a == 2 ? 0 : a + 1, c = a == 0 ? 2 : a - 1;
        if (cell[b] == 0 || cell[c] == 0)
            continue; /* on the grid's face: the surface leaves it here */
        uint32_t v[4];
        for (int t = 0; t < 4; t++) {
            v[t] = vertex_of(d, at - off[t][0] * step[b] - off[t][1] * step[c], quad_edge[a][t]);
            if (v[t] == 0)
                return; /* a neighbour the walk did not reach */
            v[t]--;
        }
        if (!(mask & 1)) { /* the inside is at the far end: face −axis */
            uint32_t s = v[1];
            v[1] = v[3], v[3] = s;
        }
        /* Split along 0–2 or 1–3: the one whose two triangles' normals agree more. */
        float n[4][3];
        for (int t = 0; t < 4; t++) {
            const float *p0 = pos + 3 * (size_t)v[t], *p1 = pos + 3 * (size_t)v[(t + 1) % 4],
                        *p2 = pos + 3 * (size_t)v[(t + 3) % 4];
            float e1[3], e2[3];
            for (int k = 0; k < 3; k++)
                e1[k] = p1[k] - p0[k], e2[k] = p2[k] - p0[k];
            v3_cross(e1, e2, n[t]);
        }
        int s = split_of(n);
        uint32_t *t = d->out->triangles + 3 * (size_t)d->out->triangle_count;
        t[0] = v[s], t[1] = v[s + 1], t[2] = v[(s + 2) % 4];
        t[3] = v[s], t[4] = v[(s + 2) % 4], t[5] = v[(s + 3) % 4];
        d->out->triangle_count += 2;
    }
}

static void dc_free(merp_walk *w, dc *d)
{
    merp_walk_free(w);
    merp_free(d->cell_v), merp_free(d->sheets), merp_free(d->x);
    merp_free(d->edges.slot), merp_free(d->edges.value);
    merp_free(d->faces.slot), merp_free(d->faces.value);
}

mer_result merp_dc_polygonize(const merp_grid *g, merp_field_fn f, merp_gradient_fn grad,
                              const void *data, const float (*seeds)[3], uint32_t nseeds,
                              merp_trimesh *out, merp_dc_source *src, mer_error *err)
{
    merp_walk w;
    dc d = {.w = &w, .out = out, .src = src};
    size_t cells = (size_t)g->n[0] * g->n[1] * g->n[2];
    assert(3 * (uint64_t)(g->n[0] + 1) * (g->n[1] + 1) * (g->n[2] + 1) < UINT32_MAX); /* edge keys */
    if (merp_walk_begin(&w, g, f, data, seeds, nseeds, cells, &d.cell_v, out, err) != MER_OK)
        return MER_ERR_NOMEM;
    w.grad = grad;
    d.cell_step[0] = 1, d.cell_step[1] = g->n[0], d.cell_step[2] = g->n[0] * g->n[1];
    d.sheets = merp_malloc(cells * sizeof *d.sheets);
    mer_result rc = d.sheets != NULL ? MER_OK : MER_ERR_NOMEM;
    uint32_t cell[3];
    float cf[8];
    uint8_t mask;
    bool room = true;
    while (rc == MER_OK && room && merp_walk_next(&w, cell, cf, &mask)) {
        room = merp_trimesh_has_room(out, MERP_DC_SHEETS, 0);
        if (room)
            rc = cell_vertices(&d, cell, cf, mask);
    }
    /* Every crossed cell has its vertices: now the quads, in the walk's
     * order (that of d.sheets), from the masks the cells kept: a quad for
     * each of a cell's three edges at its lowest corner, two triangles. */
    for (uint32_t i = 0; i < d.nsheets && rc == MER_OK && room; i++) {
        room = merp_trimesh_has_room(out, 0, 6);
        if (room)
            cell_quads(&d, d.sheets[i].cell, d.sheets[i].mask);
    }
    dc_free(&w, &d);
    if (rc != MER_OK)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory polygonizing a field");
    if (!room)
        return mer_error_set(err, MER_ERR_INVALID, NULL, "a polygonized surface outgrows its arrays");
    return MER_OK;
}
