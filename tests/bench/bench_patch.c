/* meristem benchmark: one implicit junction patch (issue 18, item 2). Builds
 * the patch of a fork (a parent of radius 0.5, a lateral of radius 0.3 at 45°,
 * the ridge grown) with its three cuts and rings, many times, and prints the
 * best and median CPU time of the thread per patch (a shared machine
 * deschedules a wall clock away), for the grid spacings given as cells per
 * parent radius. Not a test: nothing here passes or fails on time.
 *
 *   tests/bench/bench_patch [RUNS] [CELLS_PER_RADIUS...]   (default 200 10 5 4 3)
 */
#include "config.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/vec.h"
#include "mesh/implicit/implicit.h"

enum { SIDES = 12 };

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static void make_ring(float *ring, const float o[3], const float n[3], float r)
{
    float u[3], v[3];
    v3_any_perp(n, u);
    v3_cross(n, u, v);
    for (int j = 0; j < SIDES; j++) {
        float a = MERP_TWO_PI * (float)j / SIDES;
        for (int k = 0; k < 3; k++)
            ring[3 * j + k] = o[k] + r * (cosf(a) * u[k] + sinf(a) * v[k]);
    }
}

int main(int argc, char **argv)
{
    int runs = argc > 1 ? atoi(argv[1]) : 200;
    float rho_default[] = {10, 5, 4, 3};
    int nrho = argc > 2 ? argc - 2 : 4;
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
    double *t = malloc((size_t)runs * sizeof *t);
    printf("%-18s %10s %10s %8s %8s\n", "cells/radius", "best ms", "median ms", "verts", "tris");
    for (int q = 0; q < nrho; q++) {
        float rho = argc > 2 ? strtof(argv[2 + q], NULL) : rho_default[q];
        float h = 0.5f / rho;
        merp_patch pt = {.j = &j, .cuts = 3};
        for (int i = 0; i < 3; i++) {
            make_ring(rings[i], o[i], n[i], r[i]);
            pt.cut[i] = (merp_cut){{o[i][0], o[i][1], o[i][2]}, {n[i][0], n[i][1], n[i][2]}, 1.5f * r[i],
                                   rings[i], SIDES};
        }
        /* The test's box, -0.8..1.8 × -1.4..1.9 × -0.8..0.8, in cells of h. */
        pt.grid = (merp_grid){{-0.8f, -1.4f, -0.8f}, h,
                              {(uint32_t)ceilf(2.6f / h), (uint32_t)ceilf(3.3f / h), (uint32_t)ceilf(1.6f / h)}};
        uint64_t vmax, tmax;
        merp_patch_bound(&pt, &vmax, &tmax);
        merp_trimesh m = {0, 0, malloc(vmax * 3 * sizeof(float)), malloc(vmax * 3 * sizeof(float)),
                          malloc(tmax * 3 * sizeof(uint32_t))};
        mer_error err;
        for (int i = 0; i < runs; i++) {
            double t0 = now();
            if (merp_patch_build(&pt, &m, &err) != MER_OK) {
                fprintf(stderr, "bench_patch: %s\n", err.message);
                return 1;
            }
            t[i] = now() - t0;
        }
        qsort(t, (size_t)runs, sizeof *t, cmp_double);
        printf("%-18.1f %10.3f %10.3f %8u %8u\n", (double)rho, 1e3 * t[0], 1e3 * t[runs / 2], m.vertex_count,
               m.triangle_count);
        free(m.positions), free(m.normals), free(m.triangles);
    }
    free(t);
    return 0;
}
