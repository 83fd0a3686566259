/* meristem benchmark: the inverse model of G04 §4 (issue 16). Grows the
 * Populus deltoides preset through its 27 years, one step a year (each year the
 * tree is rebuilt from its functions), and shows it at a fractional year
 * (t = 12.25, the continuous development of G04 §4.3). Prints the best of RUNS
 * runs in seconds, the live internodes and the scene hash. Not a test: nothing
 * here passes or fails on time.
 *
 *   tests/bench/bench_inverse [RUNS]   (default 3)
 */
#include "config.h"

#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include <meristem.h>

#include "models/inverse/inverse.h"
#include "scene_private.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static mer_scene *populus(mer_error *err)
{
    mer_scene *s = NULL;
    return merp_scene_new_with(&merp_inverse_ops, NULL, 1, &s, err) == MER_OK ? s : NULL;
}

int main(int argc, char **argv)
{
    int runs = argc > 1 ? atoi(argv[1]) : 3;
    double grow_best = 1e30, show_best = 1e30;
    mer_summary grown = {0}, shown = {0};
    uint64_t grown_hash = 0, shown_hash = 0;
    mer_error err;
    for (int r = 0; r < (runs > 0 ? runs : 1); r++) {
        mer_scene *s = populus(&err);
        if (s == NULL) {
            fprintf(stderr, "bench_inverse: %s\n", err.message);
            return 1;
        }
        uint32_t done = 0;
        double t0 = now();
        if (mer_scene_step(s, 27, NULL, NULL, NULL, &done, &err) != MER_OK) {
            fprintf(stderr, "bench_inverse: %s\n", err.message);
            return 1;
        }
        double t1 = now();
        grow_best = t1 - t0 < grow_best ? t1 - t0 : grow_best;
        mer_scene_summary(s, &grown);
        grown_hash = mer_scene_hash(s);
        mer_scene_free(s);

        s = populus(&err);
        t0 = now();
        if (s == NULL || merp_inverse_show(s, 12.25, &err) != MER_OK) {
            fprintf(stderr, "bench_inverse: %s\n", err.message);
            return 1;
        }
        t1 = now();
        show_best = t1 - t0 < show_best ? t1 - t0 : show_best;
        mer_scene_summary(s, &shown);
        shown_hash = mer_scene_hash(s);
        mer_scene_free(s);
    }
    printf("%-28s %10u internodes %9.4f s   hash %016llx\n", "inverse-populus-27-years",
           grown.internodes, grow_best, (unsigned long long)grown_hash);
    printf("%-28s %10u internodes %9.4f s   hash %016llx\n", "inverse-populus-at-12.25",
           shown.internodes, show_best, (unsigned long long)shown_hash);
    return 0;
}
