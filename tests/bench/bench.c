/* meristem benchmark: the Table 1 workloads of Palubicki et al. 2009 and the space
 * colonization workload of issue 3. Prints one line per workload: steps, internodes,
 * seconds of stepping (wall, and the process's CPU time), internodes per second,
 * peak memory. A workload stops at the paper's step count or as soon as the tree
 * has the paper's number of internodes, whichever comes first. Not a test: nothing here passes or
 * fails on time. Run as `make bench`, or `tests/bench/bench [NAME]`; each workload
 * is best run in its own process so that the peak memory is its own. */
#include "config.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>

#include <meristem.h>

typedef struct workload {
    const char *name;
    const char *preset;
    uint32_t steps;       /* the paper's step count (or a cap) */
    uint32_t internodes;  /* stop once the tree has this many (the paper's size) */
    int markers;          /* 1: space colonization with 1,000,000 markers */
} workload;

static const workload workloads[] = {
    {"table1-fig10-left", "fig10-left", 106, 700000, 0},
    {"table1-fig10-center", "fig10-center", 90, 642000, 0},
    {"table1-fig10-right", "fig10-right", 68, 225000, 0},
    {"colonization-1M-markers", "fig4-colonization", 200, 700000, 1},
};

#define NWORK (sizeof workloads / sizeof workloads[0])

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int run(const workload *w)
{
    mer_params p;
    mer_error err;
    if (mer_preset_params(w->preset, &p, &err) != MER_OK) {
        fprintf(stderr, "bench: %s\n", err.message);
        return 1;
    }
    /* The paper's 200 × 200 × 200 grid, cells about one internode long. */
    p.bounds_min[0] = -100.0f;
    p.bounds_min[1] = 0.0f;
    p.bounds_min[2] = -100.0f;
    p.bounds_max[0] = 100.0f;
    p.bounds_max[1] = 200.0f;
    p.bounds_max[2] = 100.0f;
    if (w->markers) {
        p.marker_count = 1000000;
        p.marker_volume = MER_VOLUME_ELLIPSOID;
        /* an ellipsoid filling the grid, from just above the seedling's bud */
        p.marker_center[1] = 99.5f;
        p.marker_size[0] = p.marker_size[2] = 99.0f;
        p.marker_size[1] = 98.0f;
        /* marker grid cells of edge r (the default); MER_BENCH_CELL overrides it */
        if (getenv("MER_BENCH_CELL") != NULL)
            p.marker_cell = (float)atof(getenv("MER_BENCH_CELL"));
    }
    mer_scene *s;
    if (mer_scene_new(&p, 1, &s, &err) != MER_OK) {
        fprintf(stderr, "bench: %s\n", err.message);
        return 1;
    }
    mer_summary m;
    uint32_t steps = 0;
    double t1 = now();
    for (; steps < w->steps; steps++) {
        if (mer_scene_step(s, 1, NULL, NULL, NULL, NULL, &err) != MER_OK) {
            fprintf(stderr, "bench: %s\n", err.message);
            mer_scene_free(s);
            return 1;
        }
        /* no shedding or pruning here, so ids issued = internodes (cheaper than a summary) */
        if (mer_scene_node_bound(s) >= w->internodes) {
            steps++;
            break;
        }
    }
    double secs = now() - t1;
    mer_scene_summary(s, &m);
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    /* CPU time of the whole process (set-up included): steadier than wall time on
     * a shared machine. */
    double cpu = (double)ru.ru_utime.tv_sec + 1e-6 * (double)ru.ru_utime.tv_usec +
                 (double)ru.ru_stime.tv_sec + 1e-6 * (double)ru.ru_stime.tv_usec;
    printf("%-24s steps %4u  internodes %7u  seconds %6.3f (cpu %6.3f)  internodes/s %7.0f  "
           "peak %6.1f MB  height %.0f  width %.0f\n",
           w->name, steps, m.internodes, secs, cpu,
           secs > 0 ? (double)m.internodes / secs : 0.0, (double)ru.ru_maxrss / 1024.0,
           (double)m.height, (double)m.crown_width);
    mer_scene_free(s);
    return 0;
}

int main(int argc, char **argv)
{
    int rc = 0, any = 0;
    for (size_t i = 0; i < NWORK; i++) {
        if (argc > 1 && strcmp(argv[1], workloads[i].name) != 0)
            continue;
        any = 1;
        rc |= run(&workloads[i]);
        fflush(stdout);
    }
    if (!any) {
        fprintf(stderr, "bench: unknown workload '%s'; one of:", argv[1]);
        for (size_t i = 0; i < NWORK; i++)
            fprintf(stderr, " %s", workloads[i].name);
        fprintf(stderr, "\n");
        return 2;
    }
    return rc;
}
