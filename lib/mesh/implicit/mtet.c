/* meristem — marching tetrahedra over the Freudenthal triangulation of a
 * grid, regular or graded (implicit.h). A polygonizer for smooth fields: no
 * ambiguous case (a tetrahedron's sign pattern has one surface piece), so
 * the output is a closed manifold wherever the surface stays inside the
 * grid. */
#include "config.h"

#include <assert.h>
#include <math.h>
#include <stdbool.h>
#include <string.h>

#include "core/alloc.h"
#include "core/vec.h"
#include "mesh/implicit/implicit.h"
#include "mesh/implicit/walk.h"

/* The six tetrahedra of a cell: paths 0 → a → a|b → 7 over the corner bits
 * (x = 1, y = 2, z = 4), one per order of the three axes. */
static const uint8_t kuhn[6][4] = {
    {0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7}, {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7},
};

typedef struct mtet {
    const merp_grid *g;
    merp_field_fn f;
    const void *data;
    merp_walk *w;
    uint32_t *edge_v;  /* per sample × 7 directions: vertex + 1, 0 when none yet */
    uint32_t *cleared; /* a bit per sample: its 7 edge_v slots are cleared (on first
                          use: a walk touches few samples of its grid) */
    merp_trimesh *out;
} mtet;

void merp_mtet_bound(const merp_grid *g, uint64_t *vertices, uint64_t *triangles)
{
    uint64_t samples = (uint64_t)(g->n[0] + 1) * (g->n[1] + 1) * (g->n[2] + 1);
    uint64_t cells = (uint64_t)g->n[0] * g->n[1] * g->n[2];
    *vertices = samples * 7;
    *triangles = cells * 6 * 2;
}

static void sample_pos(const merp_grid *g, uint32_t i, uint32_t j, uint32_t k, float p[3])
{
    merp_grid_point(g, i, j, k, p);
}

/* The vertex on the edge between corners c1 ⊂ c2 (bit masks) of cell (i,j,k),
 * made once for all the tetrahedra that share the edge. */
static uint32_t edge_vertex(mtet *m, const uint32_t cell[3], uint8_t c1, uint8_t c2)
{
    uint32_t i1 = cell[0] + (c1 & 1), j1 = cell[1] + (c1 >> 1 & 1), k1 = cell[2] + (c1 >> 2 & 1);
    uint32_t i2 = cell[0] + (c2 & 1), j2 = cell[1] + (c2 >> 1 & 1), k2 = cell[2] + (c2 >> 2 & 1);
    uint32_t s1 = merp_walk_sample(m->w, i1, j1, k1), s2 = merp_walk_sample(m->w, i2, j2, k2);
    if (!(m->cleared[s1 >> 5] >> (s1 & 31) & 1u)) {
        memset(m->edge_v + (size_t)s1 * 7, 0, 7 * sizeof *m->edge_v);
        m->cleared[s1 >> 5] |= 1u << (s1 & 31);
    }
    uint32_t *slot = &m->edge_v[(size_t)s1 * 7 + (uint32_t)(c1 ^ c2) - 1];
    if (*slot != 0)
        return *slot - 1;
    float p1[3], p2[3], p[3], dir[3];
    sample_pos(m->g, i1, j1, k1, p1);
    sample_pos(m->g, i2, j2, k2, p2);
    const float *value = m->w->value; /* both corners are known: their cell was marched */
    bool in1 = value[s1] >= MERP_ISO;
    float fp = in1 ? merp_walk_solve(m->w, p1, value[s1], p2, value[s2], p)
                   : merp_walk_solve(m->w, p2, value[s2], p1, value[s1], p);
    for (int a = 0; a < 3; a++)
        dir[a] = in1 ? p2[a] - p1[a] : p1[a] - p2[a];
    merp_trimesh *o = m->out;
    uint32_t v = o->vertex_count++;
    memcpy(o->positions + 3 * (size_t)v, p, sizeof p);
    if (o->normals != NULL) /* a caller may shade from another field */
        merp_walk_normal(m->w, p, fp, dir, o->normals + 3 * (size_t)v);
    *slot = v + 1;
    return v;
}

/* The corner's position in cell units (0 or 1 per axis). */
static void corner_pos(uint8_t c, float p[3])
{
    p[0] = (float)(c & 1);
    p[1] = (float)(c >> 1 & 1);
    p[2] = (float)(c >> 2 & 1);
}

/* Emits the triangle (e[0], e[1], e[2]) of edges given as corner pairs,
 * oriented from the tetrahedron's inside corners (centroid `ci`) to its outside
 * ones (`co`). The orientation is decided on the edges' midpoints, which are
 * never degenerate, and carried over to the surface points: both lie on the
 * same side of each corner along each edge, so the winding is the same. */
static void emit(mtet *m, const uint32_t cell[3], const uint8_t e[3][2], const float ci[3],
                 const float co[3])
{
    float mid[3][3], a[3], b[3], n[3], ref[3];
    for (int t = 0; t < 3; t++) {
        float p[3], q[3];
        corner_pos(e[t][0], p);
        corner_pos(e[t][1], q);
        for (int k = 0; k < 3; k++)
            mid[t][k] = 0.5f * (p[k] + q[k]);
    }
    for (int k = 0; k < 3; k++) {
        a[k] = mid[1][k] - mid[0][k];
        b[k] = mid[2][k] - mid[0][k];
        ref[k] = co[k] - ci[k];
    }
    v3_cross(a, b, n);
    bool flip = v3_dot(n, ref) < 0.0f;
    uint32_t v[3];
    for (int t = 0; t < 3; t++) {
        uint8_t c1 = e[t][0] < e[t][1] ? e[t][0] : e[t][1];
        uint8_t c2 = e[t][0] ^ e[t][1] ^ c1;
        v[t] = edge_vertex(m, cell, c1, c2);
    }
    merp_trimesh *o = m->out;
    uint32_t *tri = o->triangles + 3 * (size_t)o->triangle_count++;
    tri[0] = v[0];
    tri[1] = flip ? v[2] : v[1];
    tri[2] = flip ? v[1] : v[2];
}

/* One tetrahedron of corners c[4] (bit masks) of `cell`. */
static void tetra(mtet *m, const uint32_t cell[3], const uint8_t c[4], const float f[4])
{
    uint8_t in[4], out[4];
    int ni = 0, no = 0;
    float ci[3] = {0, 0, 0}, co[3] = {0, 0, 0}, p[3];
    for (int t = 0; t < 4; t++) {
        bool inside = f[t] >= MERP_ISO;
        corner_pos(c[t], p);
        for (int k = 0; k < 3; k++) {
            if (inside)
                ci[k] += p[k];
            else
                co[k] += p[k];
        }
        if (inside)
            in[ni++] = c[t];
        else
            out[no++] = c[t];
    }
    if (ni == 0 || no == 0)
        return;
    for (int k = 0; k < 3; k++)
        ci[k] /= (float)ni, co[k] /= (float)no;
    if (ni == 1 || no == 1) {
        uint8_t lone = ni == 1 ? in[0] : out[0];
        const uint8_t *rest = ni == 1 ? out : in;
        const uint8_t e[3][2] = {{lone, rest[0]}, {lone, rest[1]}, {lone, rest[2]}};
        emit(m, cell, e, ci, co);
        return;
    }
    /* Two in, two out: the quad (i0o0, i0o1, i1o1, i1o0), as two triangles. */
    const uint8_t e1[3][2] = {{in[0], out[0]}, {in[0], out[1]}, {in[1], out[1]}};
    const uint8_t e2[3][2] = {{in[0], out[0]}, {in[1], out[1]}, {in[1], out[0]}};
    emit(m, cell, e1, ci, co);
    emit(m, cell, e2, ci, co);
}

/* Marches a cell whose corners (values cf) differ in sign. */
static void cell_march(mtet *m, const uint32_t cell[3], const float cf[8])
{
    for (int t = 0; t < 6; t++) {
        const float f[4] = {cf[kuhn[t][0]], cf[kuhn[t][1]], cf[kuhn[t][2]], cf[kuhn[t][3]]};
        tetra(m, cell, kuhn[t], f);
    }
}

/* Marches the cells the walk gives: every crossed cell when `seeds` is NULL,
 * else those reached from the seeds. */
static mer_result march(const merp_grid *g, merp_field_fn f, const void *data, const float (*seeds)[3],
                        uint32_t nseeds, merp_trimesh *out, mer_error *err)
{
    merp_walk w;
    if (merp_walk_init(&w, g, f, data, err) != MER_OK)
        return MER_ERR_NOMEM;
    mtet m = {g, f, data, &w, NULL, NULL, out};
    size_t samples = (size_t)w.sx * w.sy * (g->n[2] + 1);
    m.edge_v = merp_malloc(samples * 7 * sizeof(uint32_t));
    m.cleared = merp_calloc(samples / 32 + 1, sizeof(uint32_t));
    if (m.edge_v == NULL || m.cleared == NULL) {
        merp_walk_free(&w);
        merp_free(m.edge_v), merp_free(m.cleared);
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory polygonizing a field");
    }
    merp_walk_start(&w, seeds, nseeds);
    out->vertex_count = out->triangle_count = 0;
    uint32_t cell[3];
    float cf[8];
    uint8_t mask;
    bool room = true;
    while (room && merp_walk_next(&w, cell, cf, &mask)) {
        /* A cell adds at most a vertex per edge of its tetrahedra (19) and
         * two triangles per tetrahedron. */
        room = merp_trimesh_has_room(out, 19, 12);
        if (room)
            cell_march(&m, cell, cf);
    }
    merp_walk_free(&w);
    merp_free(m.edge_v), merp_free(m.cleared);
    if (!room)
        return mer_error_set(err, MER_ERR_INVALID, NULL, "a polygonized surface outgrows its arrays");
    return MER_OK;
}

mer_result merp_mtet_polygonize(const merp_grid *g, merp_field_fn f, const void *data,
                                merp_trimesh *out, mer_error *err)
{
    return march(g, f, data, NULL, 0, out, err);
}

mer_result merp_mtet_polygonize_seeded(const merp_grid *g, merp_field_fn f, const void *data,
                                       const float (*seeds)[3], uint32_t nseeds, merp_trimesh *out,
                                       mer_error *err)
{
    assert(seeds != NULL && nseeds >= 1);
    return march(g, f, data, seeds, nseeds, out, err);
}
