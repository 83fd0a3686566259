// meristem — glTF 2.0 encoding with tinygltf, behind the C API of meristem/gltf.h.
//
// The only C++ in libmeristem. tinygltf's implementation is compiled here with
// image loading and file-system access compiled out: meristem writes geometry,
// never textures, and lib does no I/O.
#include "config.h"

#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wnull-dereference"
#pragma GCC diagnostic ignored "-Wdouble-promotion"
#pragma GCC diagnostic ignored "-Wcast-align"
#pragma GCC diagnostic ignored "-Wformat-nonliteral"
#pragma GCC diagnostic ignored "-Wpedantic"
#endif
#include <tiny_gltf.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

#include <cfloat>
#include <cstdlib>
#include <cstring>
#include <new>
#include <sstream>

#include <meristem/gltf.h>
#include <meristem/version.h>

namespace {

// Appends `bytes` to the single buffer, padded to 4 bytes as glTF requires of
// every bufferView holding 4-byte components, and returns its bufferView index.
int add_view(tinygltf::Model &model, const void *bytes, size_t size, int target)
{
    std::vector<unsigned char> &data = model.buffers[0].data;
    size_t offset = data.size();
    data.resize(offset + ((size + 3u) & ~size_t{3}));
    std::memcpy(data.data() + offset, bytes, size);

    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = offset;
    view.byteLength = size;
    view.target = target;
    model.bufferViews.push_back(view);
    return static_cast<int>(model.bufferViews.size() - 1);
}

int add_accessor(tinygltf::Model &model, int view, int component_type, int type,
                 size_t count)
{
    tinygltf::Accessor accessor;
    accessor.bufferView = view;
    accessor.byteOffset = 0;
    accessor.componentType = component_type;
    accessor.type = type;
    accessor.count = count;
    model.accessors.push_back(accessor);
    return static_cast<int>(model.accessors.size() - 1);
}

mer_result check_mesh(const mer_gltf_mesh *mesh, mer_error *err)
{
    if (mesh == nullptr)
        return mer_error_set(err, MER_ERR_INVALID, "mesh", "no mesh given");
    if (mesh->positions == nullptr || mesh->vertex_count == 0)
        return mer_error_set(err, MER_ERR_INVALID, "positions",
                             "a mesh needs at least one vertex position");
    if (mesh->vertex_count > UINT32_MAX)
        return mer_error_set(err, MER_ERR_RANGE, "vertex_count",
                             "%zu vertices exceed the 2^32 - 1 that indices can address",
                             mesh->vertex_count);
    if (mesh->indices == nullptr || mesh->index_count == 0 || mesh->index_count % 3 != 0)
        return mer_error_set(err, MER_ERR_INVALID, "indices",
                             "triangle indices must be a positive multiple of 3, got %zu",
                             mesh->index_count);
    for (size_t i = 0; i < mesh->index_count; i++)
        if (mesh->indices[i] >= mesh->vertex_count)
            return mer_error_set(err, MER_ERR_RANGE, "indices",
                                 "index %zu is %u, past the last vertex %zu", i,
                                 mesh->indices[i], mesh->vertex_count - 1);
    for (size_t i = 0; i < 3 * mesh->vertex_count; i++)
        if (!std::isfinite(mesh->positions[i]))
            return mer_error_set(err, MER_ERR_RANGE, "positions",
                                 "vertex %zu has a non-finite coordinate", i / 3);
    if (mesh->node_ids != nullptr)
        for (size_t i = 0; i < mesh->vertex_count; i++)
            if (mesh->node_ids[i] >= MER_GLTF_NODE_ID_LIMIT)
                return mer_error_set(err, MER_ERR_RANGE, "node_ids",
                                     "node id %u of vertex %zu is not below 2^24, the largest "
                                     "integer a float attribute holds exactly",
                                     mesh->node_ids[i], i);
    return MER_OK;
}

void build_model(const mer_gltf_mesh *mesh, tinygltf::Model &model)
{
    model.asset.version = "2.0";
    model.asset.generator = std::string("meristem ") + mer_version();
    model.buffers.resize(1);

    tinygltf::Primitive primitive;
    primitive.mode = TINYGLTF_MODE_TRIANGLES;

    const size_t n = mesh->vertex_count;
    int view = add_view(model, mesh->positions, n * 3 * sizeof(float),
                        TINYGLTF_TARGET_ARRAY_BUFFER);
    int position = add_accessor(model, view, TINYGLTF_COMPONENT_TYPE_FLOAT,
                                TINYGLTF_TYPE_VEC3, n);
    // POSITION must carry min and max (glTF 2.0 §3.7.2.1).
    std::vector<double> lo(3, DBL_MAX), hi(3, -DBL_MAX);
    for (size_t i = 0; i < n; i++)
        for (int k = 0; k < 3; k++) {
            double v = mesh->positions[3 * i + k];
            lo[k] = std::min(lo[k], v);
            hi[k] = std::max(hi[k], v);
        }
    model.accessors[position].minValues = lo;
    model.accessors[position].maxValues = hi;
    primitive.attributes["POSITION"] = position;

    if (mesh->normals != nullptr) {
        view = add_view(model, mesh->normals, n * 3 * sizeof(float),
                        TINYGLTF_TARGET_ARRAY_BUFFER);
        primitive.attributes["NORMAL"] =
            add_accessor(model, view, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, n);
    }
    if (mesh->node_ids != nullptr) {
        std::vector<float> ids(n);
        for (size_t i = 0; i < n; i++)
            ids[i] = static_cast<float>(mesh->node_ids[i]);
        view = add_view(model, ids.data(), n * sizeof(float), TINYGLTF_TARGET_ARRAY_BUFFER);
        primitive.attributes["_NODE_ID"] =
            add_accessor(model, view, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_SCALAR, n);
    }

    const size_t m = mesh->index_count;
    if (n <= 0xFFFF) {
        std::vector<uint16_t> narrow(m);
        for (size_t i = 0; i < m; i++)
            narrow[i] = static_cast<uint16_t>(mesh->indices[i]);
        view = add_view(model, narrow.data(), m * sizeof(uint16_t),
                        TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
        primitive.indices = add_accessor(model, view, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                                         TINYGLTF_TYPE_SCALAR, m);
    } else {
        view = add_view(model, mesh->indices, m * sizeof(uint32_t),
                        TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
        primitive.indices = add_accessor(model, view, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT,
                                         TINYGLTF_TYPE_SCALAR, m);
    }

    tinygltf::Mesh gmesh;
    gmesh.name = "tree";
    gmesh.primitives.push_back(primitive);
    model.meshes.push_back(gmesh);

    tinygltf::Node node;
    node.name = "tree";
    node.mesh = 0;
    model.nodes.push_back(node);

    tinygltf::Scene scene;
    scene.nodes.push_back(0);
    model.scenes.push_back(scene);
    model.defaultScene = 0;
}

}  // namespace

extern "C" mer_result mer_gltf_write_glb(const mer_gltf_mesh *mesh, uint8_t **out_glb,
                                         size_t *out_size, mer_error *err)
{
    if (out_glb == nullptr || out_size == nullptr)
        return mer_error_set(err, MER_ERR_INVALID, nullptr, "no output pointers given");
    *out_glb = nullptr;
    *out_size = 0;
    mer_result rc = check_mesh(mesh, err);
    if (rc != MER_OK)
        return rc;
    try {
        tinygltf::Model model;
        build_model(mesh, model);
        std::ostringstream stream;
        tinygltf::TinyGLTF writer;
        if (!writer.WriteGltfSceneToStream(&model, stream, false, true))
            return mer_error_set(err, MER_ERR_INTERNAL, nullptr, "tinygltf could not encode the GLB");
        const std::string bytes = stream.str();
        uint8_t *copy = static_cast<uint8_t *>(std::malloc(bytes.size()));
        if (copy == nullptr)
            return mer_error_set(err, MER_ERR_NOMEM, nullptr, "out of memory for %zu GLB bytes",
                                 bytes.size());
        std::memcpy(copy, bytes.data(), bytes.size());
        *out_glb = copy;
        *out_size = bytes.size();
        return MER_OK;
    } catch (const std::bad_alloc &) {
        return mer_error_set(err, MER_ERR_NOMEM, nullptr, "out of memory while encoding glTF");
    } catch (const std::exception &e) {
        return mer_error_set(err, MER_ERR_INTERNAL, nullptr, "glTF encoding failed: %s", e.what());
    } catch (...) {
        return mer_error_set(err, MER_ERR_INTERNAL, nullptr, "glTF encoding failed");
    }
}

extern "C" void mer_gltf_free(void *bytes)
{
    std::free(bytes);
}
