/* meristem — a scene as a glTF file (see export.h). */
#include "config.h"

#include "server/export.h"

mer_result merd_export_tree(const mer_scene *scene, const mer_mesh_options *mesh,
                            const mer_gltf_options *gltf, const merd_origin *origin,
                            uint8_t **bytes, size_t *size, size_t *triangles, mer_error *err)
{
    mer_mesh *m = NULL;
    mer_result rc = mer_mesh_build(scene, mesh, &m, err);
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
