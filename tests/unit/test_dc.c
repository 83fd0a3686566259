/* Dual contouring on fields with known surfaces: a ball and a tapered
 * capsule (vertices on the surface, closed genus-0 manifolds wound
 * outwards, within merp_dc_bound), and a rotated cube, whose twelve sharp
 * edges DC keeps and marching tetrahedra round off, closed and manifold
 * where two sheets cross a cell face. */
#include "config.h"

#include <math.h>
#include <setjmp.h>
#include <stdbool.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include <cmocka.h>

#include "mesh/implicit/implicit.h"
#include "trimesh_check.h"

static float seg_fn(const float p[3], const void *data)
{
    return merp_seg_field(data, p);
}

/* A cube of half side a, turned about (1, 2, 3) so that no edge follows the
 * grid: f = c − (max_i |q_i| − a) with q the turned p (a field with sharp
 * edges and corners, f ≥ c inside). */
typedef struct cube {
    float R[3][3];
    float a;
} cube;

static void cube_init(cube *c, float a)
{
    float u[3] = {1, 2, 3}, l = sqrtf(14.0f), th = 0.5f;
    for (int k = 0; k < 3; k++)
        u[k] /= l;
    float cs = cosf(th), sn = sinf(th);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            float e = (i == j ? cs : 0.0f) + (1 - cs) * u[i] * u[j];
            int k = 3 - i - j;
            if (i != j)
                e += ((i + 1) % 3 == j ? -1.0f : 1.0f) * sn * u[k];
            c->R[i][j] = e;
        }
    c->a = a;
}

static void cube_q(const cube *c, const float p[3], float q[3])
{
    for (int i = 0; i < 3; i++)
        q[i] = c->R[i][0] * p[0] + c->R[i][1] * p[1] + c->R[i][2] * p[2];
}

static float cube_fn(const float p[3], const void *data)
{
    const cube *c = data;
    float q[3];
    cube_q(c, p, q);
    float m = fmaxf(fabsf(q[0]), fmaxf(fabsf(q[1]), fabsf(q[2])));
    return MERP_ISO - (m - c->a);
}

static void dc(const merp_grid *g, merp_field_fn f, const void *data, mesh_out *o)
{
    uint64_t v, t;
    merp_dc_bound(g, &v, &t);
    mesh_alloc(o, v, t);
    mer_error err;
    assert_int_equal(merp_dc_polygonize(g, f, NULL, data, NULL, 0, &o->m, NULL, &err), MER_OK);
    assert_true(o->m.vertex_count <= o->vmax && o->m.triangle_count <= o->tmax);
    assert_true(o->m.triangle_count > 100);
}

static void mtet(const merp_grid *g, merp_field_fn f, const void *data, mesh_out *o)
{
    uint64_t v, t;
    merp_mtet_bound(g, &v, &t);
    mesh_alloc(o, v, t);
    mer_error err;
    assert_int_equal(merp_mtet_polygonize(g, f, data, &o->m, &err), MER_OK);
}

static void ball(void **state)
{
    (void)state;
    const merp_seg s = {{0, 0, 0}, {0, 0, 0}, 1, 1};
    const merp_grid g = {{-1.5f, -1.5f, -1.5f}, 0.1f, {30, 30, 30}, NULL};
    mesh_out o;
    dc(&g, seg_fn, &s, &o);
    assert_closed_genus0(&o);
    for (uint32_t v = 0; v < o.m.vertex_count; v++) {
        const float *p = o.m.positions + 3 * v, *n = o.m.normals + 3 * v;
        float r = sqrtf(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        /* The QEF's minimum lies a little off a curved surface (its tangent
         * planes meet outside it, the mass point is inside): within 5 % of h. */
        assert_float_equal(r, 1.0f, 5e-3);
        assert_true((p[0] * n[0] + p[1] * n[1] + p[2] * n[2]) / r > 0.999f);
    }
    double v = tm_volume(o.m.positions, o.m.triangles, o.m.triangle_count);
    assert_true(fabs(v - 4.0 / 3.0 * M_PI) < 0.02 * 4.0 / 3.0 * M_PI);
    mesh_free(&o);
}

/* With rooms set (merp_trimesh.vertex_room, triangle_room), both
 * polygonizers stop with MER_ERR_INVALID rather than write past them, and
 * with room enough give the mesh they give with their whole bound: a run's
 * patch reserves what its surface can take, not what a surface through
 * every cell of its grid would. */
static void rooms_are_kept(void **state)
{
    (void)state;
    const merp_seg s = {{0, 0, 0}, {0, 0, 0}, 1, 1};
    const merp_grid g = {{-1.5f, -1.5f, -1.5f}, 0.1f, {30, 30, 30}, NULL};
    for (int sharp = 0; sharp < 2; sharp++) {
        mesh_out whole;
        if (sharp)
            dc(&g, seg_fn, &s, &whole);
        else
            mtet(&g, seg_fn, &s, &whole);
        uint32_t V = whole.m.vertex_count, T = whole.m.triangle_count;
        /* rooms as the whole mesh needs (plus a cell's worth), then one short */
        const uint32_t rooms[4][2] = {{V + 19, T + 12}, {V + 19, 0}, {V / 2, 0}, {0, T / 2}};
        for (int r = 0; r < 4; r++) {
            mesh_out o;
            mesh_alloc(&o, rooms[r][0] ? rooms[r][0] : whole.vmax, rooms[r][1] ? rooms[r][1] : whole.tmax);
            o.m.vertex_room = rooms[r][0], o.m.triangle_room = rooms[r][1];
            mer_error err;
            mer_result rc = sharp ? merp_dc_polygonize(&g, seg_fn, NULL, &s, NULL, 0, &o.m, NULL, &err)
                                  : merp_mtet_polygonize(&g, seg_fn, &s, &o.m, &err);
            if (r < 2) {
                assert_int_equal(rc, MER_OK);
                assert_int_equal(o.m.vertex_count, V);
                assert_int_equal(o.m.triangle_count, T);
                assert_memory_equal(o.m.positions, whole.m.positions, (size_t)V * 3 * sizeof(float));
                assert_memory_equal(o.m.triangles, whole.m.triangles, (size_t)T * 3 * sizeof(uint32_t));
            } else {
                assert_int_equal(rc, MER_ERR_INVALID);
                assert_true(o.m.vertex_count <= (rooms[r][0] ? rooms[r][0] : V));
                assert_true(o.m.triangle_count <= (rooms[r][1] ? rooms[r][1] : T));
            }
            mesh_free(&o);
        }
        mesh_free(&whole);
    }
}

static void capsule(void **state)
{
    (void)state;
    const merp_seg s = {{0, -1, 0}, {0, 1, 0}, 0.6f, 0.3f};
    const merp_grid g = {{-0.9f, -1.9f, -0.9f}, 0.07f, {26, 54, 26}, NULL};
    mesh_out o;
    dc(&g, seg_fn, &s, &o);
    assert_closed_genus0(&o);
    for (uint32_t v = 0; v < o.m.vertex_count; v++) {
        float t, d = merp_seg_distance(&s, o.m.positions + 3 * v, &t);
        assert_float_equal(d, (1 - t) * 0.6f + t * 0.3f, 7e-3); /* 10 % of h, at r = 0.3 */
    }
    mesh_free(&o);
}

/* The distance from p to the nearest of the cube's 12 edges. */
static float edge_distance(const cube *c, const float p[3])
{
    float q[3], best = INFINITY;
    cube_q(c, p, q);
    for (int ax = 0; ax < 3; ax++) { /* edges along ax: the other two coordinates at ±a */
        int b = (ax + 1) % 3, d = (ax + 2) % 3;
        float along = fmaxf(0.0f, fabsf(q[ax]) - c->a);
        float db = fabsf(q[b]) - c->a, dd = fabsf(q[d]) - c->a;
        best = fminf(best, sqrtf(along * along + db * db + dd * dd));
    }
    return best;
}

typedef struct crease_fit {
    double volume_error; /* |V − (2a)³| / (2a)³ */
    uint32_t on_crease;  /* vertices within h / 20 of an edge */
} crease_fit;

static crease_fit fit(const mesh_out *o, const cube *c, float h)
{
    crease_fit r = {0, 0};
    double v = tm_volume(o->m.positions, o->m.triangles, o->m.triangle_count), exact = 8.0 * (double)c->a * (double)c->a * (double)c->a;
    r.volume_error = fabs(v - exact) / exact;
    for (uint32_t i = 0; i < o->m.vertex_count; i++)
        r.on_crease += edge_distance(c, o->m.positions + 3 * i) < 0.05f * h;
    return r;
}

/* The cube's edges: DC puts a vertex on the crease in every cell it crosses
 * (about 12 · 2a / h of them: 169 vertices within h / 20 of an edge here)
 * and loses a quarter of the volume marching tetrahedra does (0.18 % against
 * 0.74 %), which cuts each edge off: its vertices lie on grid edges, which
 * the crease rarely meets (40 near an edge). */
static void cube_creases(void **state)
{
    (void)state;
    cube c;
    cube_init(&c, 0.6f);
    const float h = 0.1f;
    const merp_grid g = {{-1.23f, -1.21f, -1.22f}, h, {25, 25, 25}, NULL};
    mesh_out d, t;
    dc(&g, cube_fn, &c, &d);
    mtet(&g, cube_fn, &c, &t);
    /* Closed, manifold and consistently wound, genus 0: at the cube's
     * corners a few cell faces have four crossed edges (two sheets), and
     * each sheet gets a vertex of its own. */
    assert_closed_genus0(&d);
    assert_true(tm_volume(d.m.positions, d.m.triangles, d.m.triangle_count) > 0);
    crease_fit fd = fit(&d, &c, h), ft = fit(&t, &c, h);
    print_message("volume error: DC %.5f, mtet %.5f; vertices on an edge: DC %u, mtet %u\n", fd.volume_error,
                  ft.volume_error, fd.on_crease, ft.on_crease);
    const uint32_t crease_cells = (uint32_t)(12 * 2 * c.a / h);
    assert_true(fd.on_crease >= crease_cells);
    assert_true(ft.on_crease < fd.on_crease / 3);
    assert_true(fd.volume_error < 0.5 * ft.volume_error);
    mesh_free(&d);
    mesh_free(&t);
}

/* A field of random values at the samples of a grid of cells of side 1,
 * trilinear between them: a tangle of thin sheets, tunnels and saddles in
 * every few cells, and outside on the grid's faces (so the surface closes
 * inside it). */
#define NOISE_N 10
typedef struct noise {
    float v[NOISE_N + 1][NOISE_N + 1][NOISE_N + 1];
} noise;

static void noise_init(noise *z, uint32_t seed)
{
    uint32_t x = seed * 2654435761u + 1u;
    for (int i = 0; i <= NOISE_N; i++)
        for (int j = 0; j <= NOISE_N; j++)
            for (int k = 0; k <= NOISE_N; k++) {
                x = x * 1664525u + 1013904223u;
                bool face = i == 0 || j == 0 || k == 0 || i == NOISE_N || j == NOISE_N || k == NOISE_N;
                z->v[i][j][k] = face ? MERP_ISO - 1.0f : MERP_ISO + (float)(x >> 8) / (float)(1u << 24) - 0.5f;
            }
}

static float noise_fn(const float p[3], const void *data)
{
    const noise *z = data;
    int c[3];
    float t[3];
    for (int a = 0; a < 3; a++) {
        float x = fminf(fmaxf(p[a], 0.0f), (float)NOISE_N);
        c[a] = x >= (float)NOISE_N ? NOISE_N - 1 : (int)x;
        t[a] = x - (float)c[a];
    }
    float f = 0.0f;
    for (int q = 0; q < 8; q++) {
        int di = q & 1, dj = q >> 1 & 1, dk = q >> 2 & 1;
        float w = (di ? t[0] : 1 - t[0]) * (dj ? t[1] : 1 - t[1]) * (dk ? t[2] : 1 - t[2]);
        f += w * z->v[c[0] + di][c[1] + dj][c[2] + dk];
    }
    return f;
}

/* Where a cell face has four crossed edges and one sheet crosses it twice
 * on both sides, the decider's choice is reversed there (dc.c,
 * cell_sheets_chosen): on a hundred noise fields DC's mesh is closed and
 * every directed edge comes once, though nearly all have handles (without
 * the reversal, all 100 had directed edges twice, 7,022 in all; reversed
 * only from both cells' sheets as the decider left them, 60 did, where a
 * second reversal in a cell merged what the first split). The noise keeps
 * off the grid's faces, so the surface closes inside it. */
static void tunnels_are_split(void **state)
{
    (void)state;
    const merp_grid g = {{0, 0, 0}, 1.0f, {NOISE_N, NOISE_N, NOISE_N}, NULL};
    noise *z = malloc(sizeof *z);
    uint32_t bad = 0, tangled = 0;
    for (uint32_t seed = 1; seed <= 100; seed++) {
        noise_init(z, seed);
        mesh_out o;
        uint64_t v, t;
        merp_dc_bound(&g, &v, &t);
        mesh_alloc(&o, v, t);
        mer_error err;
        assert_int_equal(merp_dc_polygonize(&g, noise_fn, NULL, z, NULL, 0, &o.m, NULL, &err), MER_OK);
        size_t twice, edges;
        size_t open = tm_open_edges(o.m.triangles, o.m.triangle_count, &twice, &edges);
        bad += open != 0 || twice != 0;
        if (open || twice) print_message("seed %u open %zu twice %zu\n", seed, open, twice);
        long chi = (long)o.m.vertex_count - (long)edges + (long)o.m.triangle_count;
        tangled += chi < 0; /* handles: the noise's tunnels */
        mesh_free(&o);
    }
    print_message("%u of 100 noise meshes not closed and manifold, %u with handles\n", bad, tangled);
    assert_int_equal(bad, 0);
    assert_true(tangled >= 50);
    free(z);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(ball),
        cmocka_unit_test(rooms_are_kept),
        cmocka_unit_test(capsule),
        cmocka_unit_test(cube_creases),
        cmocka_unit_test(tunnels_are_split),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
