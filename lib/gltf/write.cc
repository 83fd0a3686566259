// meristem — mer_gltf_write_tree: checks a mesh, lays it out (tree.cc) and
// frames it as a GLB, a compressed GLB (meshopt.cc) or an embedded .gltf.
#include "config.h"

#include "core/alloc.h"
#include "gltf/gltf_private.h"

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <sstream>

using namespace merp_gltf;

namespace {

// The chunks of part `p` tile its vertices, indices and line indices, and every
// index stays within its chunk; `indices` and `lines` name the fields.
mer_result check_chunks(const mer_mesh_part &p, const char *indices, const char *lines,
                        mer_error *err)
{
    uint32_t next_vertex = 0, next_index = 0, next_line = 0;
    for (uint32_t c = 0; c < p.chunk_count; c++) {
        const mer_mesh_chunk &ch = p.chunks[c];
        if (ch.first_vertex != next_vertex || ch.first_index != next_index || ch.vertex_count == 0 ||
            ch.index_count == 0 || ch.index_count % 3 != 0)
            return mer_error_set(err, MER_ERR_INVALID, indices,
                                 "chunk %u does not continue where chunk %u ended", c, c - 1);
        for (uint32_t i = ch.first_index; i < ch.first_index + ch.index_count; i++)
            if (p.indices[i] >= ch.vertex_count)
                return mer_error_set(err, MER_ERR_RANGE, indices,
                                     "index %u is %u, past the last vertex %u of its chunk", i,
                                     p.indices[i], ch.vertex_count - 1);
        if (ch.line_index_count > 0 &&
            (ch.first_line_index != next_line || ch.line_index_count % 2 != 0 ||
             ch.line_index_count > p.line_index_count - next_line))
            return mer_error_set(err, MER_ERR_INVALID, lines,
                                 "chunk %u's line indices do not continue the last ones", c);
        for (uint32_t i = ch.first_line_index; i < ch.first_line_index + ch.line_index_count; i++)
            if (p.line_indices[i] >= ch.vertex_count)
                return mer_error_set(err, MER_ERR_RANGE, lines,
                                     "line index %u is %u, past the last vertex %u of its chunk", i,
                                     p.line_indices[i], ch.vertex_count - 1);
        next_vertex += ch.vertex_count;
        next_index += ch.index_count;
        next_line += ch.line_index_count;
    }
    if (next_line != p.line_index_count)
        return mer_error_set(err, MER_ERR_INVALID, lines,
                             "the chunks cover %u of %u line indices", next_line, p.line_index_count);
    if (next_vertex != p.vertex_count || next_index != p.index_count)
        return mer_error_set(err, MER_ERR_INVALID, indices,
                             "the chunks cover %u of %u vertices and %u of %u indices", next_vertex,
                             p.vertex_count, next_index, p.index_count);
    return MER_OK;
}

// Finite positions and node ids that a float attribute holds exactly.
mer_result check_values(const mer_mesh_part &p, const char *positions, const char *ids,
                        mer_error *err)
{
    for (size_t i = 0; i < 3 * size_t{p.vertex_count}; i++)
        if (!std::isfinite(p.positions[i]))
            return mer_error_set(err, MER_ERR_RANGE, positions,
                                 "vertex %zu has a non-finite coordinate", i / 3);
    if (p.node_ids != nullptr)
        for (size_t i = 0; i < p.vertex_count; i++)
            if (p.node_ids[i] >= MER_GLTF_NODE_ID_LIMIT)
                return mer_error_set(err, MER_ERR_RANGE, ids,
                                     "node id %u of vertex %zu is not below 2^24, the largest "
                                     "integer a float attribute holds exactly",
                                     p.node_ids[i], i);
    return MER_OK;
}

// `prefix` names the part in error fields ("mesh.bark." gives "mesh.bark.indices").
mer_result check_part(const mer_mesh_part &p, const std::string &prefix, mer_error *err)
{
    const std::string indices = prefix + "indices", positions = prefix + "positions",
                      ids = prefix + "node_ids", lines = prefix + "line_indices";
    if (p.vertex_count == 0)
        return MER_OK;
    if (p.positions == nullptr)
        return mer_error_set(err, MER_ERR_INVALID, positions.c_str(), "no vertex positions given");
    if (p.indices == nullptr || p.index_count == 0 || p.index_count % 3 != 0)
        return mer_error_set(err, MER_ERR_INVALID, indices.c_str(),
                             "triangle indices must be a positive multiple of 3, got %u",
                             p.index_count);
    if (p.line_index_count % 2 != 0 || (p.line_index_count > 0 && p.line_indices == nullptr))
        return mer_error_set(err, MER_ERR_INVALID, lines.c_str(),
                             "line indices must come in pairs, got %u", p.line_index_count);
    if (p.chunks == nullptr || p.chunk_count == 0)
        return mer_error_set(err, MER_ERR_INVALID, indices.c_str(), "no chunks given");
    mer_result rc = check_chunks(p, indices.c_str(), lines.c_str(), err);
    return rc == MER_OK ? check_values(p, positions.c_str(), ids.c_str(), err) : rc;
}

mer_result check_options(const mer_gltf_options &options, mer_error *err)
{
    if (options.format != MER_GLTF_BINARY && options.format != MER_GLTF_EMBEDDED)
        return mer_error_set(err, MER_ERR_RANGE, "format", "format must be binary or embedded");
    if (options.unquantized > 1)
        return mer_error_set(err, MER_ERR_RANGE, "unquantized", "must be 0 or 1");
    if (options.compression > MER_GLTF_MESHOPT)
        return mer_error_set(err, MER_ERR_RANGE, "compression", "compression must be none or meshopt");
    if (options.compression != MER_GLTF_UNCOMPRESSED && options.format != MER_GLTF_BINARY)
        return mer_error_set(err, MER_ERR_RANGE, "compression",
                             "meshopt compression is for binary glTF (.glb) only");
    return MER_OK;
}

mer_result to_bytes(const std::string &text, uint8_t **out, size_t *out_size, mer_error *err)
{
    uint8_t *copy = static_cast<uint8_t *>(merp_malloc(text.size()));
    if (copy == nullptr)
        return mer_error_set(err, MER_ERR_NOMEM, nullptr, "out of memory for %zu glTF bytes",
                             text.size());
    std::memcpy(copy, text.data(), text.size());
    *out = copy;
    *out_size = text.size();
    return MER_OK;
}

void put_u32(uint8_t *p, uint32_t v)
{
    p[0] = static_cast<uint8_t>(v);
    p[1] = static_cast<uint8_t>(v >> 8);
    p[2] = static_cast<uint8_t>(v >> 16);
    p[3] = static_cast<uint8_t>(v >> 24);
}

// GLB with the BIN data straight from the caller's arrays.
mer_result write_binary(Writer &w, uint8_t **out, size_t *out_size, mer_error *err)
{
    uint8_t *bin = nullptr;
    mer_result rc = assemble_glb(json_of(w), w.bin_size, out, out_size, &bin, err);
    if (rc == MER_OK && w.bin_size > 0)
        w.fill(bin);
    return rc;
}

// .gltf with the buffer embedded as base64: tinygltf does it all (debugging aid).
mer_result write_embedded(Writer &w, uint8_t **out, size_t *out_size, mer_error *err)
{
    w.model.buffers[0].data.resize(w.bin_size);
    if (w.bin_size)
        w.fill(w.model.buffers[0].data.data());
    std::ostringstream stream;
    tinygltf::TinyGLTF gltf;
    if (!gltf.WriteGltfSceneToStream(&w.model, stream, true, false))
        return mer_error_set(err, MER_ERR_INTERNAL, nullptr, "tinygltf could not encode the glTF");
    return to_bytes(stream.str(), out, out_size, err);
}

// Checks and encodes.
mer_result write_checked(const mer_mesh &mesh, const mer_gltf_meta *meta,
                         const mer_gltf_options &options, uint8_t **out, size_t *out_size,
                         mer_error *err)
{
    *out = nullptr;
    *out_size = 0;
    mer_result rc = check_options(options, err);
    if (rc != MER_OK)
        return rc;
    return guarded(err, [&]() {
        mer_result checked = check_part(mesh.bark, "mesh.bark.", err);
        if (checked == MER_OK)
            checked = check_part(mesh.leaves, "mesh.leaves.", err);
        if (checked == MER_OK && mesh.leaves.line_index_count != 0)
            checked = mer_error_set(err, MER_ERR_INVALID, "mesh.leaves.line_indices",
                                    "only bark has twig lines");
        if (checked != MER_OK)
            return checked;
        Writer w;
        w.quantized = options.unquantized == 0;
        build_tree(w, mesh, meta);
        if (options.format == MER_GLTF_EMBEDDED)
            return write_embedded(w, out, out_size, err);
        return options.compression == MER_GLTF_MESHOPT ? write_meshopt(w, out, out_size, err)
                                                       : write_binary(w, out, out_size, err);
    });
}

}  // namespace

namespace merp_gltf {

// tinygltf serializes the JSON; the GLB's buffer 0 is the BIN chunk (tinygltf
// would write an empty buffer as a data URI).
nlohmann::json json_of(Writer &w)
{
    std::ostringstream stream;
    tinygltf::TinyGLTF gltf;
    if (!gltf.WriteGltfSceneToStream(&w.model, stream, false, false))
        throw std::runtime_error("tinygltf could not encode the JSON");
    nlohmann::json doc = nlohmann::json::parse(stream.str());
    doc["buffers"] = nlohmann::json::array({{{"byteLength", w.bin_size}}});
    return doc;
}

mer_result assemble_glb(const nlohmann::json &doc, size_t bin_size, uint8_t **out,
                        size_t *out_size, uint8_t **bin, mer_error *err)
{
    assert(out != nullptr && out_size != nullptr && bin != nullptr);
    std::string text = doc.dump();
    text.append((4 - text.size() % 4) % 4, ' ');  // the JSON chunk pads with spaces
    const size_t total = 12 + 8 + text.size() + (bin_size ? 8 + bin_size : 0);
    if (total > UINT32_MAX)
        return mer_error_set(err, MER_ERR_LIMIT, nullptr,
                             "the GLB would be %zu bytes, over the format's 4 GiB; lower the detail",
                             total);
    uint8_t *glb = static_cast<uint8_t *>(merp_malloc(total));
    if (glb == nullptr)
        return mer_error_set(err, MER_ERR_NOMEM, nullptr, "out of memory for %zu GLB bytes", total);
    std::memcpy(glb, "glTF", 4);
    put_u32(glb + 4, 2);
    put_u32(glb + 8, static_cast<uint32_t>(total));
    put_u32(glb + 12, static_cast<uint32_t>(text.size()));
    std::memcpy(glb + 16, "JSON", 4);
    std::memcpy(glb + 20, text.data(), text.size());
    *bin = nullptr;
    if (bin_size) {
        uint8_t *chunk = glb + 20 + text.size();
        put_u32(chunk, static_cast<uint32_t>(bin_size));
        std::memcpy(chunk + 4, "BIN\0", 4);
        *bin = chunk + 8;
    }
    *out = glb;
    *out_size = total;
    return MER_OK;
}

}  // namespace merp_gltf

extern "C" mer_result mer_gltf_write_tree(const mer_mesh *mesh, const mer_gltf_meta *meta,
                                          const mer_gltf_options *options, uint8_t **out,
                                          size_t *out_size, mer_error *err)
{
    if (out == nullptr || out_size == nullptr || mesh == nullptr)
        return mer_error_set(err, MER_ERR_INVALID, nullptr, "no mesh or output pointers given");
    const mer_gltf_options defaults{};
    return write_checked(*mesh, meta, options != nullptr ? *options : defaults, out, out_size, err);
}

extern "C" void mer_gltf_free(void *bytes)
{
    merp_free(bytes);
}
