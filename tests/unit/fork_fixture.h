/* The fork of the junction patch's test and benchmark: a parent of radius
 * 0.5 (0.45 above the junction point J at the origin), a lateral of radius
 * 0.3 at 45° in the x–y plane, its ridge grown, each shaft cut with a ring
 * of `sides` vertices, polygonized on a box about them. */
#ifndef MERISTEM_TESTS_FORK_FIXTURE_H
#define MERISTEM_TESTS_FORK_FIXTURE_H

#include <math.h>
#include <stdint.h>

#include "core/vec.h"
#include "mesh/implicit/implicit.h"

#define FORK_MAX_SIDES 16

typedef struct fork_fixture {
    merp_junction j;
    float rings[3][FORK_MAX_SIDES * 3];
    float o[3][3], n[3][3], r[3]; /* each cut's centre, normal (away from J), ring radius */
    merp_patch pt;                /* its field is j: keep the fixture in place */
} fork_fixture;

/* A ring of `sides` vertices of radius r in the plane (o, n), turned by
 * `phase`, listed anticlockwise (dir 1) or clockwise (dir −1) about n. */
static inline void fork_ring(float *ring, uint32_t sides, const float o[3], const float n[3], float r, float phase,
                             int dir)
{
    float u[3], v[3];
    v3_any_perp(n, u);
    v3_cross(n, u, v);
    for (uint32_t j = 0; j < sides; j++) {
        float a = phase + (float)dir * MERP_TWO_PI * (float)j / (float)sides;
        for (int k = 0; k < 3; k++)
            ring[3 * j + k] = o[k] + r * (cosf(a) * u[k] + sinf(a) * v[k]);
    }
}

/* The fork with rings of `sides` (≤ FORK_MAX_SIDES) vertices (each turned
 * by 0.3 rad more than the last, the out ring clockwise: a patch takes any),
 * its grid cells of h over −0.8..1.8 × −1.4..1.9 × −0.8..0.8, moved by
 * `shift` (a grid plane tangent to a shaft is the polygonizers' worst case). */
static inline void fork_fixture_init(fork_fixture *f, uint32_t sides, float h, const float shift[3])
{
    const float s2 = 0.70710678f;
    *f = (fork_fixture){
        .j = {.in = {{0, -2.5f, 0}, {0, 0, 0}, 0.5f, 0.5f},
              .out = {{0, 0, 0}, {0, 2.5f, 0}, 0.45f, 0.45f},
              .lateral = {{{0, 0, 0}, {3 * s2, 3 * s2, 0}, 0.3f, 0.3f}},
              .laterals = 1,
              .w = 0.15f},
        .o = {{0, -1.3f, 0}, {0, 1.3f, 0}, {2 * s2, 2 * s2, 0}},
        .n = {{0, -1, 0}, {0, 1, 0}, {s2, s2, 0}},
        .r = {0.5f, 0.45f, 0.3f},
    };
    const float up[3] = {0, 1, 0};
    merp_junction_bound(&f->j, 0, up, 1.0f);
    f->pt = (merp_patch){.j = &f->j, .cuts = 3};
    f->pt.grid = (merp_grid){{-0.8f + shift[0], -1.4f + shift[1], -0.8f + shift[2]},
                             h,
                             {(uint32_t)ceilf(2.6f / h), (uint32_t)ceilf(3.3f / h), (uint32_t)ceilf(1.6f / h)},
                             NULL};
    for (int i = 0; i < 3; i++) {
        fork_ring(f->rings[i], sides, f->o[i], f->n[i], f->r[i], 0.3f * (float)i, i == 1 ? -1 : 1);
        f->pt.cut[i] = (merp_cut){{f->o[i][0], f->o[i][1], f->o[i][2]},
                                  {f->n[i][0], f->n[i][1], f->n[i][2]},
                                  1.5f * f->r[i],
                                  f->rings[i],
                                  sides,
                                  INFINITY};
    }
}

#endif
