/* meristem benchmark: meshing and GLB encoding (issue "Tree geometry and glTF
 * snapshots"). Grows a tree to about N internodes, then meshes and encodes it
 * several times and prints the best time, triangles per second and bytes per
 * internode. Not a test: nothing here passes or fails on time.
 *
 *   tests/bench/bench_mesh [INTERNODES] [DETAIL] [compact|implicit|tubes] [THREADS] [MESHINGS]
 *   (default 10000 3 tubes 1; MESHINGS 3 for implicit junctions or a tree over
 *   100,000 internodes, else 20)
 *
 * "compact" encodes the brush client's snapshot: no UVs, twig lines, EXT_meshopt_compression.
 * "implicit" meshes forks of thick branches as implicit junctions (mesh.h, Junctions),
 * their patches on THREADS threads. Besides the wall clock, the process's CPU time
 * of the best run: on a shared machine the wall clock counts other programs too,
 * and more meshings make the best one likelier to have run undisturbed.
 */
#include "config.h"

#include <malloc.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <meristem.h>

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void stop_at(void *ctx, uint32_t done, uint32_t total)
{
    (void)done;
    (void)total;
    struct { mer_scene *scene; uint32_t target; volatile int cancel; } *run = ctx;
    mer_summary s;
    mer_scene_summary(run->scene, &s);
    if (s.internodes >= run->target)
        run->cancel = 1;
}

int main(int argc, char **argv)
{
    uint32_t target = argc > 1 ? (uint32_t)strtoul(argv[1], NULL, 10) : 10000;
    uint32_t detail = argc > 2 ? (uint32_t)strtoul(argv[2], NULL, 10) : MER_MESH_DETAIL_DEFAULT;
    const int compact = argc > 3 && strcmp(argv[3], "compact") == 0;
    const int implicit = argc > 3 && strcmp(argv[3], "implicit") == 0;
    const uint32_t threads = argc > 4 ? (uint32_t)strtoul(argv[4], NULL, 10) : 1;
    int reps = argc > 5 ? atoi(argv[5]) : 0; /* 0: the default */
    if (argc > 5 && (reps < 1 || reps > 1000)) {
        fprintf(stderr, "bench_mesh: meshings must be from 1 to 1000, got %s\n", argv[5]);
        return 1;
    }
    // As meristemd does: keep freed memory for the next snapshot instead of
    // handing it back to the kernel and faulting it in again.
    mallopt(M_MMAP_THRESHOLD, 256 << 20);
    mallopt(M_TRIM_THRESHOLD, 512 << 20);
    mer_params p;
    mer_error err;
    if (mer_preset_params("fig7-bh-0.54", &p, &err) != MER_OK)
        return 1;
    // Room for a big tree: the paper's 200^3 grid.
    p.bounds_min[0] = p.bounds_min[2] = -100.0f;
    p.bounds_max[0] = p.bounds_max[2] = 100.0f;
    p.bounds_max[1] = 200.0f;
    mer_scene *scene = NULL;
    if (mer_scene_new(&p, 1, &scene, &err) != MER_OK) {
        fprintf(stderr, "bench_mesh: %s\n", err.message);
        return 1;
    }
    struct { mer_scene *scene; uint32_t target; volatile int cancel; } run = {scene, target, 0};
    if (mer_scene_step(scene, 400, stop_at, &run, &run.cancel, NULL, &err) != MER_OK) {
        fprintf(stderr, "bench_mesh: %s\n", err.message);
        return 1;
    }
    mer_summary sum;
    mer_scene_summary(scene, &sum);

    mer_mesh_options opt = {.detail = detail, .no_uvs = (uint32_t)compact, .twig_lines = (uint32_t)compact,
                            .junctions = implicit ? MER_JUNCTIONS_IMPLICIT : MER_JUNCTIONS_TUBES,
                            .threads = threads};
    mer_gltf_options gopt = {.compression = compact ? MER_GLTF_MESHOPT : MER_GLTF_UNCOMPRESSED};
    double best_mesh = 1e9, best_glb = 1e9, best_cpu = 1e9, cold = 0;
    size_t bytes = 0;
    uint32_t triangles = 0, vertices = 0, junctions = 0, open = 0, smooth = 0;
    if (reps == 0)
        reps = sum.internodes > 100000 || implicit ? 3 : 20;
    for (int r = 0; r < reps; r++) {
        double c0 = cpu_now(), t0 = now();
        mer_mesh *mesh = NULL;
        if (mer_mesh_build(scene, &opt, &mesh, &err) != MER_OK) {
            fprintf(stderr, "bench_mesh: %s\n", err.message);
            return 1;
        }
        double t1 = now();
        uint8_t *glb = NULL;
        if (mer_gltf_write_tree(mesh, NULL, &gopt, &glb, &bytes, &err) != MER_OK) {
            fprintf(stderr, "bench_mesh: %s\n", err.message);
            return 1;
        }
        double t2 = now(), c2 = cpu_now();
        triangles = mesh->bark.index_count / 3;
        vertices = mesh->bark.vertex_count;
        junctions = mesh->junctions;
        open = mesh->junctions_open;
        smooth = mesh->junctions_smooth;
        mer_gltf_free(glb);
        mer_mesh_free(mesh);
        if (r == 0)
            cold = t2 - t0;
        if (c2 - c0 < best_cpu)
            best_cpu = c2 - c0;
        if (t1 - t0 < best_mesh)
            best_mesh = t1 - t0;
        if (t2 - t1 < best_glb)
            best_glb = t2 - t1;
    }
    double total = best_mesh + best_glb;
    if (implicit)
        printf("implicit junctions %u (%u by marching tetrahedra, %u left as tubes)  threads %u  ", junctions,
               smooth, open, threads);
    printf("%s  internodes %u  steps %u  detail %u  vertices %u  triangles %u  "
           "mesh %.1f ms  glb %.1f ms  total %.1f ms (best of %d; cpu %.1f ms; first run %.1f ms)  %.1f Mtriangles/s  %zu bytes  "
           "%.1f bytes/internode\n",
           compact ? "mesh+compact-glb" : "mesh+glb", sum.internodes, sum.step, detail, vertices, triangles, 1e3 * best_mesh, 1e3 * best_glb,
           1e3 * total, reps, 1e3 * best_cpu, 1e3 * cold, (double)triangles / total / 1e6, bytes, (double)bytes / sum.internodes);
    mer_scene_free(scene);
    return 0;
}
