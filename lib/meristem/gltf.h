/* meristem — glTF 2.0 encoding behind a plain C API.
 *
 * lib/gltf.cc wraps tinygltf (Debian's libtinygltf-dev, header-only here, with
 * image loading compiled out). Nothing C++ crosses this header: every entry point
 * catches all exceptions and maps them to a mer_result.
 */
#ifndef MERISTEM_GLTF_H
#define MERISTEM_GLTF_H

#include <stddef.h>
#include <stdint.h>

#include <meristem/result.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Node ids travel in the `_NODE_ID` vertex attribute as FLOAT, because glTF 2.0
 * allows UNSIGNED_INT only for indices (accessor.componentType). float32 holds
 * every integer below 2^24 exactly; larger ids are refused. */
#define MER_GLTF_NODE_ID_LIMIT (1u << 24)

/* An indexed triangle mesh, borrowed for the duration of one call. */
typedef struct mer_gltf_mesh {
    const float *positions;    /* 3 × vertex_count, required */
    const float *normals;      /* 3 × vertex_count unit vectors, or NULL */
    const uint32_t *node_ids;  /* vertex_count ids < MER_GLTF_NODE_ID_LIMIT, or NULL;
                                  written as the application-specific `_NODE_ID` */
    size_t vertex_count;       /* >= 1 */
    const uint32_t *indices;   /* index_count entries, each < vertex_count, required */
    size_t index_count;        /* a positive multiple of 3 */
} mer_gltf_mesh;

/* Encodes `mesh` as one binary glTF (GLB) holding a single scene, node, mesh and
 * TRIANGLES primitive with POSITION (with min/max), NORMAL, `_NODE_ID` and
 * UNSIGNED_INT indices (UNSIGNED_SHORT when vertex_count <= 65535).
 *
 * On MER_OK, *out_glb holds *out_size bytes that the caller frees with
 * mer_gltf_free(). On failure *out_glb is NULL and `err` (may be NULL) says why.
 * Cost: O(vertex_count + index_count) time, about twice the buffer size in
 * transient memory. */
mer_result mer_gltf_write_glb(const mer_gltf_mesh *mesh, uint8_t **out_glb,
                              size_t *out_size, mer_error *err);

/* Frees bytes returned by this module. NULL is fine. */
void mer_gltf_free(void *bytes);

#ifdef __cplusplus
}
#endif

#endif
