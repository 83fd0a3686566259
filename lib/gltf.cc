// meristem — glTF 2.0 encoding with tinygltf, behind the C API of meristem/gltf.h.
//
// The only C++ in libmeristem. tinygltf's implementation is compiled here with
// image loading and file-system access compiled out: meristem writes geometry,
// never textures, and lib does no I/O.
#include "config.h"

#define TINYGLTF_IMPLEMENTATION
#include "tinygltf_private.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <array>
#include <cfloat>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <mutex>
#include <new>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <vector>

#include <meristem/gltf.h>
#include <meristem/mesh.h>
#include <meristem/version.h>

namespace {

// One run of bytes in the BIN chunk, filled from caller memory at write time so
// the big arrays are copied exactly once.
enum class Fill { Copy, U32ToF32, U32ToU16, QuantizePosition, QuantizeNormal, QuantizeColor };

struct Blob {
    const void *src;
    size_t count;      // elements
    size_t elem;       // source bytes per element (Copy) or 4 (conversions)
    Fill fill;
    size_t offset;     // in the BIN chunk
    size_t size;       // bytes written
    bool triangles;    // an index view of triangles (not of line segments)
};

// The uniform grid quantized positions live on: p = center + scale · q.
struct Grid {
    double center[3] = {0, 0, 0};
    double scale = 1;
};

// Round half away from zero, clamped: inline, no libm call per component.
inline int round_clamped(double x, int limit)
{
    x = std::max(-static_cast<double>(limit), std::min(static_cast<double>(limit), x));
    return x >= 0 ? static_cast<int>(x + 0.5) : -static_cast<int>(0.5 - x);
}

inline int16_t quantize_position(float p, const Grid &g, int k)
{
    return static_cast<int16_t>(round_clamped((static_cast<double>(p) - g.center[k]) / g.scale, 32767));
}

inline int8_t quantize_normal(float n)
{
    return static_cast<int8_t>(round_clamped(static_cast<double>(n) * 127.0, 127));
}

// A colour channel in [0, 1] as a normalized UNSIGNED_BYTE.
inline uint8_t quantize_unit(float c)
{
    return static_cast<uint8_t>(std::max(0, round_clamped(static_cast<double>(c) * 255.0, 255)));
}

// Output bytes per element: Copy keeps the source width; a quantized position
// is 3 SHORTs padded to 8 bytes, a quantized normal 3 BYTEs padded to 4, a
// quantized colour 4 UNSIGNED_BYTEs.
size_t out_elem(Fill fill, size_t elem)
{
    switch (fill) {
    case Fill::Copy: return elem;
    case Fill::U32ToF32: return 4;
    case Fill::U32ToU16: return 2;
    case Fill::QuantizePosition: return 8;
    case Fill::QuantizeNormal: return 4;
    case Fill::QuantizeColor: return 4;
    }
    return elem;
}

struct Writer {
    tinygltf::Model model;
    std::vector<Blob> blobs;
    size_t bin_size = 0;
    bool quantized = false;
    Grid grid;

    Writer()
    {
        model.asset.version = "2.0";
        model.asset.generator = std::string("meristem ") + mer_version();
        model.buffers.resize(1);
    }

    int view(const void *src, size_t count, size_t elem, Fill fill, int target, int stride = 0,
             bool triangles = false)
    {
        Blob b{src, count, elem, fill, bin_size, count * out_elem(fill, elem), triangles};
        bin_size += (b.size + 3u) & ~size_t{3};  // every view starts 4-aligned
        blobs.push_back(b);

        tinygltf::BufferView v;
        v.buffer = 0;
        v.byteOffset = b.offset;
        v.byteLength = b.size;
        v.byteStride = static_cast<size_t>(stride);
        v.target = target;
        model.bufferViews.push_back(v);
        return static_cast<int>(model.bufferViews.size() - 1);
    }

    int accessor(int view_index, size_t byte_offset, int component, int type, size_t count)
    {
        tinygltf::Accessor a;
        a.bufferView = view_index;
        a.byteOffset = byte_offset;
        a.componentType = component;
        a.type = type;
        a.count = count;
        model.accessors.push_back(a);
        return static_cast<int>(model.accessors.size() - 1);
    }

    // A vertex attribute of a whole part: one bufferView that every chunk's
    // accessor reads at its own offset (hence a byteStride, glTF 2.0 §3.6.2.4).
    int vertex_view(const void *src, size_t vertices, int components, Fill fill = Fill::Copy)
    {
        if (fill == Fill::QuantizePosition || fill == Fill::QuantizeNormal ||
            fill == Fill::QuantizeColor) {
            size_t stride = out_elem(fill, 0);
            return view(src, vertices, 0, fill, TINYGLTF_TARGET_ARRAY_BUFFER, static_cast<int>(stride));
        }
        return view(src, vertices * static_cast<size_t>(components), 4, fill,
                    TINYGLTF_TARGET_ARRAY_BUFFER, 4 * components);
    }

    // POSITION needs min and max (glTF 2.0 §3.7.2.1), in the stored values:
    // grid integers when quantized.
    int positions(int view_index, const float *p, size_t first, size_t count, bool quantize)
    {
        int a = quantize ? accessor(view_index, first * 8, TINYGLTF_COMPONENT_TYPE_SHORT,
                                    TINYGLTF_TYPE_VEC3, count)
                         : accessor(view_index, first * 12, TINYGLTF_COMPONENT_TYPE_FLOAT,
                                    TINYGLTF_TYPE_VEC3, count);
        float lo_f[3] = {FLT_MAX, FLT_MAX, FLT_MAX}, hi_f[3] = {-FLT_MAX, -FLT_MAX, -FLT_MAX};
        for (size_t i = first; i < first + count; i++)
            for (size_t k = 0; k < 3; k++) {
                lo_f[k] = std::min(lo_f[k], p[3 * i + k]);
                hi_f[k] = std::max(hi_f[k], p[3 * i + k]);
            }
        // Quantization is monotonic, so the bounds of the stored integers are
        // the quantized float bounds.
        std::vector<double> lo(3), hi(3);
        for (int k = 0; k < 3; k++) {
            size_t kk = static_cast<size_t>(k);
            lo[kk] = quantize ? quantize_position(lo_f[kk], grid, k) : static_cast<double>(lo_f[kk]);
            hi[kk] = quantize ? quantize_position(hi_f[kk], grid, k) : static_cast<double>(hi_f[kk]);
        }
        model.accessors[static_cast<size_t>(a)].minValues = lo;
        model.accessors[static_cast<size_t>(a)].maxValues = hi;
        return a;
    }

    int indices(const uint32_t *idx, size_t count, size_t vertex_count, bool triangles)
    {
        bool narrow = vertex_count <= 0xFFFF;
        int v = view(idx, count, 4, narrow ? Fill::U32ToU16 : Fill::Copy,
                     TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER, 0, triangles);
        return accessor(v, 0, narrow ? TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT
                                     : TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT,
                        TINYGLTF_TYPE_SCALAR, count);
    }

    void fill(uint8_t *bin) const
    {
        for (const Blob &b : blobs)
            fill(b, bin);
    }

    // One blob's bytes (and the padding after them) at its offset in `bin`.
    void fill(const Blob &b, uint8_t *bin) const
    {
        uint8_t *dst = bin + b.offset;
        switch (b.fill) {
        case Fill::Copy:
            std::memcpy(dst, b.src, b.size);
            break;
        case Fill::U32ToF32: {
            const uint32_t *src = static_cast<const uint32_t *>(b.src);
            for (size_t i = 0; i < b.count; i++) {
                float f = static_cast<float>(src[i]);
                std::memcpy(dst + 4 * i, &f, 4);
            }
            break;
        }
        case Fill::QuantizePosition: {
            const float *src = static_cast<const float *>(b.src);
            for (size_t i = 0; i < b.count; i++) {
                int16_t q[4] = {quantize_position(src[3 * i], grid, 0),
                                quantize_position(src[3 * i + 1], grid, 1),
                                quantize_position(src[3 * i + 2], grid, 2), 0};
                std::memcpy(dst + 8 * i, q, 8);
            }
            break;
        }
        case Fill::QuantizeNormal: {
            const float *src = static_cast<const float *>(b.src);
            for (size_t i = 0; i < b.count; i++) {
                int8_t q[4] = {quantize_normal(src[3 * i]), quantize_normal(src[3 * i + 1]),
                               quantize_normal(src[3 * i + 2]), 0};
                std::memcpy(dst + 4 * i, q, 4);
            }
            break;
        }
        case Fill::QuantizeColor: {
            const float *src = static_cast<const float *>(b.src);
            for (size_t i = 0; i < 4 * b.count; i++)
                dst[i] = quantize_unit(src[i]);
            break;
        }
        case Fill::U32ToU16: {
            const uint32_t *src = static_cast<const uint32_t *>(b.src);
            for (size_t i = 0; i < b.count; i++) {
                uint16_t h = static_cast<uint16_t>(src[i]);
                std::memcpy(dst + 2 * i, &h, 2);
            }
            break;
        }
        }
        std::memset(dst + b.size, 0, ((b.size + 3u) & ~size_t{3}) - b.size);
    }
};

int add_material(tinygltf::Model &model, const char *name, const double rgba[4], double roughness,
                 bool double_sided)
{
    tinygltf::Material m;
    m.name = name;
    m.pbrMetallicRoughness.baseColorFactor = {rgba[0], rgba[1], rgba[2], rgba[3]};
    m.pbrMetallicRoughness.metallicFactor = 0.0;
    m.pbrMetallicRoughness.roughnessFactor = roughness;
    m.doubleSided = double_sided;
    model.materials.push_back(m);
    return static_cast<int>(model.materials.size() - 1);
}

// `prefix` names the part in error fields ("bark." gives "bark.indices").
mer_result check_part(const mer_mesh_part &p, const std::string &prefix, mer_error *err)
{
    const std::string indices = prefix + "indices", positions = prefix + "positions",
                      ids = prefix + "node_ids";
    if (p.vertex_count == 0)
        return MER_OK;
    if (p.positions == nullptr)
        return mer_error_set(err, MER_ERR_INVALID, positions.c_str(), "no vertex positions given");
    if (p.indices == nullptr || p.index_count == 0 || p.index_count % 3 != 0)
        return mer_error_set(err, MER_ERR_INVALID, indices.c_str(),
                             "triangle indices must be a positive multiple of 3, got %u",
                             p.index_count);
    const std::string lines = prefix + "line_indices";
    if (p.line_index_count % 2 != 0 || (p.line_index_count > 0 && p.line_indices == nullptr))
        return mer_error_set(err, MER_ERR_INVALID, lines.c_str(),
                             "line indices must come in pairs, got %u", p.line_index_count);
    if (p.chunks == nullptr || p.chunk_count == 0)
        return mer_error_set(err, MER_ERR_INVALID, indices.c_str(), "no chunks given");
    uint32_t next_vertex = 0, next_index = 0, next_line = 0;
    for (uint32_t c = 0; c < p.chunk_count; c++) {
        const mer_mesh_chunk &ch = p.chunks[c];
        if (ch.first_vertex != next_vertex || ch.first_index != next_index || ch.vertex_count == 0 ||
            ch.index_count == 0 || ch.index_count % 3 != 0)
            return mer_error_set(err, MER_ERR_INVALID, indices.c_str(),
                                 "chunk %u does not continue where chunk %u ended", c, c - 1);
        for (uint32_t i = ch.first_index; i < ch.first_index + ch.index_count; i++)
            if (p.indices[i] >= ch.vertex_count)
                return mer_error_set(err, MER_ERR_RANGE, indices.c_str(),
                                     "index %u is %u, past the last vertex %u of its chunk", i,
                                     p.indices[i], ch.vertex_count - 1);
        if (ch.line_index_count > 0 &&
            (ch.first_line_index != next_line || ch.line_index_count % 2 != 0 ||
             ch.line_index_count > p.line_index_count - next_line))
            return mer_error_set(err, MER_ERR_INVALID, lines.c_str(),
                                 "chunk %u's line indices do not continue the last ones", c);
        for (uint32_t i = ch.first_line_index; i < ch.first_line_index + ch.line_index_count; i++)
            if (p.line_indices[i] >= ch.vertex_count)
                return mer_error_set(err, MER_ERR_RANGE, lines.c_str(),
                                     "line index %u is %u, past the last vertex %u of its chunk", i,
                                     p.line_indices[i], ch.vertex_count - 1);
        next_vertex += ch.vertex_count;
        next_index += ch.index_count;
        next_line += ch.line_index_count;
    }
    if (next_line != p.line_index_count)
        return mer_error_set(err, MER_ERR_INVALID, lines.c_str(),
                             "the chunks cover %u of %u line indices", next_line, p.line_index_count);
    if (next_vertex != p.vertex_count || next_index != p.index_count)
        return mer_error_set(err, MER_ERR_INVALID, indices.c_str(),
                             "the chunks cover %u of %u vertices and %u of %u indices", next_vertex,
                             p.vertex_count, next_index, p.index_count);
    for (size_t i = 0; i < 3 * size_t{p.vertex_count}; i++)
        if (!std::isfinite(p.positions[i]))
            return mer_error_set(err, MER_ERR_RANGE, positions.c_str(),
                                 "vertex %zu has a non-finite coordinate", i / 3);
    if (p.node_ids != nullptr)
        for (size_t i = 0; i < p.vertex_count; i++)
            if (p.node_ids[i] >= MER_GLTF_NODE_ID_LIMIT)
                return mer_error_set(err, MER_ERR_RANGE, ids.c_str(),
                                     "node id %u of vertex %zu is not below 2^24, the largest "
                                     "integer a float attribute holds exactly",
                                     p.node_ids[i], i);
    return MER_OK;
}

// Checks and encodes; `prefix` as for check_part.
mer_result write_checked(const mer_mesh &mesh, const mer_gltf_meta *meta,
                         const mer_gltf_options &options, const std::string &prefix, uint8_t **out,
                         size_t *out_size, mer_error *err);

// One primitive per chunk; the attribute bufferViews are shared by the chunks.
// A chunk of twigs' prisms (mesh.h, Twig lines) is marked {"twig": true} in its
// extras, and followed by a LINES primitive of its twig lines, in `line_material`,
// on the same POSITION (and COLOR_0) accessors, with {"twig_diameter_max": d}.
void add_triangles(Writer &w, tinygltf::Mesh &mesh, const mer_mesh_part &p, int material,
                   int line_material = -1, double twig_diameter_max = 0)
{
    if (p.vertex_count == 0)
        return;
    const size_t n = p.vertex_count;
    const bool q = w.quantized;
    const int pos = w.vertex_view(p.positions, n, 3, q ? Fill::QuantizePosition : Fill::Copy);
    const int nrm = p.normals != nullptr
                        ? w.vertex_view(p.normals, n, 3, q ? Fill::QuantizeNormal : Fill::Copy)
                        : -1;
    const int uv = p.uvs != nullptr ? w.vertex_view(p.uvs, n, 2) : -1;
    const int col = p.colors != nullptr
                        ? w.vertex_view(p.colors, n, 4, q ? Fill::QuantizeColor : Fill::Copy)
                        : -1;
    const int ids = p.node_ids != nullptr ? w.vertex_view(p.node_ids, n, 1, Fill::U32ToF32) : -1;
    for (uint32_t c = 0; c < p.chunk_count; c++) {
        const mer_mesh_chunk &ch = p.chunks[c];
        const size_t first = ch.first_vertex, count = ch.vertex_count;
        tinygltf::Primitive prim;
        prim.mode = TINYGLTF_MODE_TRIANGLES;
        prim.material = material;
        if (ch.twig)
            prim.extras = tinygltf::Value(tinygltf::Value::Object{{"twig", tinygltf::Value(true)}});
        prim.attributes["POSITION"] = w.positions(pos, p.positions, first, count, q);
        if (nrm >= 0) {
            prim.attributes["NORMAL"] =
                q ? w.accessor(nrm, first * 4, TINYGLTF_COMPONENT_TYPE_BYTE, TINYGLTF_TYPE_VEC3, count)
                  : w.accessor(nrm, first * 12, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3,
                               count);
            if (q)
                w.model.accessors.back().normalized = true;
        }
        if (uv >= 0)
            prim.attributes["TEXCOORD_0"] = w.accessor(uv, first * 8, TINYGLTF_COMPONENT_TYPE_FLOAT,
                                                       TINYGLTF_TYPE_VEC2, count);
        if (col >= 0) {
            prim.attributes["COLOR_0"] =
                q ? w.accessor(col, first * 4, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_TYPE_VEC4,
                               count)
                  : w.accessor(col, first * 16, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC4, count);
            if (q)
                w.model.accessors.back().normalized = true;
        }
        // Node ids as FLOAT: UNSIGNED_INT is for indices only.
        if (ids >= 0)
            prim.attributes["_NODE_ID"] = w.accessor(ids, first * 4, TINYGLTF_COMPONENT_TYPE_FLOAT,
                                                     TINYGLTF_TYPE_SCALAR, count);
        prim.indices = w.indices(p.indices + ch.first_index, ch.index_count, count, true);
        mesh.primitives.push_back(prim);
        if (ch.line_index_count > 0 && line_material >= 0) {
            tinygltf::Primitive lines;
            lines.mode = TINYGLTF_MODE_LINE;
            lines.material = line_material;
            lines.attributes["POSITION"] = prim.attributes["POSITION"];
            if (col >= 0)
                lines.attributes["COLOR_0"] = prim.attributes["COLOR_0"];
            lines.indices = w.indices(p.line_indices + ch.first_line_index, ch.line_index_count,
                                      count, false);
            lines.extras = tinygltf::Value(tinygltf::Value::Object{
                {"twig_diameter_max", tinygltf::Value(twig_diameter_max)}});
            mesh.primitives.push_back(lines);
        }
    }
}

int add_node(tinygltf::Model &model, const char *name, tinygltf::Mesh &&mesh)
{
    mesh.name = name;
    model.meshes.push_back(std::move(mesh));
    tinygltf::Node node;
    node.name = name;
    node.mesh = static_cast<int>(model.meshes.size() - 1);
    model.nodes.push_back(node);
    return static_cast<int>(model.nodes.size() - 1);
}

void add_extras(tinygltf::Model &model, const mer_gltf_meta *meta)
{
    if (meta == nullptr)
        return;
    tinygltf::Value::Object o;
    if (meta->session != nullptr)
        o["session"] = tinygltf::Value(std::string(meta->session));
    o["revision"] = tinygltf::Value(static_cast<double>(meta->revision));
    o["step"] = tinygltf::Value(static_cast<int>(meta->step));
    if (meta->preset != nullptr)
        o["preset"] = tinygltf::Value(std::string(meta->preset));
    if (meta->seed < (uint64_t{1} << 53))
        o["seed"] = tinygltf::Value(static_cast<double>(meta->seed));
    else
        o["seed"] = tinygltf::Value(std::to_string(meta->seed));
    tinygltf::Value::Object options;
    options["detail"] = tinygltf::Value(static_cast<int>(meta->detail));
    options["leaves"] = tinygltf::Value(meta->leaves != 0);
    options["markers"] = tinygltf::Value(meta->markers != 0);
    static const char *const colors[] = {"none", "order", "light", "age"};
    options["color"] = tinygltf::Value(std::string(meta->color < 4 ? colors[meta->color] : "none"));
    o["mesh_options"] = tinygltf::Value(options);
    model.asset.extras = tinygltf::Value(o);
}

// The quantization grid: centred on the bounding box of bark and leaves, one
// uniform step so that the largest half-extent spans ±32767.
Grid grid_for(const mer_mesh &mesh)
{
    double lo[3] = {DBL_MAX, DBL_MAX, DBL_MAX}, hi[3] = {-DBL_MAX, -DBL_MAX, -DBL_MAX};
    for (const mer_mesh_part *p : {&mesh.bark, &mesh.leaves})
        for (size_t i = 0; i < p->vertex_count; i++)
            for (size_t k = 0; k < 3; k++) {
                double x = p->positions[3 * i + k];
                lo[k] = std::min(lo[k], x);
                hi[k] = std::max(hi[k], x);
            }
    Grid g;
    double half = 0;
    for (size_t k = 0; k < 3; k++) {
        if (lo[k] > hi[k])
            return g;
        g.center[k] = 0.5 * (lo[k] + hi[k]);
        half = std::max(half, 0.5 * (hi[k] - lo[k]));
    }
    g.scale = half > 0 ? half / 32767.0 : 1.0;
    return g;
}

// Lays out the whole scene graph; the BIN bytes stay in the caller's arrays.
void build_tree(Writer &w, const mer_mesh &mesh, const mer_gltf_meta *meta)
{
    if (w.quantized)
        w.grid = grid_for(mesh);
    tinygltf::Model &model = w.model;
    add_extras(model, meta);
    tinygltf::Scene scene;
    scene.name = "meristem";

    const bool colored = mesh.bark.colors != nullptr || mesh.leaves.colors != nullptr;
    // Vertex colours multiply the base colour, so debug colours get a white base.
    const double bark_rgba[4] = {0.11, 0.07, 0.045, 1.0}, white[4] = {1, 1, 1, 1};
    const double leaf_rgba[4] = {0.20, 0.42, 0.10, 1.0}, marker_rgba[4] = {0.55, 0.55, 0.55, 1.0};
    tinygltf::Mesh tree;
    if (mesh.bark.vertex_count > 0) {
        int bark = add_material(model, "bark", colored ? white : bark_rgba, 0.9, false);
        int twig = mesh.bark.line_index_count > 0
                       ? add_material(model, "twig", colored ? white : bark_rgba, 0.9, false)
                       : -1;
        add_triangles(w, tree, mesh.bark, bark, twig, static_cast<double>(mesh.twig_diameter_max));
    }
    if (mesh.leaves.vertex_count > 0)
        add_triangles(w, tree, mesh.leaves,
                      add_material(model, "leaf", colored ? white : leaf_rgba, 0.6, true));
    if (!tree.primitives.empty()) {
        int node = add_node(model, "tree", std::move(tree));
        if (w.quantized) {
            tinygltf::Node &n = model.nodes[static_cast<size_t>(node)];
            n.translation = {w.grid.center[0], w.grid.center[1], w.grid.center[2]};
            n.scale = {w.grid.scale, w.grid.scale, w.grid.scale};
            model.extensionsUsed.push_back("KHR_mesh_quantization");
            model.extensionsRequired.push_back("KHR_mesh_quantization");
        }
        scene.nodes.push_back(node);
    }

    if (mesh.point_count > 0) {
        tinygltf::Primitive points;
        points.mode = TINYGLTF_MODE_POINTS;
        points.material = add_material(model, "marker", marker_rgba, 1.0, false);
        int view = w.vertex_view(mesh.points, mesh.point_count, 3);
        points.attributes["POSITION"] = w.positions(view, mesh.points, 0, mesh.point_count, false);
        tinygltf::Mesh markers;
        markers.primitives.push_back(points);
        scene.nodes.push_back(add_node(model, "markers", std::move(markers)));
    }
    model.scenes.push_back(scene);
    model.defaultScene = 0;
}

mer_result to_bytes(const std::string &text, uint8_t **out, size_t *out_size, mer_error *err)
{
    uint8_t *copy = static_cast<uint8_t *>(std::malloc(text.size()));
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

// Lays out header, JSON chunk and BIN chunk (glTF 2.0 §4.4); `fill_bin` writes
// the `bin_size` BIN bytes in place.
template <typename F>
mer_result assemble_glb(const nlohmann::json &doc, size_t bin_size, F &&fill_bin, uint8_t **out,
                        size_t *out_size, mer_error *err)
{
    std::string text = doc.dump();
    text.append((4 - text.size() % 4) % 4, ' ');  // the JSON chunk pads with spaces
    const size_t total = 12 + 8 + text.size() + (bin_size ? 8 + bin_size : 0);
    if (total > UINT32_MAX)
        return mer_error_set(err, MER_ERR_LIMIT, nullptr,
                             "the GLB would be %zu bytes, over the format's 4 GiB; lower the detail",
                             total);
    uint8_t *glb = static_cast<uint8_t *>(std::malloc(total));
    if (glb == nullptr)
        return mer_error_set(err, MER_ERR_NOMEM, nullptr, "out of memory for %zu GLB bytes", total);
    std::memcpy(glb, "glTF", 4);
    put_u32(glb + 4, 2);
    put_u32(glb + 8, static_cast<uint32_t>(total));
    put_u32(glb + 12, static_cast<uint32_t>(text.size()));
    std::memcpy(glb + 16, "JSON", 4);
    std::memcpy(glb + 20, text.data(), text.size());
    if (bin_size) {
        uint8_t *chunk = glb + 20 + text.size();
        put_u32(chunk, static_cast<uint32_t>(bin_size));
        std::memcpy(chunk + 4, "BIN\0", 4);
        fill_bin(chunk + 8);
    }
    *out = glb;
    *out_size = total;
    return MER_OK;
}

// GLB with the BIN data straight from the caller's arrays.
mer_result write_binary(Writer &w, uint8_t **out, size_t *out_size, mer_error *err)
{
    return assemble_glb(json_of(w), w.bin_size, [&w](uint8_t *bin) { w.fill(bin); }, out,
                        out_size, err);
}

// EXT_meshopt_compression asks for index codec 1 and vertex codec 0; the
// library's version switches are process-wide, so they are set once.
void meshopt_versions()
{
    static std::once_flag once;
    std::call_once(once, [] {
        meshopt_encodeIndexVersion(1);
        meshopt_encodeVertexVersion(0);
    });
}

// One past the largest of an index blob's indices (the encoder's bound needs it).
size_t index_bound(const Blob &b)
{
    const uint32_t *index = static_cast<const uint32_t *>(b.src);
    uint32_t top = 0;
    for (size_t i = 0; i < b.count; i++)
        top = std::max(top, index[i]);
    return size_t{top} + 1;
}

// GLB with every bufferView compressed (see gltf.h). Each view is laid out
// uncompressed, then encoded, into a region of its own sized for the worst case,
// on two threads (the views split by size, a fixed split: the same bytes every
// time); the regions are then packed in view order. Encoding is most of a
// compressed snapshot's time, and views do not depend on each other.
mer_result write_meshopt(Writer &w, uint8_t **out, size_t *out_size, mer_error *err)
{
    meshopt_versions();
    nlohmann::json doc = json_of(w);
    const size_t n = w.blobs.size();
    std::unique_ptr<uint8_t[]> raw(new uint8_t[w.bin_size + 1]);
    std::vector<size_t> bound(n), region(n + 1, 0), written(n, 0), stride(n), count(n);
    for (size_t i = 0; i < n; i++) {
        const Blob &b = w.blobs[i];
        const tinygltf::BufferView &view = w.model.bufferViews[i];
        const bool indices = view.target == TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER;
        stride[i] = indices ? b.size / b.count : view.byteStride;
        count[i] = indices ? b.count : b.size / stride[i];
        bound[i] = 3 + (!indices      ? meshopt_encodeVertexBufferBound(count[i], stride[i])
                        : b.triangles ? meshopt_encodeIndexBufferBound(b.count, index_bound(b))
                                      : meshopt_encodeIndexSequenceBound(b.count, index_bound(b)));
        region[i + 1] = region[i] + bound[i];
    }
    std::unique_ptr<uint8_t[]> packed(new uint8_t[region[n] + 1]);
    auto encode = [&](size_t i) {
        const Blob &b = w.blobs[i];
        w.fill(b, raw.get());
        uint8_t *dst = packed.get() + region[i];
        if (w.model.bufferViews[i].target == TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER) {
            // The encoder reads 32-bit indices: the caller's own array. TRIANGLES
            // mode may rotate a triangle's corners (keeping its winding); the
            // node-id rule does not depend on the order (see mesh.h, Picking).
            // Line segments take INDICES mode, which keeps every index as it is.
            const uint32_t *src = static_cast<const uint32_t *>(b.src);
            written[i] = b.triangles ? meshopt_encodeIndexBuffer(dst, bound[i], src, count[i])
                                     : meshopt_encodeIndexSequence(dst, bound[i], src, count[i]);
        } else {
            written[i] = meshopt_encodeVertexBuffer(dst, bound[i], raw.get() + b.offset, count[i],
                                                    stride[i]);
        }
    };
    // The biggest views first, each to the thread with less work so far.
    std::vector<size_t> order(n);
    for (size_t i = 0; i < n; i++)
        order[i] = i;
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return w.blobs[a].size > w.blobs[b].size; });
    std::vector<size_t> mine, theirs;
    size_t my_bytes = 0, their_bytes = 0;
    for (size_t i : order) {
        (my_bytes <= their_bytes ? mine : theirs).push_back(i);
        (my_bytes <= their_bytes ? my_bytes : their_bytes) += w.blobs[i].size;
    }
    std::thread helper;
    try {
        helper = std::thread([&]() {
            for (size_t i : theirs)
                encode(i);
        });
    } catch (const std::system_error &) {
        mine.insert(mine.end(), theirs.begin(), theirs.end());  // no thread: do it all here
    }
    for (size_t i : mine)
        encode(i);
    if (helper.joinable())
        helper.join();

    size_t at = 0;
    for (size_t i = 0; i < n; i++) {
        if (written[i] == 0)
            return mer_error_set(err, MER_ERR_INTERNAL, nullptr,
                                 "meshoptimizer could not encode bufferView %zu", i);
        const bool indices = w.model.bufferViews[i].target == TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER;
        std::memmove(packed.get() + at, packed.get() + region[i], written[i]);
        const size_t padded = (written[i] + 3u) & ~size_t{3};  // views start 4-aligned
        std::memset(packed.get() + at + written[i], 0, padded - written[i]);
        nlohmann::json ext = {{"buffer", 0},
                              {"byteOffset", at},
                              {"byteLength", written[i]},
                              {"byteStride", stride[i]},
                              {"count", count[i]},
                              {"mode", !indices                ? "ATTRIBUTES"
                                       : w.blobs[i].triangles ? "TRIANGLES"
                                                              : "INDICES"}};
        nlohmann::json &v = doc["bufferViews"][i];
        v["buffer"] = 1;
        v["extensions"]["EXT_meshopt_compression"] = ext;
        at += padded;
    }
    doc["buffers"] = nlohmann::json::array(
        {{{"byteLength", at}},
         {{"byteLength", w.bin_size}, {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}}});
    doc["extensionsUsed"].push_back("EXT_meshopt_compression");
    doc["extensionsRequired"].push_back("EXT_meshopt_compression");
    const uint8_t *bytes = packed.get();
    return assemble_glb(doc, at, [bytes, at](uint8_t *bin) { std::memcpy(bin, bytes, at); }, out,
                        out_size, err);
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

template <typename F>
mer_result guarded(mer_error *err, F &&body)
{
    try {
        return body();
    } catch (const std::bad_alloc &) {
        return mer_error_set(err, MER_ERR_NOMEM, nullptr, "out of memory while encoding glTF");
    } catch (const std::exception &e) {
        return mer_error_set(err, MER_ERR_INTERNAL, nullptr, "glTF encoding failed: %s", e.what());
    } catch (...) {
        return mer_error_set(err, MER_ERR_INTERNAL, nullptr, "glTF encoding failed");
    }
}

}  // namespace

namespace {

mer_result write_checked(const mer_mesh &mesh, const mer_gltf_meta *meta,
                         const mer_gltf_options &options, const std::string &prefix, uint8_t **out,
                         size_t *out_size, mer_error *err)
{
    *out = nullptr;
    *out_size = 0;
    if (options.format != MER_GLTF_BINARY && options.format != MER_GLTF_EMBEDDED)
        return mer_error_set(err, MER_ERR_RANGE, "format", "format must be binary or embedded");
    if (options.unquantized > 1)
        return mer_error_set(err, MER_ERR_RANGE, "unquantized", "must be 0 or 1");
    if (options.compression > MER_GLTF_MESHOPT)
        return mer_error_set(err, MER_ERR_RANGE, "compression", "compression must be none or meshopt");
    if (options.compression != MER_GLTF_UNCOMPRESSED && options.format != MER_GLTF_BINARY)
        return mer_error_set(err, MER_ERR_RANGE, "compression",
                             "meshopt compression is for binary glTF (.glb) only");
    return guarded(err, [&]() {
        mer_result rc = check_part(mesh.bark, prefix.empty() ? prefix : prefix + "bark.", err);
        if (rc == MER_OK)
            rc = check_part(mesh.leaves, prefix.empty() ? prefix : prefix + "leaves.", err);
        if (rc == MER_OK && mesh.leaves.line_index_count != 0)
            rc = mer_error_set(err, MER_ERR_INVALID, (prefix + "leaves.line_indices").c_str(),
                               "only bark has twig lines");
        if (rc != MER_OK)
            return rc;
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

extern "C" mer_result mer_gltf_write_tree(const mer_mesh *mesh, const mer_gltf_meta *meta,
                                          const mer_gltf_options *options, uint8_t **out,
                                          size_t *out_size, mer_error *err)
{
    if (out == nullptr || out_size == nullptr || mesh == nullptr)
        return mer_error_set(err, MER_ERR_INVALID, nullptr, "no mesh or output pointers given");
    const mer_gltf_options defaults{};
    return write_checked(*mesh, meta, options != nullptr ? *options : defaults, "mesh.", out,
                         out_size, err);
}

extern "C" mer_result mer_gltf_write_glb(const mer_gltf_mesh *in, uint8_t **out_glb,
                                         size_t *out_size, mer_error *err)
{
    if (out_glb == nullptr || out_size == nullptr)
        return mer_error_set(err, MER_ERR_INVALID, nullptr, "no output pointers given");
    *out_glb = nullptr;
    *out_size = 0;
    if (in == nullptr)
        return mer_error_set(err, MER_ERR_INVALID, "mesh", "no mesh given");
    if (in->positions == nullptr || in->vertex_count == 0)
        return mer_error_set(err, MER_ERR_INVALID, "positions",
                             "a mesh needs at least one vertex position");
    if (in->vertex_count > UINT32_MAX || in->index_count > UINT32_MAX)
        return mer_error_set(err, MER_ERR_RANGE, "vertex_count",
                             "%zu vertices exceed the 2^32 - 1 that indices can address",
                             in->vertex_count);
    if (in->index_count == 0)
        return mer_error_set(err, MER_ERR_INVALID, "indices", "a mesh needs triangles");
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
    return write_checked(mesh, nullptr, raw, "", out_glb, out_size, err);
}

namespace {

// Column-major 4×4 matrices, as glTF stores them.
using Mat4 = std::array<double, 16>;

Mat4 identity()
{
    return {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
}

Mat4 multiply(const Mat4 &a, const Mat4 &b)
{
    Mat4 m{};
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++) {
            double sum = 0;
            for (int k = 0; k < 4; k++)
                sum += a[static_cast<size_t>(k * 4 + r)] * b[static_cast<size_t>(c * 4 + k)];
            m[static_cast<size_t>(c * 4 + r)] = sum;
        }
    return m;
}

// A node's local transform: its matrix, or T · R · S (glTF 2.0 §3.5.3).
Mat4 local_transform(const tinygltf::Node &n)
{
    if (n.matrix.size() == 16) {
        Mat4 m;
        std::copy(n.matrix.begin(), n.matrix.end(), m.begin());
        return m;
    }
    double t[3] = {0, 0, 0}, q[4] = {0, 0, 0, 1}, s[3] = {1, 1, 1};
    if (n.translation.size() == 3)
        std::copy(n.translation.begin(), n.translation.end(), t);
    if (n.rotation.size() == 4)
        std::copy(n.rotation.begin(), n.rotation.end(), q);
    if (n.scale.size() == 3)
        std::copy(n.scale.begin(), n.scale.end(), s);
    const double x = q[0], y = q[1], z = q[2], w = q[3];
    const double r[9] = {1 - 2 * (y * y + z * z), 2 * (x * y + z * w),     2 * (x * z - y * w),
                         2 * (x * y - z * w),     1 - 2 * (x * x + z * z), 2 * (y * z + x * w),
                         2 * (x * z + y * w),     2 * (y * z - x * w),     1 - 2 * (x * x + y * y)};
    Mat4 m{};
    for (int c = 0; c < 3; c++)
        for (int rr = 0; rr < 3; rr++)
            m[static_cast<size_t>(c * 4 + rr)] = r[c * 3 + rr] * s[c];
    m[12] = t[0];
    m[13] = t[1];
    m[14] = t[2];
    m[15] = 1;
    return m;
}

// Reads component `k` of element `i` of an accessor as a float, decoding
// normalized integers (glTF 2.0 §3.11) and plain integers (KHR_mesh_quantization).
double component(const tinygltf::Model &model, const tinygltf::Accessor &a, size_t i, size_t k)
{
    const tinygltf::BufferView &v = model.bufferViews.at(static_cast<size_t>(a.bufferView));
    const tinygltf::Buffer &buf = model.buffers.at(static_cast<size_t>(v.buffer));
    const int size = tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(a.componentType));
    const size_t comps = static_cast<size_t>(tinygltf::GetNumComponentsInType(static_cast<uint32_t>(a.type)));
    const size_t stride = v.byteStride ? v.byteStride : comps * static_cast<size_t>(size);
    const size_t at = v.byteOffset + a.byteOffset + i * stride + k * static_cast<size_t>(size);
    if (size <= 0 || at + static_cast<size_t>(size) > buf.data.size())
        throw std::out_of_range("accessor reads past its buffer");
    const unsigned char *p = buf.data.data() + at;
    switch (a.componentType) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: { float f; std::memcpy(&f, p, 4); return f; }
    case TINYGLTF_COMPONENT_TYPE_BYTE: { int8_t x; std::memcpy(&x, p, 1); return a.normalized ? std::max(x / 127.0, -1.0) : x; }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: { uint8_t x = *p; return a.normalized ? x / 255.0 : x; }
    case TINYGLTF_COMPONENT_TYPE_SHORT: { int16_t x; std::memcpy(&x, p, 2); return a.normalized ? std::max(x / 32767.0, -1.0) : x; }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { uint16_t x; std::memcpy(&x, p, 2); return a.normalized ? x / 65535.0 : x; }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: { uint32_t x; std::memcpy(&x, p, 4); return x; }
    default: throw std::invalid_argument("unsupported component type");
    }
}

struct TriangleReader {
    const tinygltf::Model &model;
    size_t max_triangles;
    std::vector<float> xyz;

    void primitive(const tinygltf::Primitive &prim, const Mat4 &m)
    {
        if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != -1)
            return;  // points, lines and strips enclose nothing
        auto it = prim.attributes.find("POSITION");
        if (it == prim.attributes.end())
            return;
        const tinygltf::Accessor &pos = model.accessors.at(static_cast<size_t>(it->second));
        if (pos.sparse.isSparse || pos.bufferView < 0)
            throw std::invalid_argument("sparse or buffer-less POSITION accessors are not supported");
        std::vector<uint32_t> idx;
        if (prim.indices >= 0) {
            const tinygltf::Accessor &ia = model.accessors.at(static_cast<size_t>(prim.indices));
            for (size_t i = 0; i < ia.count; i++)
                idx.push_back(static_cast<uint32_t>(component(model, ia, i, 0)));
        } else {
            for (size_t i = 0; i < pos.count; i++)
                idx.push_back(static_cast<uint32_t>(i));
        }
        for (size_t t = 0; t + 2 < idx.size(); t += 3) {
            if (xyz.size() / 9 >= max_triangles)
                throw std::length_error("too many triangles");
            for (size_t c = 0; c < 3; c++) {
                size_t v = idx[t + c];
                if (v >= pos.count)
                    throw std::out_of_range("an index points past the last vertex");
                double p[3] = {component(model, pos, v, 0), component(model, pos, v, 1),
                               component(model, pos, v, 2)};
                for (size_t r = 0; r < 3; r++)
                    xyz.push_back(static_cast<float>(m[r] * p[0] + m[4 + r] * p[1] + m[8 + r] * p[2] + m[12 + r]));
            }
        }
    }

    void node(int index, const Mat4 &parent, int depth)
    {
        if (depth > 64)
            throw std::invalid_argument("the node hierarchy is deeper than 64 or cyclic");
        const tinygltf::Node &n = model.nodes.at(static_cast<size_t>(index));
        Mat4 m = multiply(parent, local_transform(n));
        if (n.mesh >= 0)
            for (const tinygltf::Primitive &p : model.meshes.at(static_cast<size_t>(n.mesh)).primitives)
                primitive(p, m);
        for (int child : n.children)
            node(child, m, depth + 1);
    }
};

}  // namespace

extern "C" mer_result mer_gltf_read_triangles(const uint8_t *bytes, size_t size,
                                              size_t max_triangles, float **out_xyz,
                                              size_t *out_triangles, mer_error *err)
{
    if (out_xyz == nullptr || out_triangles == nullptr || (bytes == nullptr && size > 0))
        return mer_error_set(err, MER_ERR_INVALID, nullptr, "no input or output pointers given");
    *out_xyz = nullptr;
    *out_triangles = 0;
    if (size > UINT32_MAX)
        return mer_error_set(err, MER_ERR_LIMIT, "gltf", "a glTF file is at most 4 GiB");
    return guarded(err, [&]() -> mer_result {
        tinygltf::TinyGLTF loader;
        // No file system: external buffers and images cannot be fetched.
        tinygltf::FsCallbacks fs{};
        fs.FileExists = [](const std::string &, void *) { return false; };
        fs.ExpandFilePath = [](const std::string &path, void *) { return path; };
        fs.ReadWholeFile = [](std::vector<unsigned char> *, std::string *e, const std::string &path, void *) {
            if (e != nullptr)
                *e = "external file '" + path + "' refused: embed buffers in the glTF";
            return false;
        };
        fs.WriteWholeFile = [](std::string *, const std::string &, const std::vector<unsigned char> &, void *) {
            return false;
        };
        loader.SetFsCallbacks(fs);
        tinygltf::Model model;
        std::string error, warning;
        bool glb = size >= 4 && std::memcmp(bytes, "glTF", 4) == 0;
        bool ok = glb ? loader.LoadBinaryFromMemory(&model, &error, &warning, bytes,
                                                    static_cast<unsigned>(size))
                      : loader.LoadASCIIFromString(&model, &error, &warning,
                                                   reinterpret_cast<const char *>(bytes),
                                                   static_cast<unsigned>(size), "");
        if (!ok)
            return mer_error_set(err, MER_ERR_FORMAT, "gltf", "not a readable glTF 2.0 asset: %s",
                                 error.empty() ? "unknown error" : error.c_str());
        TriangleReader reader{model, max_triangles, {}};
        try {
            int scene = model.defaultScene >= 0 ? model.defaultScene : 0;
            if (!model.scenes.empty())
                for (int n : model.scenes.at(static_cast<size_t>(scene)).nodes)
                    reader.node(n, identity(), 0);
        } catch (const std::length_error &) {
            return mer_error_set(err, MER_ERR_LIMIT, "gltf", "the asset has more than %zu triangles",
                                 max_triangles);
        } catch (const std::logic_error &e) {
            return mer_error_set(err, MER_ERR_FORMAT, "gltf", "%s", e.what());
        }
        if (reader.xyz.empty())
            return mer_error_set(err, MER_ERR_FORMAT, "gltf", "the asset's default scene has no triangles");
        float *copy = static_cast<float *>(std::malloc(reader.xyz.size() * sizeof(float)));
        if (copy == nullptr)
            return mer_error_set(err, MER_ERR_NOMEM, nullptr, "out of memory for triangles");
        std::memcpy(copy, reader.xyz.data(), reader.xyz.size() * sizeof(float));
        *out_xyz = copy;
        *out_triangles = reader.xyz.size() / 9;
        return MER_OK;
    });
}

extern "C" void mer_gltf_free(void *bytes)
{
    std::free(bytes);
}
