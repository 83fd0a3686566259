/* meristem — `make table1`: grows P09's Table 1 trees (the table1-* presets) at full
 * size and checks the calibration: each must reach the paper's internode count in a
 * step count within 25 % of the paper's, inside the 200³ grid. Prints per tree the
 * steps, internodes, the geometric mean growth per step, height and width. Too
 * slow for `make check` (hundreds of thousands of internodes per tree); the suite
 * checks the scaled-down growth rate (tests/unit/test_table1.c). Usage:
 * table1 [SEEDS] (default 2: seeds 1..SEEDS). Exit status 1 if a check fails. */
#include "config.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include <meristem.h>

typedef struct row {
    const char *preset;
    uint32_t steps, internodes; /* P09 Table 1 */
} row;

static const row rows[] = {
    {"table1-left", 106, 700000},
    {"table1-center", 90, 642000},
    {"table1-right", 68, 225000},
};

/* Grows `r` from `seed` until it has the paper's internodes (or twice its steps);
 * returns 0 if the step count and the extent pass. */
static int grow(const row *r, uint64_t seed)
{
    mer_params p;
    mer_error err;
    mer_scene *s;
    if (mer_preset_params(r->preset, &p, &err) != MER_OK ||
        mer_scene_new(&p, seed, &s, &err) != MER_OK) {
        fprintf(stderr, "table1: %s\n", err.message);
        return 1;
    }
    mer_summary m;
    uint32_t steps = 0;
    do {
        if (mer_scene_step(s, 1, NULL, NULL, NULL, NULL, &err) != MER_OK) {
            fprintf(stderr, "table1: %s\n", err.message);
            mer_scene_free(s);
            return 1;
        }
        steps++;
        mer_scene_summary(s, &m);
    } while (m.internodes < r->internodes && steps < 2 * r->steps);
    int inside = 1;
    for (int a = 0; a < 3; a++)
        inside &= m.bbox_min[a] >= p.bounds_min[a] && m.bbox_max[a] <= p.bounds_max[a];
    double off = ((double)steps - r->steps) / r->steps;
    int ok = m.internodes >= r->internodes && fabs(off) <= 0.25 && inside;
    printf("%-14s seed %llu  steps %3u (paper %3u, %+4.0f %%)  internodes %7u  "
           "growth/step %.3f  height %5.1f  width %5.1f  %s%s\n",
           r->preset, (unsigned long long)seed, steps, r->steps, 100.0 * off, m.internodes,
           pow((double)m.internodes, 1.0 / steps), (double)m.height, (double)m.crown_width,
           inside ? "inside the grid" : "OUTSIDE the grid", ok ? "" : "  FAIL");
    mer_scene_free(s);
    return ok ? 0 : 1;
}

int main(int argc, char **argv)
{
    int seeds = argc > 1 ? atoi(argv[1]) : 2;
    int rc = 0;
    for (size_t i = 0; i < sizeof rows / sizeof rows[0]; i++)
        for (int seed = 1; seed <= seeds; seed++) {
            rc |= grow(&rows[i], (uint64_t)seed);
            fflush(stdout);
        }
    return rc;
}
