/* Unit tests for triangle-mesh obstacles and marker volumes (lib/env/solid.c,
 * obstacles.c, volumes.c) and the growth-constraint accessor (lib/edit.c).
 *
 * The reference for a mesh cube is mer_scene_add_box with the same extent: where
 * no voxel centre and no marker lies on a face, the two must agree bit for bit
 * (markers kept, shadow grid, the grown tree). Faces are put at .1 to .4 of a
 * voxel from the voxel centres for that. */
#include "config.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include <meristem/edit.h>
#include <meristem/presets.h>
#include <meristem/rng.h>
#include <meristem/scene.h>

#include "scene_helpers.h"
#include "scene_private.h" /* s->env.shadow, s->rng and the merp_solid inside test */

/* ---- meshes built by hand ---- */

static void put_tri(float *out, const float *a, const float *b, const float *c, int flip)
{
    memcpy(out, a, 3 * sizeof *out);
    memcpy(out + 3, flip ? c : b, 3 * sizeof *out);
    memcpy(out + 6, flip ? b : c, 3 * sizeof *out);
}

/* 12 triangles, outward counter-clockwise unless `flip`. */
static void cube(const float lo[3], const float hi[3], int flip, float out[108])
{
    float v[8][3];
    for (int i = 0; i < 8; i++) {
        v[i][0] = (i & 1) ? hi[0] : lo[0];
        v[i][1] = (i & 2) ? hi[1] : lo[1];
        v[i][2] = (i & 4) ? hi[2] : lo[2];
    }
    static const int quads[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                    {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    for (int f = 0; f < 6; f++) {
        const int *q = quads[f];
        put_tri(out + 18 * f, v[q[0]], v[q[1]], v[q[2]], flip);
        put_tri(out + 18 * f + 9, v[q[0]], v[q[2]], v[q[3]], flip);
    }
}

/* |x - c| + |y - c| + |z - c| <= r: 8 triangles. */
static void octahedron(const float c[3], float r, int flip, float out[72])
{
    int t = 0;
    for (int sx = -1; sx <= 1; sx += 2)
        for (int sy = -1; sy <= 1; sy += 2)
            for (int sz = -1; sz <= 1; sz += 2) {
                float a[3] = {c[0] + (float)sx * r, c[1], c[2]};
                float b[3] = {c[0], c[1] + (float)sy * r, c[2]};
                float d[3] = {c[0], c[1], c[2] + (float)sz * r};
                /* outward when sx·sy·sz > 0 in this order; flip the others */
                int odd = sx * sy * sz < 0;
                put_tri(out + 9 * t++, a, b, d, flip ^ odd);
            }
}

static float octa_dist(const float c[3], float r, const float p[3])
{
    return fabsf(p[0] - c[0]) + fabsf(p[1] - c[1]) + fabsf(p[2] - c[2]) - r;
}

static merp_solid *solid(const float *xyz, size_t n)
{
    merp_solid *s = NULL;
    mer_error err;
    if (merp_solid_new(xyz, n, &s, &err) != MER_OK)
        fail_msg("merp_solid_new: %s", err.message);
    return s;
}

/* ---- the inside test ---- */

static void test_octahedron_inside(void **state)
{
    (void)state;
    const float c[3] = {1.0f, 2.0f, 3.0f};
    const float r = 2.0f;
    float tri[72], flipped[72];
    octahedron(c, r, 0, tri);
    octahedron(c, r, 1, flipped);
    merp_solid *s = solid(tri, 8), *f = solid(flipped, 8);
    /* Exactly the centre: every axis ray leaves through a vertex shared by four
     * faces; the tie rule must count it once. */
    assert_true(merp_solid_inside(s, c));
    const float out1[3] = {c[0] + 1.1f, c[1] + 1.0f, c[2]};
    const float in1[3] = {c[0] + 0.9f, c[1] + 1.0f, c[2]};
    assert_false(merp_solid_inside(s, out1));
    assert_true(merp_solid_inside(s, in1));
    mer_rng g;
    mer_rng_seed(&g, 7);
    int inside = 0, checked = 0;
    for (int i = 0; i < 40000; i++) {
        float p[3];
        for (int a = 0; a < 3; a++)
            p[a] = c[a] + mer_rng_range(&g, -1.3f, 1.3f) * r;
        float d = octa_dist(c, r, p);
        if (fabsf(d) < 1e-4f)
            continue;
        checked++;
        int want = d < 0.0f;
        inside += want;
        assert_int_equal(merp_solid_inside(s, p), want);
        assert_int_equal(merp_solid_inside(f, p), want); /* winding does not matter */
    }
    assert_true(inside > 1000 && checked - inside > 1000);
    /* Points on grid lines through the vertices and edges (ties everywhere). */
    for (int i = -12; i <= 12; i++)
        for (int j = -12; j <= 12; j++)
            for (int k = -12; k <= 12; k++) {
                float p[3] = {c[0] + 0.25f * (float)i, c[1] + 0.25f * (float)j,
                              c[2] + 0.25f * (float)k};
                float d = octa_dist(c, r, p);
                if (fabsf(d) < 1e-4f)
                    continue;
                assert_int_equal(merp_solid_inside(s, p), d < 0.0f);
                assert_int_equal(merp_solid_inside(f, p), d < 0.0f);
            }
    merp_solid_free(s);
    merp_solid_free(f);
}

static void test_tetrahedron_inside(void **state)
{
    (void)state;
    const float v[4][3] = {{0.1f, 0.2f, 0.3f}, {4.0f, 0.5f, -0.2f}, {1.0f, 3.7f, 0.4f},
                           {1.2f, 1.1f, 3.3f}};
    float tri[36];
    static const int face[4][3] = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
    for (int t = 0; t < 4; t++)
        put_tri(tri + 9 * t, v[face[t][0]], v[face[t][1]], v[face[t][2]], t == 2);
    merp_solid *s = solid(tri, 4);
    mer_rng g;
    mer_rng_seed(&g, 11);
    int inside = 0;
    for (int i = 0; i < 30000; i++) {
        float p[3];
        for (int a = 0; a < 3; a++)
            p[a] = mer_rng_range(&g, -0.5f, 4.5f);
        /* Barycentric signs, in double. */
        int want = 1;
        double margin = 1e9;
        for (int t = 0; t < 4; t++) {
            const float *a = v[face[t][0]], *b = v[face[t][1]], *c = v[face[t][2]];
            const float *o = v[6 - face[t][0] - face[t][1] - face[t][2]]; /* the fourth */
            double e1[3], e2[3], n[3];
            for (int k = 0; k < 3; k++) {
                e1[k] = (double)b[k] - (double)a[k];
                e2[k] = (double)c[k] - (double)a[k];
            }
            n[0] = e1[1] * e2[2] - e1[2] * e2[1];
            n[1] = e1[2] * e2[0] - e1[0] * e2[2];
            n[2] = e1[0] * e2[1] - e1[1] * e2[0];
            double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
            double dp = 0.0, dq = 0.0;
            for (int k = 0; k < 3; k++) {
                dp += n[k] * ((double)p[k] - (double)a[k]);
                dq += n[k] * ((double)o[k] - (double)a[k]);
            }
            if (dp * dq < 0.0)
                want = 0;
            margin = fmin(margin, fabs(dp) / len);
        }
        if (margin < 1e-4)
            continue;
        inside += want;
        assert_int_equal(merp_solid_inside(s, p), want);
    }
    assert_true(inside > 500);
    merp_solid_free(s);
}

/* A closed cube, the same cube wound the other way, and the cube with one
 * triangle missing (slightly open) all have the box's inside. */
static void test_cube_windings_and_holes(void **state)
{
    (void)state;
    const float lo[3] = {-1.3f, 0.7f, -2.1f}, hi[3] = {2.2f, 3.4f, 0.6f};
    float a[108], b[108];
    cube(lo, hi, 0, a);
    cube(lo, hi, 1, b);
    merp_solid *sa = solid(a, 12), *sb = solid(b, 12);
    /* Drop triangle 7 (half of the +y face): open. */
    float open[99];
    memcpy(open, a, 7 * 9 * sizeof *a);
    memcpy(open + 63, a + 72, 4 * 9 * sizeof *a);
    merp_solid *so = solid(open, 11);
    mer_rng g;
    mer_rng_seed(&g, 3);
    for (int i = 0; i < 30000; i++) {
        float p[3];
        float margin = 1e9f;
        int want = 1;
        for (int k = 0; k < 3; k++) {
            p[k] = mer_rng_range(&g, lo[k] - 1.0f, hi[k] + 1.0f);
            want &= p[k] >= lo[k] && p[k] <= hi[k];
            margin = fminf(margin, fminf(fabsf(p[k] - lo[k]), fabsf(p[k] - hi[k])));
        }
        if (margin < 1e-4f)
            continue;
        assert_int_equal(merp_solid_inside(sa, p), want);
        assert_int_equal(merp_solid_inside(sb, p), want);
        assert_int_equal(merp_solid_inside(so, p), want);
    }
    merp_solid_free(sa);
    merp_solid_free(sb);
    merp_solid_free(so);
}

/* A finely tessellated sphere (UV, fans at the poles): rays through the poles
 * and seams hit vertices shared by many triangles. Vertices come from integer
 * indices, so shared ones are bit-identical (watertight). */
static void uv_vertex(const float c[3], float r, int seg, int i, int j, float out[3])
{
    const double pi = 3.14159265358979323846;
    j %= 2 * seg;
    double th = pi * i / seg, ph = pi * j / seg;
    double st = (i == 0 || i == seg) ? 0.0 : sin(th);
    out[0] = c[0] + r * (float)(st * cos(ph));
    out[1] = c[1] + r * (float)(i == 0 ? 1.0 : i == seg ? -1.0 : cos(th));
    out[2] = c[2] + r * (float)(st * sin(ph));
}

static size_t uv_sphere(const float c[3], float r, int seg, float *out)
{
    size_t t = 0;
    for (int i = 0; i < seg; i++)
        for (int j = 0; j < 2 * seg; j++) {
            float q0[3], q1[3], q2[3], q3[3];
            uv_vertex(c, r, seg, i, j, q0);
            uv_vertex(c, r, seg, i, j + 1, q1);
            uv_vertex(c, r, seg, i + 1, j + 1, q2);
            uv_vertex(c, r, seg, i + 1, j, q3);
            if (i > 0)
                put_tri(out + 9 * t++, q0, q1, q2, 0);
            if (i < seg - 1)
                put_tri(out + 9 * t++, q0, q2, q3, 0);
            else
                put_tri(out + 9 * t++, q0, q1, q3, 0);
        }
    return t;
}

static void test_tessellated_sphere(void **state)
{
    (void)state;
    const int seg = 120;
    float *tri = malloc((size_t)seg * 2 * seg * 2 * 9 * sizeof *tri);
    assert_non_null(tri);
    const float c[3] = {0.0f, 10.0f, 0.0f};
    const float r = 4.0f;
    size_t n = uv_sphere(c, r, seg, tri);
    assert_true(n > 28000);
    merp_solid *s = solid(tri, n);
    assert_true(merp_solid_inside(s, c)); /* through the poles and seams */
    for (int a = 0; a < 3; a++) {
        float p[3] = {c[0], c[1], c[2]};
        for (int k = -40; k <= 40; k++) {
            p[a] = c[a] + 0.1f * (float)k; /* the axis lines, through the poles */
            float d = fabsf(p[a] - c[a]) - r;
            if (fabsf(d) > 0.01f)
                assert_int_equal(merp_solid_inside(s, p), d < 0.0f);
        }
    }
    mer_rng g;
    mer_rng_seed(&g, 5);
    for (int i = 0; i < 100000; i++) {
        float p[3];
        for (int a = 0; a < 3; a++)
            p[a] = c[a] + mer_rng_range(&g, -1.2f, 1.2f) * r;
        float d = sqrtf((p[0] - c[0]) * (p[0] - c[0]) + (p[1] - c[1]) * (p[1] - c[1]) +
                        (p[2] - c[2]) * (p[2] - c[2])) - r;
        if (fabsf(d) < 0.01f)
            continue; /* the facets lie up to r·(1 − cos(π/120)) inside */
        assert_int_equal(merp_solid_inside(s, p), d < 0.0f);
    }
    merp_solid_free(s);
    free(tri);
}

/* ---- a mesh cube against mer_scene_add_box ---- */

static void same_trees(const mer_scene *a, const mer_scene *b)
{
    assert_int_equal(mer_scene_node_bound(a), mer_scene_node_bound(b));
    for (uint32_t i = 0; i < mer_scene_node_bound(a); i++) {
        mer_node x, y;
        assert_int_equal(mer_scene_node(a, i, &x, NULL), MER_OK);
        assert_int_equal(mer_scene_node(b, i, &y, NULL), MER_OK);
        assert_memory_equal(&x, &y, sizeof x);
    }
}

static void same_markers(const mer_scene *a, const mer_scene *b)
{
    size_t n = mer_scene_marker_count(a);
    assert_int_equal(n, mer_scene_marker_count(b));
    float *pa = malloc((n + 1) * 3 * sizeof *pa), *pb = malloc((n + 1) * 3 * sizeof *pb);
    assert_non_null(pa);
    assert_non_null(pb);
    mer_scene_markers(a, pa, n);
    mer_scene_markers(b, pb, n);
    assert_memory_equal(pa, pb, n * 3 * sizeof *pa);
    free(pa);
    free(pb);
}

static void test_cube_acts_like_box_shadow(void **state)
{
    (void)state;
    mer_params p = mer_params_default(); /* shadow propagation, voxel 1, bounds from -50 */
    mer_scene *a = new_scene(&p, 1), *b = new_scene(&p, 1);
    const float c[3] = {0, 9, 0}, sz[3] = {7, 6, 7};
    mer_error err;
    assert_int_equal(mer_scene_fill_markers(a, MER_VOLUME_ELLIPSOID, c, sz, 6000, &err), MER_OK);
    assert_int_equal(mer_scene_fill_markers(b, MER_VOLUME_ELLIPSOID, c, sz, 6000, &err), MER_OK);
    /* Overhead, off-centre: it shades the young tree and stops its shoots. */
    const float lo[3] = {-2.3f, 6.2f, -4.6f}, hi[3] = {4.7f, 7.9f, 1.1f};
    float tri[108];
    cube(lo, hi, 0, tri);
    size_t before = mer_scene_marker_count(a);
    assert_int_equal(mer_scene_add_box(a, lo, hi, &err), MER_OK);
    assert_int_equal(mer_scene_add_mesh(b, tri, 12, &err), MER_OK);
    assert_true(mer_scene_marker_count(a) < before - 100);
    same_markers(a, b);
    assert_true(mer_shadow_hash(a->env.shadow) == mer_shadow_hash(b->env.shadow));
    int ijk[3] = {50, 7, 50}; /* inside: fully shaded */
    assert_true(mer_shadow_value(a->env.shadow, ijk) > p.shadow_c);
    assert_true(mer_shadow_value(a->env.shadow, ijk) == mer_shadow_value(b->env.shadow, ijk));
    for (int i = 0; i < 12; i++) {
        step(a, 1);
        step(b, 1);
        same_trees(a, b);
        assert_true(mer_shadow_hash(a->env.shadow) == mer_shadow_hash(b->env.shadow));
    }
    /* The tree met the obstacle: no internode ends inside it. */
    for (uint32_t i = 0; i < mer_scene_node_bound(b); i++) {
        mer_node n;
        mer_scene_node(b, i, &n, NULL);
        float e[3];
        for (int k = 0; k < 3; k++)
            e[k] = n.base[k] + n.dir[k] * n.length;
        assert_false(n.alive && merp_solid_inside(b->env.obs[0].solid, e));
    }
    /* Changing the shadow grid rebuilds it, mesh obstacles included. */
    p.voxel = 0.5f;
    assert_int_equal(mer_scene_set_params(a, &p, &err), MER_OK);
    assert_int_equal(mer_scene_set_params(b, &p, &err), MER_OK);
    assert_true(mer_shadow_hash(a->env.shadow) == mer_shadow_hash(b->env.shadow));
    mer_scene_free(a);
    mer_scene_free(b);
}

/* The small box of test_scene.c where the trunk's next end would be: blocked. */
static void test_cube_blocks_shoots(void **state)
{
    (void)state;
    mer_params p = mer_params_default();
    p.shadow_a = 0.2f;
    mer_scene *s = new_scene(&p, 0);
    const float lo[3] = {-0.3f, 2.2f, -0.3f}, hi[3] = {0.3f, 2.8f, 0.3f};
    float tri[108];
    cube(lo, hi, 1, tri);
    mer_error err;
    assert_int_equal(mer_scene_add_mesh(s, tri, 12, &err), MER_OK);
    step(s, 1);
    mer_node r;
    assert_int_equal(mer_scene_node(s, 0, &r, NULL), MER_OK);
    assert_int_equal(r.main_child, MER_NO_NODE);
    assert_int_equal(r.terminal_bud, MER_BUD_DORMANT);
    assert_int_equal(r.lateral_child[0], 1);
    /* A plant may not start inside it. */
    const float base[3] = {0.0f, 2.5f, 0.0f};
    assert_int_equal(mer_scene_add_plant(s, base, NULL, &err), MER_ERR_RANGE);
    mer_scene_free(s);
}

static void test_cube_acts_like_box_markers(void **state)
{
    (void)state;
    mer_params p;
    assert_int_equal(mer_preset_params("fig4-colonization", &p, NULL), MER_OK);
    mer_scene *a = new_scene(&p, 2), *b = new_scene(&p, 2);
    /* Through the marker cloud above the seedling. */
    const float lo[3] = {-1.6f, 6.3f, -2.7f}, hi[3] = {2.9f, 9.1f, 3.4f};
    float tri[108];
    cube(lo, hi, 0, tri);
    mer_error err;
    size_t before = mer_scene_marker_count(a);
    assert_int_equal(mer_scene_add_box(a, lo, hi, &err), MER_OK);
    assert_int_equal(mer_scene_add_mesh(b, tri, 12, &err), MER_OK);
    assert_true(mer_scene_marker_count(a) < before);
    same_markers(a, b);
    step(a, 14);
    step(b, 14);
    same_trees(a, b);
    same_markers(a, b);
    mer_summary m;
    mer_scene_summary(b, &m);
    assert_true(m.internodes > 30);
    mer_scene_free(a);
    mer_scene_free(b);
}

/* ---- marker volumes ---- */

static void test_fill_mesh_markers(void **state)
{
    (void)state;
    mer_params p = mer_params_default();
    p.environment = MER_ENV_MARKERS;
    p.marker_count = 0;
    const float c[3] = {0.5f, 7.0f, -0.5f};
    const float r = 6.0f;
    float tri[72];
    octahedron(c, r, 0, tri);
    mer_scene *s = new_scene(&p, 9);
    mer_error err;
    const uint32_t n = 8000;
    assert_int_equal(mer_scene_fill_mesh_markers(s, tri, 8, n, &err), MER_OK);
    assert_int_equal(mer_scene_marker_count(s), n);
    float *xyz = malloc((size_t)n * 3 * sizeof *xyz);
    assert_non_null(xyz);
    mer_scene_markers(s, xyz, n);
    merp_solid *so = solid(tri, 8);
    uint32_t inner = 0;
    double mean[3] = {0, 0, 0};
    for (uint32_t i = 0; i < n; i++) {
        const float *q = xyz + 3 * i;
        assert_true(octa_dist(c, r, q) <= 1e-4f);
        assert_true(merp_solid_inside(so, q));
        inner += octa_dist(c, 0.5f * r, q) <= 0.0f;
        for (int a = 0; a < 3; a++)
            mean[a] += (double)q[a] / n;
    }
    /* Uniform: the half-size octahedron holds 1/8 of the volume; the mean is the
     * centre. 8000 draws: σ = 0.0037 for the fraction. */
    assert_true(fabs((double)inner / n - 0.125) < 0.02);
    for (int a = 0; a < 3; a++)
        assert_true(fabs(mean[a] - (double)c[a]) < 0.15);
    merp_solid_free(so);
    free(xyz);

    /* Deterministic: same calls, same scene; another seed, other markers. */
    mer_scene *t = new_scene(&p, 9), *u = new_scene(&p, 10);
    assert_int_equal(mer_scene_fill_mesh_markers(t, tri, 8, n, &err), MER_OK);
    assert_int_equal(mer_scene_fill_mesh_markers(u, tri, 8, n, &err), MER_OK);
    assert_true(mer_scene_hash(s) == mer_scene_hash(t));
    assert_true(mer_scene_hash(s) != mer_scene_hash(u));
    step(s, 6);
    step(t, 6);
    assert_true(mer_scene_hash(s) == mer_scene_hash(t));
    mer_summary m;
    mer_scene_summary(s, &m);
    assert_true(m.internodes > 10); /* the volume is a marker cloud a tree grows into */
    mer_scene_free(s);
    mer_scene_free(t);
    mer_scene_free(u);
}

/* Markers of a volume that lie inside an obstacle are dropped. */
static void test_fill_mesh_markers_respects_obstacles(void **state)
{
    (void)state;
    mer_params p = mer_params_default();
    p.environment = MER_ENV_MARKERS;
    p.marker_count = 0;
    mer_scene *s = new_scene(&p, 4);
    const float lo[3] = {-3, 5, -3}, hi[3] = {3, 11, 3};
    float tri[108];
    cube(lo, hi, 0, tri);
    mer_error err;
    const float blo[3] = {-3.5f, 4.0f, -3.5f}, bhi[3] = {3.5f, 8.0f, 0.0f}; /* covers a quarter */
    assert_int_equal(mer_scene_add_box(s, blo, bhi, &err), MER_OK);
    assert_int_equal(mer_scene_fill_mesh_markers(s, tri, 12, 4000, &err), MER_OK);
    size_t m = mer_scene_marker_count(s);
    assert_true(m > 2600 && m < 3400); /* about 3/4 kept */
    /* The mesh as an obstacle too: nothing can live inside it any more. */
    assert_int_equal(mer_scene_add_mesh(s, tri, 12, &err), MER_OK);
    assert_int_equal(mer_scene_marker_count(s), 0);
    assert_int_equal(mer_scene_fill_mesh_markers(s, tri, 12, 100, &err), MER_OK);
    assert_int_equal(mer_scene_marker_count(s), 0);
    mer_scene_free(s);
}

/* ---- hashing and errors ---- */

static void test_mesh_hash(void **state)
{
    (void)state;
    mer_params p = mer_params_default();
    const float lo[3] = {5, 1, 5}, hi[3] = {8, 4, 9};
    float tri[108], moved[108];
    cube(lo, hi, 0, tri);
    memcpy(moved, tri, sizeof tri);
    moved[0] -= 0.25f; /* one vertex moved: another mesh */
    mer_scene *a = new_scene(&p, 0), *b = new_scene(&p, 0), *c = new_scene(&p, 0), *d = new_scene(&p, 0);
    uint64_t empty = mer_scene_hash(a);
    assert_int_equal(mer_scene_add_mesh(a, tri, 12, NULL), MER_OK);
    assert_int_equal(mer_scene_add_mesh(b, tri, 12, NULL), MER_OK);
    assert_int_equal(mer_scene_add_mesh(c, moved, 12, NULL), MER_OK);
    assert_int_equal(mer_scene_add_box(d, lo, hi, NULL), MER_OK);
    assert_true(mer_scene_hash(a) != empty);
    assert_true(mer_scene_hash(a) == mer_scene_hash(b));
    assert_true(mer_scene_hash(a) != mer_scene_hash(c));
    assert_true(mer_scene_hash(a) != mer_scene_hash(d));
    assert_true(mer_scene_hash(d) != empty); /* boxes count too */
    step(a, 5);
    step(b, 5);
    assert_true(mer_scene_hash(a) == mer_scene_hash(b));
    mer_scene_free(a);
    mer_scene_free(b);
    mer_scene_free(c);
    mer_scene_free(d);
}

static void test_mesh_errors(void **state)
{
    (void)state;
    mer_params p = mer_params_default();
    p.environment = MER_ENV_MARKERS;
    p.marker_count = 0;
    mer_scene *s = new_scene(&p, 0);
    uint64_t h0 = mer_scene_hash(s);
    const float lo[3] = {1, 1, 1}, hi[3] = {2, 2, 2};
    float tri[108];
    cube(lo, hi, 0, tri);
    mer_error err;
    assert_int_equal(mer_scene_add_mesh(s, tri, 0, &err), MER_ERR_INVALID);
    assert_string_equal(err.field, "triangles");
    assert_int_equal(mer_scene_add_mesh(s, NULL, 12, &err), MER_ERR_INVALID);
    assert_string_equal(err.field, "triangles");
    assert_int_equal(mer_scene_add_mesh(s, tri, (size_t)MER_MESH_TRIANGLES_MAX + 1, &err),
                     MER_ERR_LIMIT);
    assert_string_equal(err.field, "triangles");
    float bad[108];
    memcpy(bad, tri, sizeof bad);
    bad[40] = NAN;
    assert_int_equal(mer_scene_add_mesh(s, bad, 12, &err), MER_ERR_INVALID);
    assert_string_equal(err.field, "xyz");
    bad[40] = INFINITY;
    assert_int_equal(mer_scene_fill_mesh_markers(s, bad, 12, 10, &err), MER_ERR_INVALID);
    assert_string_equal(err.field, "xyz");
    bad[40] = -2e6f;
    assert_int_equal(mer_scene_add_mesh(s, bad, 12, &err), MER_ERR_RANGE);
    assert_string_equal(err.field, "xyz");
    /* Flat: no volume. */
    const float flat[9] = {0, 1, 0, 1, 1, 0, 0, 1, 1};
    assert_int_equal(mer_scene_add_mesh(s, flat, 1, &err), MER_ERR_RANGE);
    assert_string_equal(err.field, "xyz");
    assert_int_equal(mer_scene_fill_mesh_markers(s, tri, 12, MER_MESH_FILL_MAX + 1, &err),
                     MER_ERR_LIMIT);
    assert_string_equal(err.field, "count");
    /* A lone slanted triangle has a box but no inside: the draws run out, and
     * nothing changes, the generator included. */
    const float sheet[9] = {0, 1, 0, 1, 1, 0, 0, 2, 1};
    assert_int_equal(mer_scene_fill_mesh_markers(s, sheet, 1, 50, &err), MER_ERR_RANGE);
    assert_string_equal(err.field, "xyz");
    assert_int_equal(mer_scene_marker_count(s), 0);
    assert_true(mer_scene_hash(s) == h0);
    assert_int_equal(mer_scene_fill_mesh_markers(s, tri, 12, 0, &err), MER_OK);
    assert_true(mer_scene_hash(s) == h0);
    /* The obstacle limit counts meshes. */
    for (unsigned i = 0; i < MER_OBSTACLES_MAX; i++) {
        const float c[3] = {30.0f, 50.0f, 30.0f};
        assert_int_equal(mer_scene_add_sphere(s, c, 0.5f, NULL), MER_OK);
    }
    assert_int_equal(mer_scene_add_mesh(s, tri, 12, &err), MER_ERR_LIMIT);
    assert_string_equal(err.field, "obstacles");
    mer_scene_free(s);
}

/* ---- the constraint accessor ---- */

static void test_constraint_accessor(void **state)
{
    (void)state;
    mer_params p = mer_params_default();
    p.shadow_a = 0.2f;
    mer_scene *s = new_scene(&p, 0);
    uint32_t node = 77, slot = 77;
    assert_int_equal(mer_scene_constraint(s, &node, &slot), 0);
    assert_int_equal(node, 77);
    assert_int_equal(slot, 77);
    step(s, 2);
    mer_error err;
    assert_int_equal(mer_scene_constrain(s, 1, 0, &err), MER_OK);
    assert_int_equal(mer_scene_constraint(s, &node, &slot), 1);
    assert_int_equal(node, 1);
    assert_int_equal(slot, 0);
    assert_int_equal(mer_scene_constraint(s, NULL, NULL), 1);
    assert_int_equal(mer_scene_constrain(s, 0, 1, &err), MER_OK); /* grown out: allowed */
    assert_int_equal(mer_scene_constraint(s, &node, &slot), 1);
    assert_int_equal(node, 0);
    assert_int_equal(slot, 1);
    /* A refused constraint leaves the old one. */
    assert_int_equal(mer_scene_constrain(s, 0, 5, &err), MER_ERR_RANGE);
    assert_int_equal(mer_scene_constraint(s, &node, &slot), 1);
    assert_int_equal(node, 0);
    assert_int_equal(slot, 1);
    mer_scene_unconstrain(s);
    assert_int_equal(mer_scene_constraint(s, &node, &slot), 0);
    /* Pruning the constrained node lifts it. */
    assert_int_equal(mer_scene_constrain(s, 1, 0, &err), MER_OK);
    assert_int_equal(mer_scene_prune(s, 1, &err), MER_OK);
    assert_int_equal(mer_scene_constraint(s, &node, &slot), 0);
    mer_scene_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_octahedron_inside),
        cmocka_unit_test(test_tetrahedron_inside),
        cmocka_unit_test(test_cube_windings_and_holes),
        cmocka_unit_test(test_tessellated_sphere),
        cmocka_unit_test(test_cube_acts_like_box_shadow),
        cmocka_unit_test(test_cube_blocks_shoots),
        cmocka_unit_test(test_cube_acts_like_box_markers),
        cmocka_unit_test(test_fill_mesh_markers),
        cmocka_unit_test(test_fill_mesh_markers_respects_obstacles),
        cmocka_unit_test(test_mesh_hash),
        cmocka_unit_test(test_mesh_errors),
        cmocka_unit_test(test_constraint_accessor),
    };
    return cmocka_run_group_tests_name("obstacles", tests, NULL, NULL);
}
