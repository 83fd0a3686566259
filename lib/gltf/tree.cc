// meristem — a tree mesh as a glTF scene graph: materials, one primitive per
// chunk, twig lines, the markers, the quantization grid and asset.extras
// (see mer_gltf_write_tree in meristem/gltf.h).
#include "config.h"

#include "gltf/gltf_private.h"

#include <cfloat>
#include <cmath>

namespace merp_gltf {

namespace {

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

// A part's vertex attribute bufferViews, shared by its chunks; -1: absent.
struct PartViews {
    int pos, nrm, uv, col, ids, ridge;
};

PartViews part_views(Writer &w, const mer_mesh_part &p)
{
    const size_t n = p.vertex_count;
    const bool q = w.quantized;
    PartViews v;
    v.pos = w.vertex_view(p.positions, n, 3, q ? Fill::QuantizePosition : Fill::Copy);
    v.nrm = p.normals != nullptr ? w.vertex_view(p.normals, n, 3, q ? Fill::QuantizeNormal : Fill::Copy)
                                 : -1;
    v.uv = p.uvs != nullptr ? w.vertex_view(p.uvs, n, 2) : -1;
    v.col = p.colors != nullptr ? w.vertex_view(p.colors, n, 4, q ? Fill::QuantizeColor : Fill::Copy)
                                : -1;
    v.ids = p.node_ids != nullptr ? w.vertex_view(p.node_ids, n, 1, Fill::U32ToF32) : -1;
    v.ridge = p.ridge != nullptr ? w.vertex_view(p.ridge, n, 1) : -1;
    return v;
}

// A chunk's accessor into one of its part's attribute views: FLOAT, or when
// quantized a normalized `quantized` component, one 4-byte element per vertex
// (writer.cc); a `quantized` of FLOAT means the attribute is never quantized.
int attribute(Writer &w, int view, size_t first, size_t count, int type, int quantized)
{
    const size_t components =
        static_cast<size_t>(tinygltf::GetNumComponentsInType(static_cast<uint32_t>(type)));
    if (!w.quantized || quantized == TINYGLTF_COMPONENT_TYPE_FLOAT)
        return w.accessor(view, first * 4 * components, TINYGLTF_COMPONENT_TYPE_FLOAT, type, count);
    int a = w.accessor(view, first * 4, quantized, type, count);
    w.model.accessors.back().normalized = true;
    return a;
}

// The TRIANGLES primitive of one chunk: its accessors into the part's views.
tinygltf::Primitive chunk_triangles(Writer &w, const mer_mesh_part &p, const PartViews &v,
                                    const mer_mesh_chunk &ch, const Box &box, int material)
{
    const size_t first = ch.first_vertex, count = ch.vertex_count;
    const bool q = w.quantized;
    tinygltf::Primitive prim;
    prim.mode = TINYGLTF_MODE_TRIANGLES;
    prim.material = material;
    if (ch.twig)
        prim.extras = tinygltf::Value(tinygltf::Value::Object{{"twig", tinygltf::Value(true)}});
    prim.attributes["POSITION"] = w.positions(v.pos, box, first, count, q);
    // Node ids as FLOAT: UNSIGNED_INT is for indices only.
    const struct {
        const char *name;
        int view, type, quantized;
    } attributes[] = {
        {"NORMAL", v.nrm, TINYGLTF_TYPE_VEC3, TINYGLTF_COMPONENT_TYPE_BYTE},
        {"TEXCOORD_0", v.uv, TINYGLTF_TYPE_VEC2, TINYGLTF_COMPONENT_TYPE_FLOAT},
        {"COLOR_0", v.col, TINYGLTF_TYPE_VEC4, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE},
        {"_NODE_ID", v.ids, TINYGLTF_TYPE_SCALAR, TINYGLTF_COMPONENT_TYPE_FLOAT},
        // b = F_b of an implicit junction (mesh.h, Junctions): 0 on tubes, 1 on the ridge.
        {"_RIDGE", v.ridge, TINYGLTF_TYPE_SCALAR, TINYGLTF_COMPONENT_TYPE_FLOAT},
    };
    for (const auto &a : attributes)
        if (a.view >= 0)
            prim.attributes[a.name] = attribute(w, a.view, first, count, a.type, a.quantized);
    prim.indices = w.indices(p.indices + ch.first_index, ch.index_count, count, true);
    return prim;
}

// One primitive per chunk; the attribute bufferViews are shared by the chunks.
// A chunk of twigs' prisms (mesh.h, Twig lines) is marked {"twig": true} in its
// extras, and followed by a LINES primitive of its twig lines, in `line_material`,
// on the same POSITION (and COLOR_0) accessors, with {"twig_diameter_max": d}.
void add_triangles(Writer &w, tinygltf::Mesh &mesh, const mer_mesh_part &p, const std::vector<Box> &boxes,
                   int material, int line_material = -1, double twig_diameter_max = 0)
{
    if (p.vertex_count == 0)
        return;
    const PartViews v = part_views(w, p);
    for (uint32_t c = 0; c < p.chunk_count; c++) {
        const mer_mesh_chunk &ch = p.chunks[c];
        tinygltf::Primitive prim = chunk_triangles(w, p, v, ch, boxes[c], material);
        mesh.primitives.push_back(prim);
        if (ch.line_index_count == 0 || line_material < 0)
            continue;
        tinygltf::Primitive lines;
        lines.mode = TINYGLTF_MODE_LINE;
        lines.material = line_material;
        lines.attributes["POSITION"] = prim.attributes["POSITION"];
        if (v.col >= 0)
            lines.attributes["COLOR_0"] = prim.attributes["COLOR_0"];
        lines.indices = w.indices(p.line_indices + ch.first_line_index, ch.line_index_count,
                                  ch.vertex_count, false);
        lines.extras = tinygltf::Value(
            tinygltf::Value::Object{{"twig_diameter_max", tinygltf::Value(twig_diameter_max)}});
        mesh.primitives.push_back(lines);
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
    tinygltf::Value::Object units;
    units["length"] = tinygltf::Value(std::string("metre"));
    units["up"] = tinygltf::Value(std::string("+Y"));
    if (meta->internode_length > 0)
        // Parameters are floats: six significant digits say what was asked for.
        units["internode_length"] =
            tinygltf::Value(std::round(meta->internode_length * 1e6) / 1e6);
    o["units"] = tinygltf::Value(units);
    model.asset.extras = tinygltf::Value(o);
}

// Each chunk's bounding box (its POSITION's min and max; the chunks tile
// the part's vertices, check_part says so).
std::vector<Box> chunk_boxes(const mer_mesh_part &p)
{
    std::vector<Box> boxes;
    if (p.vertex_count > 0)
        for (uint32_t c = 0; c < p.chunk_count; c++)
            boxes.push_back(box_of(p.positions, p.chunks[c].first_vertex, p.chunks[c].vertex_count));
    return boxes;
}

// The quantization grid: centred on the bounding box of bark and leaves (of
// their chunks' boxes), one uniform step so that the largest half-extent
// spans ±32767.
Grid grid_for(const std::vector<Box> &bark, const std::vector<Box> &leaves)
{
    double lo[3] = {DBL_MAX, DBL_MAX, DBL_MAX}, hi[3] = {-DBL_MAX, -DBL_MAX, -DBL_MAX};
    for (const std::vector<Box> *boxes : {&bark, &leaves})
        for (const Box &b : *boxes)
            for (size_t k = 0; k < 3; k++) {
                lo[k] = std::min(lo[k], static_cast<double>(b.lo[k]));
                hi[k] = std::max(hi[k], static_cast<double>(b.hi[k]));
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

// Node "tree": bark (and its twig lines) and leaves, placed on the grid when quantized.
void add_tree(Writer &w, const mer_mesh &mesh, const std::vector<Box> &bark_boxes,
              const std::vector<Box> &leaf_boxes, tinygltf::Scene &scene)
{
    tinygltf::Model &model = w.model;
    const bool colored = mesh.bark.colors != nullptr || mesh.leaves.colors != nullptr;
    // Vertex colours multiply the base colour, so debug colours get a white base.
    const double bark_rgba[4] = {0.11, 0.07, 0.045, 1.0}, white[4] = {1, 1, 1, 1};
    const double leaf_rgba[4] = {0.20, 0.42, 0.10, 1.0};
    tinygltf::Mesh tree;
    if (mesh.bark.vertex_count > 0) {
        int bark = add_material(model, "bark", colored ? white : bark_rgba, 0.9, false);
        int twig = mesh.bark.line_index_count > 0
                       ? add_material(model, "twig", colored ? white : bark_rgba, 0.9, false)
                       : -1;
        add_triangles(w, tree, mesh.bark, bark_boxes, bark, twig, static_cast<double>(mesh.twig_diameter_max));
    }
    if (mesh.leaves.vertex_count > 0)
        add_triangles(w, tree, mesh.leaves, leaf_boxes,
                      add_material(model, "leaf", colored ? white : leaf_rgba, 0.6, true));
    if (tree.primitives.empty())
        return;
    int node = add_node(model, "tree", std::move(tree));
    if (mesh.junction_forks != nullptr) {
        // Which forks implicit junctions patched (mesh.h): a viewer's close-up of one
        // cannot tell a patch's own fork from a neighbour's by the ridge alone.
        tinygltf::Value::Array forks;
        for (uint32_t i = 0; i < mesh.junctions; i++)
            forks.emplace_back(static_cast<int>(mesh.junction_forks[i]));
        tinygltf::Value::Object extras;
        extras["junction_forks"] = tinygltf::Value(std::move(forks));
        model.nodes[static_cast<size_t>(node)].extras = tinygltf::Value(std::move(extras));
    }
    if (w.quantized) {
        tinygltf::Node &n = model.nodes[static_cast<size_t>(node)];
        n.translation = {w.grid.center[0], w.grid.center[1], w.grid.center[2]};
        n.scale = {w.grid.scale, w.grid.scale, w.grid.scale};
        model.extensionsUsed.push_back("KHR_mesh_quantization");
        model.extensionsRequired.push_back("KHR_mesh_quantization");
    }
    scene.nodes.push_back(node);
}

}  // namespace

void build_tree(Writer &w, const mer_mesh &mesh, const mer_gltf_meta *meta)
{
    const std::vector<Box> bark_boxes = chunk_boxes(mesh.bark), leaf_boxes = chunk_boxes(mesh.leaves);
    if (w.quantized)
        w.grid = grid_for(bark_boxes, leaf_boxes);
    tinygltf::Model &model = w.model;
    add_extras(model, meta);
    tinygltf::Scene scene;
    scene.name = "meristem";
    add_tree(w, mesh, bark_boxes, leaf_boxes, scene);
    if (mesh.point_count > 0) {
        const double marker_rgba[4] = {0.55, 0.55, 0.55, 1.0};
        tinygltf::Primitive points;
        points.mode = TINYGLTF_MODE_POINTS;
        points.material = add_material(model, "marker", marker_rgba, 1.0, false);
        int view = w.vertex_view(mesh.points, mesh.point_count, 3);
        points.attributes["POSITION"] =
            w.positions(view, box_of(mesh.points, 0, mesh.point_count), 0, mesh.point_count, false);
        tinygltf::Mesh markers;
        markers.primitives.push_back(points);
        scene.nodes.push_back(add_node(model, "markers", std::move(markers)));
    }
    model.scenes.push_back(scene);
    model.defaultScene = 0;
}

}  // namespace merp_gltf
