/* meristem benchmark: the L-system language at ten million modules (issue 15:
 * derivation and interpretation linear in the string, memory proportional to
 * it). Honda's monopodial tree of ABOP Fig. 2.6a, a parametric system whose
 * string holds about 7·2^n modules after n steps, derived to n = 21 (about 15
 * million modules, two million F).
 *
 *   tests/bench/bench_lsystem string [RUNS] [N]
 *     derives the string (all N steps, and the last step alone) and interprets
 *     it with the turtle (segments only): modules, segments, seconds (min of
 *     RUNS), peak memory (getrusage maxrss) and bytes per module.
 *   tests/bench/bench_lsystem step [RUNS] [N]
 *     the model's step N through the scene API: the last derivation step, the
 *     turtle, and the drawing onto the shared skeleton.
 *
 * Each mode runs in a process of its own (make bench calls it twice), so its
 * peak memory is its own. Not a test: nothing here passes or fails on time.
 */
#include "config.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>

#include <meristem/params.h>
#include <meristem/scene.h>

#include "models/lsystem/lsystem.h"

static const char HONDA[] =
    "#define r1 0.9\n#define r2 0.6\n#define a0 45\n#define a2 45\n"
    "#define d 137.5\n#define wr 0.707\n"
    "axiom: A(1,10)\n"
    "A(l,w) : * -> !(w)F(l)[&(a0)B(l*r2,w*wr)]/(d)A(l*r1,w*wr)\n"
    "B(l,w) : * -> !(w)F(l)[-(a2)$C(l*r2,w*wr)]C(l*r1,w*wr)\n"
    "C(l,w) : * -> !(w)F(l)[+(a2)$B(l*r2,w*wr)]B(l*r1,w*wr)\n";

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static double peak_mb(void)
{
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return (double)ru.ru_maxrss / 1024.0;
}

static double min(double a, double b) { return a < b ? a : b; }

/* FNV-1a over the string, so that a faster derivation shows it derived the same. */
static uint64_t string_hash(const merp_lstr *s)
{
    uint64_t h = UINT64_C(0xcbf29ce484222325);
    const unsigned char *p[3] = {(const void *)s->sym, (const void *)s->poff, (const void *)s->par};
    size_t len[3] = {s->n * sizeof *s->sym, (s->n + 1) * sizeof *s->poff, s->npar * sizeof *s->par};
    for (int k = 0; k < 3; k++)
        for (size_t i = 0; i < len[k]; i++)
            h = (h ^ p[k][i]) * UINT64_C(0x100000001b3);
    return h;
}

static int bench_string(int runs, int n)
{
    merp_ls_error le;
    merp_lsys *ls = merp_lsys_parse(HONDA, &le);
    if (ls == NULL) {
        fprintf(stderr, "bench_lsystem: %d:%d %s\n", le.line, le.col, le.msg);
        return 1;
    }
    merp_ls_turtle tp = merp_ls_turtle_default();
    double all = 1e30, last = 1e30, turtle = 1e30;
    merp_lstr s, prev;
    merp_ls_segs segs = {0};
    merp_lstr_init(&s);
    merp_lstr_init(&prev);
    for (int r = 0; r < runs; r++) {
        double t0 = now();
        if (merp_lsys_run(ls, n - 1, 1, &prev))
            return 1;
        double t1 = now();
        if (merp_lsys_derive(ls, &prev, &s, 1, (uint32_t)(n - 1)))
            return 1;
        double t2 = now();
        if (merp_ls_interpret(&s, &tp, &segs))
            return 1;
        double t3 = now();
        all = min(all, t2 - t0);
        last = min(last, t2 - t1);
        turtle = min(turtle, t3 - t2);
    }
    double mb = peak_mb();
    printf("%-26s %11zu %9zu %8.3f %8.3f %8.3f %8s %9.1f %8.1f  %016llx\n", "lsystem-honda-string",
           s.n, segs.n, all, last, turtle, "-", mb, mb * 1048576.0 / (double)s.n,
           (unsigned long long)string_hash(&s));
    merp_lstr_free(&s);
    merp_lstr_free(&prev);
    merp_ls_segs_free(&segs);
    merp_lsys_free(ls);
    return 0;
}

static int bench_step(int runs, int n)
{
    double best = 1e30;
    mer_summary sum = {0};
    uint64_t hash = 0;
    mer_error err;
    for (int r = 0; r < runs; r++) {
        mer_params p = mer_params_default();
        p.model = MER_MODEL_LSYSTEM;
        p.ls_delta = 90.0f;
        mer_scene *sc = NULL;
        uint32_t done = 0;
        if (mer_scene_new(&p, 1, &sc, &err) != MER_OK ||
            mer_scene_set_definition(sc, HONDA, strlen(HONDA), &err) != MER_OK ||
            mer_scene_step(sc, (uint32_t)(n - 1), NULL, NULL, NULL, &done, &err) != MER_OK) {
            fprintf(stderr, "bench_lsystem: %s\n", err.message);
            return 1;
        }
        double t0 = now();
        if (mer_scene_step(sc, 1, NULL, NULL, NULL, &done, &err) != MER_OK) {
            fprintf(stderr, "bench_lsystem: %s\n", err.message);
            return 1;
        }
        best = min(best, now() - t0);
        mer_scene_summary(sc, &sum);
        hash = mer_scene_hash(sc);
        mer_scene_free(sc);
    }
    printf("%-26s %11s %9u %8s %8s %8s %8.3f %9.1f %8s  %016llx\n", "lsystem-honda-model-step", "-",
           sum.internodes, "-", "-", "-", best, peak_mb(), "-", (unsigned long long)hash);
    return 0;
}

int main(int argc, char **argv)
{
    const char *mode = argc > 1 ? argv[1] : "string";
    int runs = argc > 2 ? atoi(argv[2]) : 3;
    int n = argc > 3 ? atoi(argv[3]) : 21;
    if (runs < 1 || n < 1 || n > 26) {
        fprintf(stderr, "bench_lsystem: RUNS >= 1, 1 <= N <= 26\n");
        return 2;
    }
    if (strcmp(mode, "--header") == 0) {
        printf("%-26s %11s %9s %8s %8s %8s %8s %9s %8s  %16s\n", "L-system workload", "modules",
               "segments", "derive s", "last s", "turtle s", "step s", "peak MB", "B/module",
               "hash");
        return 0;
    }
    if (strcmp(mode, "string") == 0)
        return bench_string(runs, n);
    if (strcmp(mode, "step") == 0)
        return bench_step(runs, n);
    fprintf(stderr, "bench_lsystem: mode is string or step\n");
    return 2;
}
