/* A junction's patch stitched to its shafts' rings: with a tube stub on each
 * ring (sharing its vertices' positions), the whole is one closed 2-manifold,
 * consistently wound, genus 0: no boundary edge is left between patch and
 * tube. */
#include "config.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "core/vec.h"
#include "mesh/implicit/implicit.h"
#include "trimesh_check.h"

enum { SIDES = 9, STUBS_V = 3 * (2 * SIDES + 1), STUBS_T = 3 * 3 * SIDES };

/* The patch and the stubs, in arrays sized from merp_patch_bound. */
typedef struct soup {
    float *pos;
    uint32_t vn, tn;
    uint32_t *tri;
} soup;

/* A ring of SIDES vertices of radius r in the plane (o, n), turned by `phase`,
 * listed clockwise or anticlockwise as `dir` says. */
static void make_ring(float *ring, const float o[3], const float n[3], float r, float phase, int dir)
{
    float u[3], v[3];
    v3_any_perp(n, u);
    v3_cross(n, u, v);
    for (int j = 0; j < SIDES; j++) {
        float a = phase + (float)dir * MERP_TWO_PI * (float)j / SIDES;
        for (int k = 0; k < 3; k++)
            ring[3 * j + k] = o[k] + r * (cosf(a) * u[k] + sinf(a) * v[k]);
    }
}

static uint32_t add_vertex(soup *s, const float p[3])
{
    memcpy(s->pos + 3 * s->vn, p, 3 * sizeof(float));
    return s->vn++;
}

/* Adds triangle (a, b, c) facing along `out` (outwards). */
static void add_facing(soup *s, uint32_t a, uint32_t b, uint32_t c, const float out[3])
{
    const float *pa = s->pos + 3 * a, *pb = s->pos + 3 * b, *pc = s->pos + 3 * c;
    float e1[3], e2[3], n[3];
    for (int k = 0; k < 3; k++)
        e1[k] = pb[k] - pa[k], e2[k] = pc[k] - pa[k];
    v3_cross(e1, e2, n);
    uint32_t *t = s->tri + 3 * s->tn++;
    t[0] = a;
    t[1] = v3_dot(n, out) >= 0 ? b : c;
    t[2] = v3_dot(n, out) >= 0 ? c : b;
}

/* A tube stub from `ring` one unit along n, closed by a flat cap. */
static void add_stub(soup *s, const float *ring, const float o[3], const float n[3])
{
    uint32_t r0 = s->vn, r1, centre;
    for (int j = 0; j < SIDES; j++)
        add_vertex(s, ring + 3 * j);
    r1 = s->vn;
    for (int j = 0; j < SIDES; j++) {
        const float p[3] = {ring[3 * j] + n[0], ring[3 * j + 1] + n[1], ring[3 * j + 2] + n[2]};
        add_vertex(s, p);
    }
    const float c[3] = {o[0] + n[0], o[1] + n[1], o[2] + n[2]};
    centre = add_vertex(s, c);
    for (uint32_t j = 0; j < SIDES; j++) {
        uint32_t k = (j + 1) % SIDES;
        float out[3];
        for (int a = 0; a < 3; a++)
            out[a] = ring[3 * j + a] + ring[3 * k + a] - 2 * o[a];
        add_facing(s, r0 + j, r0 + k, r1 + k, out);
        add_facing(s, r0 + j, r1 + k, r1 + j, out);
        add_facing(s, centre, r1 + j, r1 + k, n);
    }
}

/* Welds each vertex from `first` on to an earlier one of equal position (the
 * stubs' rings to the patch's copies); returns how many vertices are used. */
static uint32_t weld(soup *s, uint32_t first)
{
    uint32_t *canon = malloc(s->vn * sizeof *canon), used = 0;
    uint8_t *seen = calloc(s->vn, 1);
    for (uint32_t v = 0; v < s->vn; v++) {
        canon[v] = v;
        /* The ring copies are the patch's last vertices; a loop vertex may
         * sit on a ring vertex too, so search from the end. */
        for (uint32_t w = first; w-- > 0 && v >= first;)
            if (memcmp(s->pos + 3 * v, s->pos + 3 * w, 3 * sizeof(float)) == 0) {
                canon[v] = w;
                break;
            }
    }
    for (uint32_t k = 0; k < 3 * s->tn; k++) {
        s->tri[k] = canon[s->tri[k]];
        used += !seen[s->tri[k]];
        seen[s->tri[k]] = 1;
    }
    free(canon);
    free(seen);
    return used;
}

static void fork_patch(void **state)
{
    (void)state;
    const float s2 = 0.70710678f;
    merp_junction j = {
        .in = {{0, -2.5f, 0}, {0, 0, 0}, 0.5f, 0.5f},
        .out = {{0, 0, 0}, {0, 2.5f, 0}, 0.45f, 0.45f},
        .lateral = {{{0, 0, 0}, {3 * s2, 3 * s2, 0}, 0.3f, 0.3f}},
        .laterals = 1,
        .w = 0.15f,
    };
    const float up[3] = {0, 1, 0};
    merp_junction_bound(&j, 0, up, 1.0f);
    static float rings[3][SIDES * 3];
    const float o[3][3] = {{0, -1.3f, 0}, {0, 1.3f, 0}, {2 * s2, 2 * s2, 0}};
    const float n[3][3] = {{0, -1, 0}, {0, 1, 0}, {s2, s2, 0}};
    const float r[3] = {0.5f, 0.45f, 0.3f};
    merp_patch pt = {.j = &j, .cuts = 3, .grid = {{-0.8f, -1.4f, -0.8f}, 0.05f, {52, 66, 32}}};
    for (int i = 0; i < 3; i++) {
        make_ring(rings[i], o[i], n[i], r[i], 0.3f * (float)i, i == 1 ? -1 : 1);
        pt.cut[i] = (merp_cut){{o[i][0], o[i][1], o[i][2]}, {n[i][0], n[i][1], n[i][2]}, 1.5f * r[i],
                               rings[i], SIDES};
    }
    uint64_t vmax, tmax;
    merp_patch_bound(&pt, &vmax, &tmax);
    soup *s = calloc(1, sizeof *s);
    s->pos = malloc((vmax + STUBS_V) * 3 * sizeof(float));
    s->tri = malloc((tmax + STUBS_T) * 3 * sizeof(uint32_t));
    merp_trimesh m = {0, 0, s->pos, malloc(vmax * 3 * sizeof(float)), s->tri};
    mer_error err;
    if (merp_patch_build(&pt, &m, &err) != MER_OK)
        fail_msg("%s", err.message);
    s->vn = m.vertex_count, s->tn = m.triangle_count;
    /* Alone, the patch is open exactly along its three rings. */
    size_t twice, edges;
    assert_int_equal(tm_open_edges(s->tri, s->tn, &twice, &edges), 3 * SIDES);
    assert_int_equal(twice, 0);
    uint32_t patch_vertices = s->vn;
    for (int i = 0; i < 3; i++)
        add_stub(s, rings[i], o[i], n[i]);
    uint32_t used = weld(s, patch_vertices);
    assert_int_equal(tm_open_edges(s->tri, s->tn, &twice, &edges), 0);
    assert_int_equal(twice, 0);
    assert_int_equal((long)used - (long)edges + (long)s->tn, 2);
    assert_true(tm_volume(s->pos, s->tri, s->tn) > 0);
    free(m.normals);
    free(s->pos);
    free(s->tri);
    free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(fork_patch),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
