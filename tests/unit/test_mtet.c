/* The marching-tetrahedra polygonizer on fields with known surfaces: a ball,
 * a tapered capsule, two capsules in PCM contact (a crease). Vertices lie on
 * the surface, the mesh is a closed 2-manifold of genus 0 wound outwards,
 * and the output fits merp_mtet_bound. */
#include "config.h"

#include <math.h>
#include <setjmp.h>
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

/* Two capsules deformed by PCM and joined: B1 of a junction. */
static float contact_fn(const float p[3], const void *data)
{
    const merp_seg *s = data;
    return merp_pcm_union(merp_seg_field(&s[0], p), merp_seg_field(&s[1], p), 0.15f);
}

static void polygonize(const merp_grid *g, merp_field_fn f, const void *data, mesh_out *o)
{
    uint64_t v, t;
    merp_mtet_bound(g, &v, &t);
    mesh_alloc(o, v, t);
    mer_error err;
    assert_int_equal(merp_mtet_polygonize(g, f, data, &o->m, &err), MER_OK);
    assert_true(o->m.vertex_count <= o->vmax && o->m.triangle_count <= o->tmax);
    assert_true(o->m.triangle_count > 100);
}

/* As assert_closed_genus0, enclosing `volume` within a fraction `tol`. */
static void assert_closed_sphere_like(const mesh_out *o, double volume, double tol)
{
    assert_closed_genus0(o);
    double v = tm_volume(o->m.positions, o->m.triangles, o->m.triangle_count);
    assert_true(fabs(v - volume) < tol * volume);
}

static const merp_grid grid_ball = {{-1.5f, -1.5f, -1.5f}, 0.1f, {30, 30, 30}, NULL};

static void ball(void **state)
{
    (void)state;
    const merp_seg s = {{0, 0, 0}, {0, 0, 0}, 1, 1};
    mesh_out o;
    polygonize(&grid_ball, seg_fn, &s, &o);
    for (uint32_t v = 0; v < o.m.vertex_count; v++) {
        const float *p = o.m.positions + 3 * v, *n = o.m.normals + 3 * v;
        float r = sqrtf(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        assert_float_equal(r, 1.0f, 1e-4);
        /* The normal points outwards: along p. */
        assert_true((p[0] * n[0] + p[1] * n[1] + p[2] * n[2]) / r > 0.999f);
    }
    assert_closed_sphere_like(&o, 4.0 / 3.0 * M_PI, 0.02);
    mesh_free(&o);
}

/* A tapered capsule: every vertex at distance r(t) from the segment. */
static void capsule(void **state)
{
    (void)state;
    const merp_seg s = {{0, -1, 0}, {0, 1, 0}, 0.6f, 0.3f};
    const merp_grid g = {{-0.9f, -1.9f, -0.9f}, 0.07f, {26, 54, 26}, NULL};
    mesh_out o;
    polygonize(&g, seg_fn, &s, &o);
    for (uint32_t v = 0; v < o.m.vertex_count; v++) {
        float t, d = merp_seg_distance(&s, o.m.positions + 3 * v, &t);
        assert_float_equal(d, (1 - t) * 0.6f + t * 0.3f, 2e-4);
    }
    /* Frustum of height 2 plus the two half balls, as the capsule's iso is
     * (nearly: the caps are the end radii's balls cut at the segment ends). */
    double vol = M_PI * 2 / 3 * (0.36 + 0.18 + 0.09) + 2.0 / 3 * M_PI * (0.216 + 0.027);
    assert_closed_sphere_like(&o, vol, 0.05);
    mesh_free(&o);
}

/* PCM contact of two crossing capsules: still one closed manifold, and the
 * vertices on the crease lie on the contact surface f1 = f2. */
static void contact_crease(void **state)
{
    (void)state;
    const merp_seg s[2] = {{{0, -1, 0}, {0, 1, 0}, 0.5f, 0.5f}, {{0, 0, 0}, {1, 1, 0}, 0.3f, 0.3f}};
    const merp_grid g = {{-1.2f, -1.8f, -1.2f}, 0.06f, {45, 60, 40}, NULL};
    mesh_out o;
    polygonize(&g, contact_fn, s, &o);
    assert_closed_genus0(&o);
    for (uint32_t v = 0; v < o.m.vertex_count; v++) {
        const float *p = o.m.positions + 3 * v;
        assert_float_equal(contact_fn(p, s), MERP_ISO, 2e-3);
    }
    mesh_free(&o);
}

/* Cut by the grid: the surface leaves through the grid's faces, so edges
 * there are open; the checker is not blind. */
static void open_when_cut(void **state)
{
    (void)state;
    const merp_seg s = {{0, -3, 0}, {0, 3, 0}, 0.5f, 0.5f};
    const merp_grid g = {{-1, -1, -1}, 0.1f, {20, 20, 20}, NULL};
    mesh_out o;
    polygonize(&g, seg_fn, &s, &o);
    size_t twice, edges;
    assert_true(tm_open_edges(o.m.triangles, o.m.triangle_count, &twice, &edges) > 0);
    mesh_free(&o);
}

/* A fork (parent axis, one lateral at 45°, the ridge fully grown): one closed
 * genus-0 surface, with vertices on the ridge (F_b = 1, where B1's crease is)
 * and on the blend (F_b = 0), all on F_g = c. */
static void fork(void **state)
{
    (void)state;
    merp_junction j = {
        .in = {{0, -1, 0}, {0, 0, 0}, 0.5f, 0.45f},
        .out = {{0, 0, 0}, {0, 1.2f, 0}, 0.45f, 0.4f},
        .lateral = {{{0, 0, 0}, {0.9f, 0.9f, 0}, 0.3f, 0.25f}},
        .laterals = 1,
        .w = 0.15f,
    };
    const float up[3] = {0, 1, 0};
    merp_junction_bound(&j, 0, up, 1.0f);
    const merp_grid g = {{-1.0f, -1.7f, -0.9f}, 0.04f, {60, 90, 45}, NULL};
    mesh_out o;
    polygonize(&g, merp_junction_field, &j, &o);
    assert_closed_genus0(&o);
    uint32_t ridge = 0, blend = 0;
    for (uint32_t v = 0; v < o.m.vertex_count; v++) {
        const float *p = o.m.positions + 3 * v;
        assert_float_equal(merp_junction_field(p, &j), MERP_ISO, 2e-3);
        float b = merp_junction_ridge(&j, p);
        ridge += b == 1.0f;
        blend += b == 0.0f;
    }
    assert_true(ridge > 10 && blend > o.m.vertex_count / 2);
    mesh_free(&o);
}

/* The walk from seeds finds the same surface as the dense march, and
 * evaluates only around it: two balls, one seeded, the other not reached. */
static void seeded_walk(void **state)
{
    (void)state;
    const merp_seg s = {{0, 0, 0}, {0, 0, 0}, 1, 1};
    mesh_out dense, walked;
    polygonize(&grid_ball, seg_fn, &s, &dense);
    walked.m = (merp_trimesh){.positions = malloc(dense.vmax * 3 * sizeof(float)),
                              .normals = malloc(dense.vmax * 3 * sizeof(float)),
                              .triangles = malloc(dense.tmax * 3 * sizeof(uint32_t))};
    const float seed[1][3] = {{0.05f, -0.3f, 0.2f}};
    mer_error err;
    assert_int_equal(merp_mtet_polygonize_seeded(&grid_ball, seg_fn, &s, seed, 1, &walked.m, &err), MER_OK);
    assert_int_equal(walked.m.vertex_count, dense.m.vertex_count);
    assert_int_equal(walked.m.triangle_count, dense.m.triangle_count);
    assert_closed_sphere_like(&walked, 4.0 / 3.0 * M_PI, 0.02);
    /* A second ball far from the seed is not reached. */
    const merp_seg two[2] = {{{-0.8f, 0, 0}, {-0.8f, 0, 0}, 0.5f, 0.5f}, {{0.8f, 0, 0}, {0.8f, 0, 0}, 0.5f, 0.5f}};
    const float left[1][3] = {{-0.8f, 0, 0}};
    assert_int_equal(merp_mtet_polygonize_seeded(&grid_ball, contact_fn, two, left, 1, &walked.m, &err), MER_OK);
    for (uint32_t v = 0; v < walked.m.vertex_count; v++)
        assert_true(walked.m.positions[3 * v] < 0.0f);
    assert_closed_genus0(&walked);
    mesh_free(&dense);
    mesh_free(&walked);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(ball),
        cmocka_unit_test(capsule),
        cmocka_unit_test(contact_crease),
        cmocka_unit_test(open_when_cut),
        cmocka_unit_test(fork),
        cmocka_unit_test(seeded_walk),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
