/* meristem — a scene as a glTF file (see export.h). */
#include "config.h"

#include "server/export.h"

#include "server/cpu_quota.h"

#include <sched.h>
#include <unistd.h>

#define MAX_PATCH_THREADS 64 /* mer_mesh_options.threads' range */

/* Implicit junction patches are independent and their bytes do not depend on
 * the thread count (mer_mesh_options.threads), so they may take every core
 * the process may run on: its CPU affinity's (a container's or taskset's
 * share), where the system tells it, rather than every core online, and no
 * more than its control groups' CPU quota pays for (cpu_quota.h). */
uint32_t merd_export_cores(void)
{
    cpu_set_t set;
    long n = sched_getaffinity(0, sizeof set, &set) == 0 ? CPU_COUNT(&set) : sysconf(_SC_NPROCESSORS_ONLN);
    uint32_t quota = merd_cpu_quota_cores();
    if (quota > 0 && quota < n)
        n = quota;
    return n < 1 ? 1u : n > MAX_PATCH_THREADS ? MAX_PATCH_THREADS : (uint32_t)n;
}

mer_result merd_export_tree(const mer_scene *scene, const mer_mesh_options *mesh,
                            const mer_gltf_options *gltf, const merd_origin *origin,
                            uint8_t **bytes, size_t *size, merd_export_counts *counts, mer_error *err)
{
    if (counts != NULL)
        *counts = (merd_export_counts){0};
    mer_mesh_options o = *mesh;
    if (o.junctions != MER_JUNCTIONS_TUBES && o.threads == 0)
        o.threads = merd_export_cores();
    mer_mesh *m = NULL;
    mer_result rc = mer_mesh_build(scene, &o, &m, err);
    if (rc != MER_OK)
        return rc;
    mer_gltf_meta meta = {.session = origin->session,
                          .revision = origin->revision,
                          .step = mer_scene_step_index(scene),
                          .preset = origin->preset,
                          .seed = origin->seed,
                          .detail = mesh->detail ? mesh->detail : MER_MESH_DETAIL_DEFAULT,
                          .leaves = mesh->leaves,
                          .markers = mesh->markers,
                          .color = mesh->color,
                          .internode_length = (double)mer_scene_params(scene)->internode_length};
    rc = mer_gltf_write_tree(m, &meta, gltf, bytes, size, err);
    if (counts != NULL)
        *counts = (merd_export_counts){.triangles = (m->bark.index_count + m->leaves.index_count) / 3,
                                       .junctions = m->junctions,
                                       .junctions_smooth = m->junctions_smooth,
                                       .junctions_open = m->junctions_open,
                                       .junctions_unfit = m->junctions_unfit};
    mer_mesh_free(m);
    return rc;
}
