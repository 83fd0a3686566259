// A plain indexed triangle mesh written as a GLB through the library's one
// writer, mer_gltf_write_tree: one bark chunk, unquantized, no meta. The unit
// tests of the encoding (test_gltf.cc) use it; the library has no plain-mesh
// entry point of its own, since nothing else needs one.
#ifndef MERISTEM_TEST_PLAIN_GLB_H
#define MERISTEM_TEST_PLAIN_GLB_H

#include <cassert>
#include <cstddef>
#include <cstdint>

#include <meristem/gltf.h>

// Borrowed for the duration of one call.
struct plain_mesh {
    const float *positions;    // 3 × vertex_count, required
    const float *normals;      // 3 × vertex_count unit vectors, or NULL
    const uint32_t *node_ids;  // vertex_count ids < MER_GLTF_NODE_ID_LIMIT, or NULL
    size_t vertex_count;       // 1 .. 2^32 - 1
    const uint32_t *indices;   // index_count entries, each < vertex_count, required
    size_t index_count;        // a positive multiple of 3
};

// One TRIANGLES primitive with POSITION (with min/max), NORMAL, `_NODE_ID` and
// indices (UNSIGNED_SHORT when vertex_count <= 65535), all unquantized; errors
// as mer_gltf_write_tree's, naming fields "mesh.bark.*".
static inline mer_result write_plain_glb(const plain_mesh *in, uint8_t **out, size_t *out_size,
                                         mer_error *err)
{
    assert(in != nullptr && in->vertex_count <= UINT32_MAX && in->index_count <= UINT32_MAX);
    mer_mesh mesh{};
    mesh.bark.vertex_count = static_cast<uint32_t>(in->vertex_count);
    mesh.bark.index_count = static_cast<uint32_t>(in->index_count);
    mesh.bark.positions = const_cast<float *>(in->positions);
    mesh.bark.normals = const_cast<float *>(in->normals);
    mesh.bark.node_ids = const_cast<uint32_t *>(in->node_ids);
    mesh.bark.indices = const_cast<uint32_t *>(in->indices);
    mer_mesh_chunk whole{0, mesh.bark.vertex_count, 0, mesh.bark.index_count, 0, 0, 0};
    mesh.bark.chunks = &whole;
    mesh.bark.chunk_count = 1;
    mer_gltf_options raw{};
    raw.unquantized = 1;
    return mer_gltf_write_tree(&mesh, nullptr, &raw, out, out_size, err);
}

#endif
