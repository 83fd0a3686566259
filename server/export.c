/* meristem — a scene as a glTF file (see export.h). */
#include "config.h"

#include "server/export.h"

#include <unistd.h>

/* Implicit junction patches are independent and their bytes do not depend on
 * the thread count (mer_mesh_options.threads), so a mesh that asks for none is
 * given the machine's cores: one snapshot request or one offline export is
 * then meshed as fast as the machine allows. */
static uint32_t patch_threads(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1u : n > 64 ? 64u : (uint32_t)n;
}

mer_result merd_export_tree(const mer_scene *scene, const mer_mesh_options *mesh,
                            const mer_gltf_options *gltf, const merd_origin *origin,
                            uint8_t **bytes, size_t *size, size_t *triangles, mer_error *err)
{
    mer_mesh_options o = *mesh;
    if (o.junctions != MER_JUNCTIONS_TUBES && o.threads == 0)
        o.threads = patch_threads();
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
    if (triangles != NULL)
        *triangles = (m->bark.index_count + m->leaves.index_count) / 3;
    mer_mesh_free(m);
    return rc;
}
