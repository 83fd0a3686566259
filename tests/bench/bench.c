/* meristem benchmark: the Table 1 workloads of Palubicki et al. 2009 (§6), space
 * colonization with a million markers (P09's and Runions et al. 2007's), a
 * forest of 100 trees growing together, a sown forest of 100 trees of four
 * presets (scene.sow: P09's BH trees, space colonization in Voronoi cells, an
 * L-system), and a guiding-vector tree of about
 * 4,000 endpoints (Xu & Mould 2015's Fig. 4, its six iterations in its own
 * crown).
 * Each workload grows until it has its number of internodes (the paper's, for
 * Table 1) and prints how many steps that took beside the paper's step count, so
 * the figures read the same whatever pace the presets grow at. Columns:
 * internodes, steps, seconds of stepping (the process's CPU time, steadier than
 * wall time on a shared machine: the minimum and median of the runs; and the
 * wall time of the fastest run), internodes per second (at the minimum), peak
 * memory (getrusage maxrss; each run grows in a process of its own), and the
 * scene's hash, so that a change meant to keep the output can be checked at
 * this scale too. Not a test: nothing here passes or fails on time. Run as
 * `make bench`, or `tests/bench/bench [NAME [RUNS]]`. */
#include "config.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <meristem.h>

#define GRID 200        /* the paper's grid: 200 × 200 × 200 voxels (§6) */
#define STEP_CAP 1000u  /* a workload that has not reached its size by then fails */
#define RUNS_MAX 64

typedef struct workload {
    const char *name;
    const char *preset;
    uint32_t paper_steps; /* the paper's step count (0: none given) */
    uint32_t internodes;  /* grow until the scene has this many */
    uint32_t markers;     /* > 0: space colonization with this many markers */
    uint32_t trees;       /* > 1: a square lattice of this many plants */
    uint32_t steps;       /* > 0: grow this many steps, in the preset's own bounds */
    const char *sow;      /* a forest's definition (the preset is then unused) */
} workload;

#define SOWN "area -45 -45 45 45\ncount 100\nmin_distance 7\nseed 1\n" \
             "presets default fig7-bh-0.54 fig4-colonization abop-1.24b\n"

static const workload workloads[] = {
    {"table1-left", "table1-left", 106, 700000, 0, 1, 0, NULL},
    {"table1-center", "table1-center", 90, 642000, 0, 1, 0, NULL},
    {"table1-right", "table1-right", 68, 225000, 0, 1, 0, NULL},
    {"colonization-1M-markers", "fig4-colonization", 0, 500000, 1000000, 1, 0, NULL},
    {"forest-100-trees", "default", 0, 500000, 0, 100, 0, NULL},
    {"runions-1M-markers", "runions-2007", 0, 50000, 1000000, 1, 0, NULL},
    {"guiding-4000-endpoints", "gv-fig4-4000", 0, 10000, 0, 1, 6, NULL},
    {"forest-100-sown", "default", 0, 20000, 0, 1, 12, SOWN},
};

#define NWORK (sizeof workloads / sizeof workloads[0])

typedef struct outcome {
    uint32_t steps, internodes;
    double secs, wall;
    float height, width;
    uint64_t hash;
} outcome;

static double now(clockid_t clock)
{
    struct timespec ts;
    clock_gettime(clock, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The paper's 200³ grid with the preset's voxel (about one internode long),
 * centred on the origin in x and z, from the ground up. */
static void paper_grid(mer_params *p)
{
    float half = 0.5f * GRID * p->voxel;
    p->bounds_min[0] = p->bounds_min[2] = -half;
    p->bounds_max[0] = p->bounds_max[2] = half;
    p->bounds_min[1] = 0.0f;
    p->bounds_max[1] = GRID * p->voxel;
    /* The marker grid has as many cells as the shadow grid, or fewer. */
    if (p->marker_cell < p->voxel)
        p->marker_cell = p->voxel;
}

static mer_result make_scene(const workload *w, mer_scene **out, mer_error *err)
{
    mer_params p;
    mer_result rc = mer_preset_params(w->preset, &p, err);
    if (rc != MER_OK)
        return rc;
    if (w->sow != NULL) {
        p.model = MER_MODEL_FOREST;
        p.seedlings = 0;
        p.environment = MER_ENV_MARKERS;
        p.marker_count = 0;
        rc = mer_scene_new(&p, 1, out, err);
        if (rc == MER_OK && (rc = mer_scene_set_definition(*out, w->sow, strlen(w->sow), err)) != MER_OK) {
            mer_scene_free(*out);
            *out = NULL;
        }
        return rc;
    }
    if (w->steps == 0)
        paper_grid(&p);
    if (w->markers > 0) {
        p.marker_count = w->markers;
        p.marker_volume = MER_VOLUME_ELLIPSOID;
        /* an ellipsoid filling the grid, from just above the seedling's bud */
        float half = 0.5f * GRID * p.voxel;
        p.marker_center[0] = p.marker_center[2] = 0.0f;
        p.marker_center[1] = half - 0.5f * p.voxel;
        p.marker_size[0] = p.marker_size[2] = half - p.voxel;
        p.marker_size[1] = half - 2.0f * p.voxel;
        /* marker grid cells of edge r (the default); MER_BENCH_CELL overrides it */
        if (getenv("MER_BENCH_CELL") != NULL)
            p.marker_cell = (float)atof(getenv("MER_BENCH_CELL"));
    }
    if (w->trees > 1)
        p.seedlings = 0;
    rc = mer_scene_new(&p, 1, out, err);
    if (rc != MER_OK || w->trees <= 1)
        return rc;
    /* A square lattice filling the ground, a cell per tree, trunks at the cells'
     * centres. */
    uint32_t side = 1;
    while (side * side < w->trees)
        side++;
    float extent = GRID * p.voxel, cell = extent / (float)side;
    for (uint32_t t = 0; t < w->trees && rc == MER_OK; t++) {
        float base[3] = {-0.5f * extent + cell * ((float)(t % side) + 0.5f), 0.0f,
                         -0.5f * extent + cell * ((float)(t / side) + 0.5f)};
        rc = mer_scene_add_plant(*out, base, NULL, err);
    }
    if (rc != MER_OK) {
        mer_scene_free(*out);
        *out = NULL;
    }
    return rc;
}

static int grow(const workload *w, outcome *o)
{
    mer_error err;
    mer_scene *s;
    if (make_scene(w, &s, &err) != MER_OK) {
        fprintf(stderr, "bench: %s: %s\n", w->name, err.message);
        return 1;
    }
    uint32_t steps = 0;
    double t1 = now(CLOCK_PROCESS_CPUTIME_ID), w1 = now(CLOCK_MONOTONIC);
    /* no shedding or pruning here, so ids issued = internodes (cheaper than a summary) */
    while (w->steps > 0 ? steps < w->steps
                        : mer_scene_node_bound(s) < w->internodes && steps < STEP_CAP) {
        if (mer_scene_step(s, 1, NULL, NULL, NULL, NULL, &err) != MER_OK) {
            fprintf(stderr, "bench: %s: %s\n", w->name, err.message);
            mer_scene_free(s);
            return 1;
        }
        steps++;
    }
    o->secs = now(CLOCK_PROCESS_CPUTIME_ID) - t1;
    o->wall = now(CLOCK_MONOTONIC) - w1;
    mer_summary m;
    mer_scene_summary(s, &m);
    o->hash = mer_scene_hash(s);
    mer_scene_free(s);
    o->steps = steps;
    o->internodes = m.internodes;
    o->height = m.height;
    o->width = m.crown_width;
    if (m.internodes < w->internodes) {
        fprintf(stderr, "bench: %s: only %u internodes after %u steps\n", w->name,
                m.internodes, steps);
        return 1;
    }
    return 0;
}

static int by_secs(const void *a, const void *b)
{
    double x = ((const outcome *)a)->secs, y = ((const outcome *)b)->secs;
    return (x > y) - (x < y);
}

/* One run in a child process of its own, so that the peak memory is the run's:
 * the children's maxrss is the largest of them. */
static int grow_apart(const workload *w, outcome *o)
{
    int fd[2];
    if (pipe(fd) != 0) {
        perror("bench: pipe");
        return 1;
    }
    fflush(stdout);
    pid_t pid = fork();
    if (pid < 0) {
        perror("bench: fork");
        return 1;
    }
    if (pid == 0) {
        close(fd[0]);
        int rc = grow(w, o);
        if (rc == 0 && write(fd[1], o, sizeof *o) != (ssize_t)sizeof *o)
            rc = 1;
        _exit(rc);
    }
    close(fd[1]);
    ssize_t got = read(fd[0], o, sizeof *o);
    close(fd[0]);
    int status;
    if (waitpid(pid, &status, 0) != pid || !WIFEXITED(status) || WEXITSTATUS(status) != 0 ||
        got != (ssize_t)sizeof *o)
        return 1;
    return 0;
}

static int run(const workload *w, int runs)
{
    outcome o[RUNS_MAX];
    for (int r = 0; r < runs; r++)
        if (grow_apart(w, &o[r]) != 0)
            return 1;
    qsort(o, (size_t)runs, sizeof *o, by_secs);
    double med = runs % 2 ? o[runs / 2].secs : 0.5 * (o[runs / 2 - 1].secs + o[runs / 2].secs);
    struct rusage ru;
    getrusage(RUSAGE_CHILDREN, &ru);
    char paper[16] = "-";
    if (w->paper_steps > 0)
        snprintf(paper, sizeof paper, "%u", w->paper_steps);
    printf("%-24s %10u %5u %5s %8.3f %8.3f %8.3f %12.0f %8.1f %5.0f %5.0f %016llx\n", w->name,
           o[0].internodes, o[0].steps, paper, o[0].secs, med, o[0].wall,
           o[0].secs > 0 ? (double)o[0].internodes / o[0].secs : 0.0,
           (double)ru.ru_maxrss / 1024.0, (double)o[0].height, (double)o[0].width,
           (unsigned long long)o[0].hash);
    return 0;
}

int main(int argc, char **argv)
{
    int rc = 0, any = 0;
    int runs = argc > 2 ? atoi(argv[2]) : 1;
    if (runs < 1 || runs > RUNS_MAX) {
        fprintf(stderr, "bench: RUNS must be from 1 to %d\n", RUNS_MAX);
        return 2;
    }
    if (argc > 1 && strcmp(argv[1], "--header") == 0) {
        printf("%-24s %10s %5s %5s %8s %8s %8s %12s %8s %5s %5s %16s\n", "workload",
               "internodes", "steps", "paper", "min s", "median s", "wall s", "internodes/s",
               "peak MB", "high", "wide", "scene hash");
        return 0;
    }
    for (size_t i = 0; i < NWORK; i++) {
        if (argc > 1 && strcmp(argv[1], workloads[i].name) != 0)
            continue;
        any = 1;
        rc |= run(&workloads[i], runs);
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
