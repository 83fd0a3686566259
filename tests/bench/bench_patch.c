/* meristem benchmark: one implicit junction patch (issue 18, item 2). Builds
 * the patch of a fork (a parent of radius 0.5, a lateral of radius 0.3 at 45°,
 * the ridge grown) with its three cuts and rings, many times, by marching
 * tetrahedra and by dual contouring, and prints the
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

#include "../unit/fork_fixture.h"

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

int main(int argc, char **argv)
{
    int runs = argc > 1 ? atoi(argv[1]) : 200;
    float rho_default[] = {10, 5, 4, 3};
    int nrho = argc > 2 ? argc - 2 : 4;
    double *t = malloc((size_t)runs * sizeof *t);
    printf("%-18s %-6s %10s %10s %8s %8s\n", "cells/radius", "poly", "best ms", "median ms", "verts", "tris");
    for (int q = 0; q < 2 * nrho; q++) {
        uint32_t sharp = (uint32_t)(q % 2);
        float rho = argc > 2 ? strtof(argv[2 + q / 2], NULL) : rho_default[q / 2];
        float h = 0.5f / rho;
        static fork_fixture f;
        const float shift[3] = {0.0123f, 0.0077f, 0.0131f}; /* no grid plane tangent to a shaft */
        fork_fixture_init(&f, SIDES, h, shift);
        f.pt.sharp = sharp;
        const merp_patch pt = f.pt;
        uint64_t vmax, tmax;
        merp_patch_bound(&pt, &vmax, &tmax);
        merp_trimesh m = {.positions = malloc(vmax * 3 * sizeof(float)),
                          .normals = malloc(vmax * 3 * sizeof(float)),
                          .triangles = malloc(tmax * 3 * sizeof(uint32_t))};
        mer_error err;
        int built = 1;
        for (int i = 0; built && i < runs; i++) {
            double t0 = now();
            built = merp_patch_build(&pt, &m, &err) == MER_OK;
            t[i] = now() - t0;
        }
        if (built) {
            qsort(t, (size_t)runs, sizeof *t, cmp_double);
            printf("%-18.1f %-6s %10.3f %10.3f %8u %8u\n", (double)rho, sharp ? "DC" : "mtet", 1e3 * t[0],
                   1e3 * t[runs / 2], m.vertex_count, m.triangle_count);
        } else {
            /* A patch that does not close leaves its fork as tubes when a tree is
             * meshed (joints.c): a figure of its own, not a failed benchmark. */
            printf("%-18.1f %-6s  not built: %s\n", (double)rho, sharp ? "DC" : "mtet", err.message);
        }
        free(m.positions), free(m.normals), free(m.triangles);
    }
    free(t);
    return 0;
}
