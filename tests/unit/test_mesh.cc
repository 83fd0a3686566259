// Unit tests for lib/mesh/ and the tree path of lib/gltf/: geometry
// properties that can fail, and a round trip through tinygltf. The GLBs are
// left in $MER_ARTIFACTS for the glTF conformance test.
#include "config.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdarg>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <set>
#include <setjmp.h>
#include <string>
#include <tuple>
#include <vector>

#include <meshoptimizer.h>
#include <nlohmann/json.hpp>

extern "C" {
#include <cmocka.h>
}

#include "scene_helpers.h"

#include "gltf/tinygltf_private.h"


#include <meristem.h>

namespace {

mer_scene *grow(const char *preset, uint32_t steps, uint64_t seed,
                std::vector<std::pair<const char *, double>> sets = {})
{
    mer_params p;
    mer_error err{};
    assert_int_equal(mer_preset_params(preset, &p, &err), MER_OK);
    for (auto &kv : sets)
        if (mer_params_set(&p, kv.first, kv.second, &err) != MER_OK)
            fail_msg("set %s: %s", kv.first, err.message);
    mer_scene *s = new_preset_scene(preset, &p, seed);
    assert_int_equal(mer_scene_step(s, steps, nullptr, nullptr, nullptr, nullptr, &err), MER_OK);
    return s;
}

mer_mesh *mesh_of(const mer_scene *s, mer_mesh_options opt = {})
{
    mer_mesh *m = nullptr;
    mer_error err{};
    if (mer_mesh_build(s, &opt, &m, &err) != MER_OK)
        fail_msg("mesh: %s %s", err.field, err.message);
    return m;
}

// An option out of range is refused, naming it, and nothing is made.
void expect_refused(const mer_scene *s, const mer_mesh_options &opt, const char *field)
{
    mer_mesh *bad = nullptr;
    mer_error err{};
    assert_int_equal(mer_mesh_build(s, &opt, &bad, &err), MER_ERR_RANGE);
    assert_null(bad);
    assert_string_equal(err.field, field);
}

std::vector<uint8_t> glb_of(const mer_mesh *m, const mer_gltf_options *opt = nullptr,
                            const mer_gltf_meta *meta = nullptr)
{
    uint8_t *bytes = nullptr;
    size_t size = 0;
    mer_error err{};
    if (mer_gltf_write_tree(m, meta, opt, &bytes, &size, &err) != MER_OK)
        fail_msg("glTF: %s %s", err.field, err.message);
    std::vector<uint8_t> out(bytes, bytes + size);
    mer_gltf_free(bytes);
    return out;
}

void save_artifact(const char *name, const std::vector<uint8_t> &bytes)
{
    const char *dir = std::getenv("MER_ARTIFACTS");
    if (dir == nullptr || *dir == '\0')
        return;
    FILE *f = std::fopen((std::string(dir) + "/" + name).c_str(), "wb");
    assert_non_null(f);
    assert_int_equal(std::fwrite(bytes.data(), 1, bytes.size(), f), bytes.size());
    std::fclose(f);
}

float dist_to_line(const float *p, const float *a, const float *d)
{
    float v[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
    float t = v[0] * d[0] + v[1] * d[1] + v[2] * d[2];
    float w[3] = {v[0] - t * d[0], v[1] - t * d[1], v[2] - t * d[2]};
    return std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
}

// The trunk's internodes, from the root along main continuations.
std::vector<mer_node> trunk_of(const mer_scene *s)
{
    std::vector<mer_node> out;
    mer_node n{};
    uint32_t id = 0;
    while (id != MER_NO_NODE && mer_scene_node(s, id, &n, nullptr) == MER_OK && n.alive) {
        out.push_back(n);
        id = n.main_child;
    }
    return out;
}

// --------------------------------------------------------------- geometry

void test_normals_are_unit(void **)
{
    mer_scene *s = grow("default", 12, 1);
    mer_mesh_options opt{};
    opt.leaves = 1;
    mer_mesh *m = mesh_of(s, opt);
    assert_true(m->bark.vertex_count > 100);
    assert_true(m->leaves.vertex_count > 0);
    for (const mer_mesh_part *p : {&m->bark, &m->leaves})
        for (uint32_t i = 0; i < p->vertex_count; i++) {
            const float *n = p->normals + 3 * i;
            float len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
            if (std::fabs(len - 1.0f) > 1e-4f)
                fail_msg("normal %u has length %f", i, static_cast<double>(len));
        }
    mer_mesh_free(m);
    mer_scene_free(s);
}

// With ξ = η = 0 a trunk grows dead straight: its rings must lie at the pipe
// model's radius from the line, ring i at internode i's radius.
void test_straight_tube_radius(void **)
{
    mer_scene *s = grow("default", 6, 3, {{"xi", 0}, {"eta", 0}});
    std::vector<mer_node> trunk = trunk_of(s);
    assert_true(trunk.size() >= 3);
    mer_mesh *m = mesh_of(s);
    // The trunk is the first axis: its rings are the first vertices of the bark.
    uint32_t sides = 0;
    while (m->bark.node_ids[sides] == trunk[0].id)
        sides++;
    sides -= 1;  // the seam vertex repeats the first
    assert_true(sides >= 3);
    for (size_t ring = 0; ring + 1 < trunk.size(); ring++) {
        float r = 0.5f * trunk[ring].diameter;
        for (uint32_t j = 0; j <= sides; j++) {
            uint32_t v = static_cast<uint32_t>(ring) * (sides + 1) + j;
            assert_int_equal(m->bark.node_ids[v], trunk[ring].id);
            float d = dist_to_line(m->bark.positions + 3 * v, trunk[0].base, trunk[0].dir);
            if (std::fabs(d - r) > 1e-4f * (1.0f + r))
                fail_msg("ring %zu vertex %u lies %f from the axis, radius %f", ring, j,
                         static_cast<double>(d), static_cast<double>(r));
        }
    }
    mer_mesh_free(m);
    mer_scene_free(s);
}

// v grows along every axis: along the trunk, ring after ring, it never falls.
void test_uv_v_monotonic_and_u_around(void **)
{
    mer_scene *s = grow("fig7-bh-0.54", 10, 3);
    mer_mesh *m = mesh_of(s);
    std::vector<mer_node> trunk = trunk_of(s);
    assert_true(trunk.size() >= 3);
    uint32_t sides = 0;
    while (m->bark.node_ids[sides] == trunk[0].id)
        sides++;
    sides -= 1;
    float last_v = -1.0f;
    for (size_t ring = 0; ring + 1 < trunk.size(); ring++) {
        const float *uv = m->bark.uvs + 2 * (ring * (sides + 1));
        assert_true(uv[1] > last_v);
        for (uint32_t j = 0; j <= sides; j++) {
            assert_true(uv[2 * j + 1] == uv[1]);  // one v per ring: no seam between rings
            assert_true(std::fabs(uv[2 * j] - static_cast<float>(j) / static_cast<float>(sides)) < 1e-6f);
        }
        last_v = uv[1];
    }
    assert_true(last_v > 0.0f);
    mer_mesh_free(m);
    mer_scene_free(s);
}

// A seedling is one internode: a trunk with a base disk and a tip cone. Welded
// by position, every edge of it must belong to exactly two triangles: closed.
void test_tip_has_cap_closed_tube(void **)
{
    mer_scene *s = grow("default", 0, 0);
    mer_mesh *m = mesh_of(s);
    assert_int_equal(m->axes, 1);
    const mer_mesh_part &b = m->bark;
    std::map<std::tuple<float, float, float>, uint32_t> weld;
    std::vector<uint32_t> id(b.vertex_count);
    for (uint32_t i = 0; i < b.vertex_count; i++) {
        auto key = std::make_tuple(b.positions[3 * i], b.positions[3 * i + 1], b.positions[3 * i + 2]);
        auto it = weld.emplace(key, static_cast<uint32_t>(weld.size())).first;
        id[i] = it->second;
    }
    std::map<std::pair<uint32_t, uint32_t>, int> edges;
    for (uint32_t t = 0; t < b.index_count; t += 3)
        for (int k = 0; k < 3; k++) {
            uint32_t a = id[b.indices[t + static_cast<uint32_t>(k)]];
            uint32_t c = id[b.indices[t + static_cast<uint32_t>((k + 1) % 3)]];
            edges[{std::min(a, c), std::max(a, c)}]++;
        }
    for (auto &e : edges)
        if (e.second != 2)
            fail_msg("edge %u-%u is used by %d triangles", e.first.first, e.first.second, e.second);
    // The apex: a vertex at the seedling's tip point.
    mer_node n{};
    assert_int_equal(mer_scene_node(s, 0, &n, nullptr), MER_OK);
    float tip[3] = {n.base[0] + n.dir[0] * n.length, n.base[1] + n.dir[1] * n.length,
                    n.base[2] + n.dir[2] * n.length};
    bool found = false;
    for (uint32_t i = 0; i < b.vertex_count; i++)
        found = found || (std::fabs(b.positions[3 * i] - tip[0]) < 1e-6f &&
                          std::fabs(b.positions[3 * i + 1] - tip[1]) < 1e-6f &&
                          std::fabs(b.positions[3 * i + 2] - tip[2]) < 1e-6f);
    assert_true(found);
    mer_mesh_free(m);
    mer_scene_free(s);
}

// Internodes of no length (an L-system string that branches twice at one
// point, ABOP's Fig. 2.8a ternary tree at every branch's end; guiding
// vectors' shoots that begin with a hop of none, or are nothing else) put
// two rings one on the other: the bark keeps one ring for both, so no
// triangle of it has no area, and every vertex is a triangle's.
void test_no_length_no_flat_bands(void **)
{
    for (const char *preset : {"abop-2.8a", "gv-fig4-1000"}) {
        mer_scene *s = grow(preset, 14, 1);
        uint32_t none = 0;
        for (uint32_t id = 0; id < mer_scene_node_bound(s); id++) {
            mer_node n{};
            assert_int_equal(mer_scene_node(s, id, &n, nullptr), MER_OK);
            none += n.alive && n.length == 0.0f;
        }
        print_message("%s: %u internodes of no length\n", preset, none);
        assert_true(none > 20); // the case is there to be met
        for (bool implicit : {false, true}) {
            mer_mesh_options o{};
            o.junctions = implicit ? MER_JUNCTIONS_IMPLICIT : MER_JUNCTIONS_TUBES;
            mer_mesh *m = mesh_of(s, o);
            const mer_mesh_part &b = m->bark;
            std::vector<bool> used(b.vertex_count);
            uint32_t flat = 0;
            for (uint32_t c = 0; c < b.chunk_count; c++) {
                const mer_mesh_chunk &ch = b.chunks[c];
                for (uint32_t t = 0; t < ch.index_count; t += 3) {
                    const float *p[3];
                    for (uint32_t k = 0; k < 3; k++) {
                        uint32_t v = ch.first_vertex + b.indices[ch.first_index + t + k];
                        used[v] = true;
                        p[k] = b.positions + 3 * static_cast<size_t>(v);
                    }
                    float e1[3], e2[3];
                    for (int k = 0; k < 3; k++)
                        e1[k] = p[1][k] - p[0][k], e2[k] = p[2][k] - p[0][k];
                    float x = e1[1] * e2[2] - e1[2] * e2[1], y = e1[2] * e2[0] - e1[0] * e2[2],
                          z = e1[0] * e2[1] - e1[1] * e2[0];
                    flat += x == 0.0f && y == 0.0f && z == 0.0f;
                }
            }
            print_message("%s, %s: %u triangles, %u of no area, %u of %u vertices in none\n", preset,
                          implicit ? "implicit" : "tubes", b.index_count / 3, flat,
                          static_cast<uint32_t>(std::count(used.begin(), used.end(), false)), b.vertex_count);
            assert_int_equal(flat, 0);
            assert_int_equal(std::count(used.begin(), used.end(), false), 0);
            mer_mesh_free(m);
        }
        mer_scene_free(s);
    }
}

// Picking (mesh.h) where a ring was kept for an internode of no length: an
// axis F(2), then an internode of no length that carries three laterals,
// then F(2) again. The band along the second F(2) names it, not the
// internode of no length below it, which names no triangle at all (a click
// on the continuation once pruned that one, laterals and all).
void test_no_length_names_no_band(void **)
{
    mer_params p;
    mer_error err{};
    assert_int_equal(mer_preset_params("abop-1.24a", &p, &err), MER_OK);
    assert_int_equal(p.model, MER_MODEL_LSYSTEM);
    mer_scene *s = nullptr;
    assert_int_equal(mer_scene_new(&p, 1, &s, &err), MER_OK);
    const char *def = "axiom: !(1)F(2)[&(30)F(1)][/(120)&(30)F(1)][/(240)&(30)F(1)]F(2)\n";
    assert_int_equal(mer_scene_set_definition(s, def, std::strlen(def), &err), MER_OK);
    assert_int_equal(mer_scene_step(s, 1, nullptr, nullptr, nullptr, nullptr, &err), MER_OK);
    mer_mesh *m = mesh_of(s);
    const mer_mesh_part &b = m->bark;
    std::map<uint32_t, uint32_t> named; // internode id -> triangles that name it
    for (uint32_t c = 0; c < b.chunk_count; c++) {
        const mer_mesh_chunk &ch = b.chunks[c];
        for (uint32_t t = 0; t < ch.index_count; t += 3) {
            uint32_t id = UINT32_MAX;
            for (uint32_t k = 0; k < 3; k++)
                id = std::min(id, b.node_ids[ch.first_vertex + b.indices[ch.first_index + t + k]]);
            named[id]++;
        }
    }
    uint32_t none = 0;
    for (uint32_t id = 0; id < mer_scene_node_bound(s); id++) {
        mer_node n{};
        assert_int_equal(mer_scene_node(s, id, &n, nullptr), MER_OK);
        if (!n.alive)
            continue;
        if (n.length == 0.0f) {
            none++;
            assert_int_not_equal(n.main_child, MER_NO_NODE); // in the middle of its axis
            assert_int_equal(named[id], 0);
        } else {
            assert_true(named[id] > 0);
        }
    }
    assert_int_equal(none, 1);
    mer_mesh_free(m);
    mer_scene_free(s);
}

// A pruned axis ends in a flat disk whose normal is the axis direction.
void test_cut_has_flat_cap(void **)
{
    mer_scene *s = grow("default", 8, 4, {{"xi", 0}, {"eta", 0}});
    std::vector<mer_node> trunk = trunk_of(s);
    assert_true(trunk.size() >= 4);
    mer_error err{};
    assert_int_equal(mer_scene_prune(s, trunk[2].id, &err), MER_OK);
    mer_mesh *m = mesh_of(s);
    // Vertices of internode 1 whose normal is the trunk direction: the disk.
    uint32_t disk = 0;
    for (uint32_t i = 0; i < m->bark.vertex_count; i++) {
        const float *n = m->bark.normals + 3 * i;
        if (m->bark.node_ids[i] == trunk[1].id &&
            n[0] * trunk[1].dir[0] + n[1] * trunk[1].dir[1] + n[2] * trunk[1].dir[2] > 0.999f)
            disk++;
    }
    assert_true(disk >= 4);  // centre + at least 3 rim vertices
    mer_mesh_free(m);
    mer_scene_free(s);
}

// The smallest id among a bark triangle's vertices names the internode it covers,
// and it is the first vertex's, so a ray hit resolves to a node; every id is a
// live node of the tree.
void test_node_ids_live_and_first_vertex(void **)
{
    mer_scene *s = grow("default", 12, 5);
    mer_mesh *m = mesh_of(s);
    std::set<uint32_t> seen;
    for (uint32_t i = 0; i < m->bark.vertex_count; i++) {
        mer_node n{};
        assert_int_equal(mer_scene_node(s, m->bark.node_ids[i], &n, nullptr), MER_OK);
        assert_true(n.alive);
        seen.insert(n.id);
    }
    mer_summary sum;
    mer_scene_summary(s, &sum);
    assert_int_equal(seen.size(), sum.internodes);  // every living internode is there
    assert_int_equal(m->internodes, sum.internodes);
    // Each bark triangle's first vertex lies within its internode's span.
    for (uint32_t c = 0; c < m->bark.chunk_count; c++) {
        const mer_mesh_chunk &ch = m->bark.chunks[c];
        for (uint32_t t = ch.first_index; t < ch.first_index + ch.index_count; t += 3) {
            uint32_t v = ch.first_vertex + m->bark.indices[t];
            for (uint32_t k = 1; k < 3; k++)
                assert_true(m->bark.node_ids[v] <= m->bark.node_ids[ch.first_vertex + m->bark.indices[t + k]]);
            mer_node n{};
            mer_scene_node(s, m->bark.node_ids[v], &n, nullptr);
            const float *p = m->bark.positions + 3 * v;
            float rel[3] = {p[0] - n.base[0], p[1] - n.base[1], p[2] - n.base[2]};
            float along = rel[0] * n.dir[0] + rel[1] * n.dir[1] + rel[2] * n.dir[2];
            assert_true(along > -n.diameter - 1e-4f && along < n.length + n.diameter + 1e-4f);
        }
    }
    mer_mesh_free(m);
    mer_scene_free(s);
}

void test_sides_fall_with_diameter_and_detail(void **)
{
    mer_scene *s = grow("fig7-bh-0.54", 25, 6);
    auto count = [&](uint32_t detail) {
        mer_mesh_options opt{};
        opt.detail = detail;
        mer_mesh *m = mesh_of(s, opt);
        uint32_t v = m->bark.vertex_count;
        mer_mesh_free(m);
        return v;
    };
    uint32_t v1 = count(1), v3 = count(3), v5 = count(5);
    assert_true(v1 < v3 && v3 < v5);
    mer_mesh_options bad{};
    bad.detail = 6;
    mer_mesh *m = nullptr;
    mer_error err{};
    assert_int_equal(mer_mesh_build(s, &bad, &m, &err), MER_ERR_RANGE);
    assert_string_equal(err.field, "detail");
    assert_null(m);
    mer_scene_free(s);
}

void test_chunks_tile_and_fit_in_16_bits(void **)
{
    mer_scene *s = grow("fig7-bh-0.54", 30, 7);
    mer_mesh *m = mesh_of(s);
    assert_true(m->bark.vertex_count > MER_MESH_CHUNK_VERTICES);  // big enough to need chunks
    assert_true(m->bark.chunk_count >= 2);
    uint32_t v = 0, i = 0;
    for (uint32_t c = 0; c < m->bark.chunk_count; c++) {
        const mer_mesh_chunk &ch = m->bark.chunks[c];
        assert_int_equal(ch.first_vertex, v);
        assert_int_equal(ch.first_index, i);
        assert_true(ch.vertex_count <= MER_MESH_CHUNK_VERTICES);
        for (uint32_t k = ch.first_index; k < ch.first_index + ch.index_count; k++)
            assert_true(m->bark.indices[k] < ch.vertex_count);
        v += ch.vertex_count;
        i += ch.index_count;
    }
    assert_int_equal(v, m->bark.vertex_count);
    assert_int_equal(i, m->bark.index_count);
    mer_mesh_free(m);
    mer_scene_free(s);
}

// ------------------------------------------------------------- glTF trip

template <typename T>
std::vector<T> read_accessor(const tinygltf::Model &model, int index)
{
    const tinygltf::Accessor &a = model.accessors.at(static_cast<size_t>(index));
    const tinygltf::BufferView &view = model.bufferViews.at(static_cast<size_t>(a.bufferView));
    const tinygltf::Buffer &buf = model.buffers.at(static_cast<size_t>(view.buffer));
    size_t comps = static_cast<size_t>(tinygltf::GetNumComponentsInType(static_cast<uint32_t>(a.type)));
    size_t stride = view.byteStride ? view.byteStride : comps * sizeof(T);
    std::vector<T> out(a.count * comps);
    for (size_t i = 0; i < a.count; i++) {
        size_t at = view.byteOffset + a.byteOffset + i * stride;
        assert_true(at + comps * sizeof(T) <= buf.data.size());
        std::memcpy(&out[i * comps], buf.data.data() + at, comps * sizeof(T));
    }
    return out;
}

tinygltf::Model load(const std::vector<uint8_t> &glb)
{
    tinygltf::TinyGLTF loader;
    tinygltf::Model model;
    std::string error, warning;
    if (!loader.LoadBinaryFromMemory(&model, &error, &warning, glb.data(),
                                     static_cast<unsigned>(glb.size())))
        fail_msg("tinygltf: %s", error.c_str());
    return model;
}

void check_round_trip(const mer_scene *s, const mer_mesh *m, const tinygltf::Model &model, bool quantized)
{
    const tinygltf::Node &tree = model.nodes.at(0);
    assert_string_equal(tree.name.c_str(), "tree");
    const tinygltf::Mesh &mesh = model.meshes.at(static_cast<size_t>(tree.mesh));
    size_t vertices = 0, indices = 0, bark_prims = 0;
    for (const tinygltf::Primitive &p : mesh.primitives) {
        const tinygltf::Accessor &pos = model.accessors.at(static_cast<size_t>(p.attributes.at("POSITION")));
        assert_int_equal(pos.componentType, quantized ? TINYGLTF_COMPONENT_TYPE_SHORT : TINYGLTF_COMPONENT_TYPE_FLOAT);
        auto ids = read_accessor<float>(model, p.attributes.at("_NODE_ID"));
        const tinygltf::Accessor &ia = model.accessors.at(static_cast<size_t>(p.indices));
        std::vector<uint32_t> idx;
        if (ia.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT)
            for (uint16_t x : read_accessor<uint16_t>(model, p.indices))
                idx.push_back(x);
        else
            idx = read_accessor<uint32_t>(model, p.indices);
        for (uint32_t x : idx)
            assert_true(x < pos.count);
        for (float f : ids) {
            mer_node n{};
            assert_int_equal(mer_scene_node(s, static_cast<uint32_t>(f), &n, nullptr), MER_OK);
            assert_true(n.alive);
            assert_true(static_cast<float>(n.id) == f);
        }
        vertices += pos.count;
        indices += idx.size();
        if (model.materials.at(static_cast<size_t>(p.material)).name == "bark")
            bark_prims++;
    }
    assert_int_equal(bark_prims, m->bark.chunk_count);
    assert_int_equal(vertices, m->bark.vertex_count + m->leaves.vertex_count);
    assert_int_equal(indices, m->bark.index_count + m->leaves.index_count);
}

void test_round_trip_tinygltf(void **)
{
    mer_scene *s = grow("fig4-colonization", 25, 8);
    mer_mesh_options opt{};
    opt.leaves = 1;
    opt.markers = 1;
    mer_mesh *m = mesh_of(s, opt);
    mer_gltf_meta meta{};
    meta.session = "0123456789abcdef0123456789abcdef";
    meta.revision = 7;
    meta.step = 25;
    meta.preset = "fig4-colonization";
    meta.seed = 8;
    std::vector<uint8_t> glb = glb_of(m, nullptr, &meta);
    save_artifact("mesh-colonization-leaves-markers.glb", glb);
    tinygltf::Model model = load(glb);
    check_round_trip(s, m, model, true);
    assert_true(model.extensionsRequired.size() == 1 &&
                model.extensionsRequired[0] == "KHR_mesh_quantization");
    // asset.extras says how to grow it again.
    const tinygltf::Value &x = model.asset.extras;
    assert_string_equal(x.Get("session").Get<std::string>().c_str(), meta.session);
    assert_string_equal(x.Get("preset").Get<std::string>().c_str(), "fig4-colonization");
    assert_int_equal(x.Get("step").GetNumberAsInt(), 25);
    assert_int_equal(x.Get("seed").GetNumberAsInt(), 8);
    assert_int_equal(x.Get("revision").GetNumberAsInt(), 7);
    // The leaf material is double-sided; the markers are points.
    bool leaf_double = false;
    for (auto &mat : model.materials)
        leaf_double = leaf_double || (mat.name == "leaf" && mat.doubleSided);
    assert_true(leaf_double);
    assert_string_equal(model.nodes.at(1).name.c_str(), "markers");
    assert_int_equal(model.meshes.at(static_cast<size_t>(model.nodes[1].mesh)).primitives.at(0).mode,
                     TINYGLTF_MODE_POINTS);

    // Unquantized, the same counts, float positions.
    mer_gltf_options raw{};
    raw.unquantized = 1;
    std::vector<uint8_t> plain = glb_of(m, &raw, &meta);
    save_artifact("mesh-colonization-float.glb", plain);
    check_round_trip(s, m, load(plain), false);
    mer_mesh_free(m);
    mer_scene_free(s);
}

// Quantized positions land within half a grid step of the float ones.
void test_quantization_error_is_bounded(void **)
{
    mer_scene *s = grow("default", 15, 9);
    mer_mesh *m = mesh_of(s);
    tinygltf::Model model = load(glb_of(m));
    const tinygltf::Node &tree = model.nodes.at(0);
    assert_int_equal(tree.scale.size(), 3);
    double scale = tree.scale[0];
    const tinygltf::Primitive &p = model.meshes.at(0).primitives.at(0);
    auto q = read_accessor<int16_t>(model, p.attributes.at("POSITION"));
    for (size_t i = 0; i < q.size(); i++) {
        double back = tree.translation[i % 3] + scale * q[i];
        assert_true(std::fabs(back - static_cast<double>(m->bark.positions[i])) <= 0.5 * scale + 1e-6);
    }
    mer_mesh_free(m);
    mer_scene_free(s);
}

void test_colors_and_embedded(void **)
{
    mer_scene *s = grow("default", 10, 10);
    for (uint32_t mode = MER_COLOR_ORDER; mode <= MER_COLOR_AGE; mode++) {
        mer_mesh_options opt{};
        opt.color = mode;
        mer_mesh *m = mesh_of(s, opt);
        assert_non_null(m->bark.colors);
        std::vector<uint8_t> glb = glb_of(m);
        char name[64];
        std::snprintf(name, sizeof name, "mesh-color-%u.glb", mode);
        save_artifact(name, glb);
        tinygltf::Model model = load(glb);
        const tinygltf::Primitive &prim = model.meshes.at(0).primitives.at(0);
        assert_true(prim.attributes.count("COLOR_0") == 1);
        // Quantized: normalized UNSIGNED_BYTE RGBA, within half a step of the floats.
        const int ci = prim.attributes.at("COLOR_0");
        const tinygltf::Accessor &ca = model.accessors.at(static_cast<size_t>(ci));
        assert_int_equal(ca.componentType, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE);
        assert_true(ca.normalized);
        std::vector<uint8_t> rgba = read_accessor<uint8_t>(model, ci);
        assert_int_equal(rgba.size(), 4 * size_t{m->bark.chunks[0].vertex_count});
        for (size_t i = 0; i < rgba.size(); i++)
            assert_true(std::fabs(rgba[i] / 255.0 - static_cast<double>(m->bark.colors[i])) <= 0.5 / 255 + 1e-6);
        mer_gltf_options raw{};
        raw.unquantized = 1;
        tinygltf::Model floats = load(glb_of(m, &raw));
        const int fi = floats.meshes.at(0).primitives.at(0).attributes.at("COLOR_0");
        assert_int_equal(floats.accessors.at(static_cast<size_t>(fi)).componentType, TINYGLTF_COMPONENT_TYPE_FLOAT);
        mer_mesh_free(m);
    }
    mer_mesh *m = mesh_of(s);
    mer_gltf_options emb{};
    emb.format = MER_GLTF_EMBEDDED;
    std::vector<uint8_t> text = glb_of(m, &emb);
    save_artifact("mesh-embedded.gltf", text);
    tinygltf::TinyGLTF loader;
    tinygltf::Model model;
    std::string error, warning;
    assert_true(loader.LoadASCIIFromString(&model, &error, &warning,
                                           reinterpret_cast<const char *>(text.data()),
                                           static_cast<unsigned>(text.size()), ""));
    check_round_trip(s, m, model, true);
    mer_mesh_free(m);
    mer_scene_free(s);
}

void test_same_skeleton_same_bytes(void **)
{
    mer_scene *a = grow("fig9-priority-k0.5", 15, 11);
    mer_scene *b = grow("fig9-priority-k0.5", 15, 11);
    mer_mesh_options opt{};
    opt.leaves = 1;
    mer_mesh *ma = mesh_of(a, opt), *mb = mesh_of(b, opt);
    std::vector<uint8_t> ga = glb_of(ma), gb = glb_of(mb);
    assert_int_equal(ga.size(), gb.size());
    assert_memory_equal(ga.data(), gb.data(), ga.size());
    mer_mesh_free(ma);
    mer_mesh_free(mb);
    mer_scene_free(a);
    mer_scene_free(b);
}

// Our own GLB, read back as obstacle triangles: quantized positions decoded
// through the node transform land where the mesh put them.
void test_read_triangles_round_trip(void **)
{
    mer_scene *s = grow("default", 8, 12);
    mer_mesh *m = mesh_of(s);
    for (uint32_t unq = 0; unq <= 1; unq++) {
        mer_gltf_options opt{};
        opt.unquantized = unq;
        std::vector<uint8_t> glb = glb_of(m, &opt);
        float *xyz = nullptr;
        size_t n = 0;
        mer_error err{};
        assert_int_equal(mer_gltf_read_triangles(glb.data(), glb.size(), 10000000, &xyz, &n, &err), MER_OK);
        assert_int_equal(n, m->bark.index_count / 3);
        tinygltf::Model model = load(glb);
        double step = unq ? 1e-6 : model.nodes.at(0).scale.at(0);
        // The first triangle of the first chunk.
        for (int k = 0; k < 3; k++) {
            const float *want = m->bark.positions + 3 * m->bark.indices[k];
            for (int c = 0; c < 3; c++)
                assert_true(std::fabs(static_cast<double>(xyz[3 * k + c] - want[c])) <= 0.5 * step + 1e-5);
        }
        mer_gltf_free(xyz);

        assert_int_equal(mer_gltf_read_triangles(glb.data(), glb.size(), 10, &xyz, &n, &err), MER_ERR_LIMIT);
        assert_null(xyz);
    }
    const char junk[] = "{\"asset\": {\"version\": \"2.0\"}, \"buffers\": [{\"uri\": \"secret.bin\", \"byteLength\": 4}]}";
    float *xyz = nullptr;
    size_t n = 0;
    mer_error err{};
    assert_int_equal(mer_gltf_read_triangles(reinterpret_cast<const uint8_t *>(junk), sizeof junk - 1,
                                             100, &xyz, &n, &err), MER_ERR_FORMAT);
    assert_string_equal(err.field, "gltf");
    const uint8_t garbage[] = {'g', 'l', 'T', 'F', 2, 0, 0, 0, 99, 0, 0, 0};
    assert_int_equal(mer_gltf_read_triangles(garbage, sizeof garbage, 100, &xyz, &n, &err), MER_ERR_FORMAT);
    mer_mesh_free(m);
    mer_scene_free(s);
}

// The JSON and BIN chunks of a GLB we wrote (two chunks, in that order).
std::pair<nlohmann::json, std::vector<uint8_t>> chunks_of(const std::vector<uint8_t> &glb)
{
    auto u32 = [&](size_t at) {
        return static_cast<size_t>(glb.at(at)) | static_cast<size_t>(glb.at(at + 1)) << 8 |
               static_cast<size_t>(glb.at(at + 2)) << 16 | static_cast<size_t>(glb.at(at + 3)) << 24;
    };
    const size_t json_size = u32(12), bin_at = 20 + json_size;
    nlohmann::json doc = nlohmann::json::parse(glb.begin() + 20, glb.begin() + static_cast<std::ptrdiff_t>(bin_at));
    const size_t bin_size = u32(bin_at);
    assert_int_equal(u32(bin_at + 4), 0x004E4942u);  // "BIN\0"
    auto first = glb.begin() + static_cast<std::ptrdiff_t>(bin_at + 8);
    return {doc, std::vector<uint8_t>(first, first + static_cast<std::ptrdiff_t>(bin_size))};
}

// Rotates each decoded triangle of `out` to start where the same triangle of
// `want` starts, when its corners are a rotation of want's (else leaves it, and
// the byte comparison after fails).
void unrotate(std::vector<uint8_t> &out, const uint8_t *want, size_t count, size_t stride)
{
    auto at = [stride](const uint8_t *p, size_t i) {
        return stride == 2 ? uint32_t{reinterpret_cast<const uint16_t *>(p)[i]}
                           : reinterpret_cast<const uint32_t *>(p)[i];
    };
    std::vector<uint8_t> copy(out);
    for (size_t t = 0; t + 3 <= count; t += 3)
        for (size_t r = 1; r < 3; r++)
            if (at(copy.data(), t + r) == at(want, t) && at(copy.data(), t + (r + 1) % 3) == at(want, t + 1) &&
                at(copy.data(), t + (r + 2) % 3) == at(want, t + 2))
                for (size_t k = 0; k < 3; k++)
                    std::memcpy(out.data() + (t + k) * stride, copy.data() + (t + (r + k) % 3) * stride, stride);
}

// EXT_meshopt_compression: decoding every bufferView of the compressed GLB gives
// back the uncompressed GLB's BIN byte for byte (a triangle's corners may come
// back rotated, nothing else), and the scene graph is the same.
void test_meshopt_decodes_to_the_uncompressed_bytes(void **)
{
    mer_scene *s = grow("fig4-colonization", 20, 8);
    size_t default_size = 0;
    // Variant 2: twig lines, on a tree that has twigs (their index views take
    // INDICES mode).
    mer_scene *twiggy = grow("fig7-bh-0.52", 14, 3);
    for (uint32_t variant = 0; variant <= 2; variant++) {
        const uint32_t no_uvs = variant >= 1;
        mer_mesh_options opt{};
        opt.leaves = 1;
        opt.markers = 1;
        opt.no_uvs = no_uvs;
        opt.twig_lines = variant == 2;
        mer_mesh *m = mesh_of(variant == 2 ? twiggy : s, opt);
        assert_true((variant == 2 || m->point_count > 0) && m->leaves.vertex_count > 0);
        mer_gltf_options z{};
        z.compression = MER_GLTF_MESHOPT;
        std::vector<uint8_t> plain = glb_of(m), packed = glb_of(m, &z);
        assert_true(packed == glb_of(m, &z));  // deterministic
        if (variant == 1)
            save_artifact("mesh-meshopt.glb", packed);
        // Fewer bytes: 0.50 of the plain GLB with UVs and 0.52 without on this
        // tree (its FLOAT markers pack poorly); without UVs, 0.39 of the default.
        assert_true(10 * packed.size() < 6 * plain.size());
        if (no_uvs == 0)
            default_size = plain.size();
        else if (variant == 1)
            assert_true(100 * packed.size() < 45 * default_size);
        auto [pj, pbin] = chunks_of(packed);
        auto [uj, ubin] = chunks_of(plain);
        assert_true(pj["accessors"] == uj["accessors"]);
        assert_true(pj["meshes"] == uj["meshes"]);
        assert_true(pj["nodes"] == uj["nodes"]);
        assert_true(pj["extensionsRequired"].back() == "EXT_meshopt_compression");
        assert_int_equal(pj["buffers"].size(), 2);
        assert_int_equal(pj["buffers"][0]["byteLength"].get<size_t>(), pbin.size());
        assert_int_equal(pj["buffers"][1]["byteLength"].get<size_t>(), ubin.size());
        assert_true(pj["buffers"][1]["extensions"]["EXT_meshopt_compression"]["fallback"] == true);
        assert_int_equal(pj["bufferViews"].size(), uj["bufferViews"].size());
        size_t index_views = 0, line_views = 0;
        for (size_t i = 0; i < pj["bufferViews"].size(); i++) {
            const nlohmann::json &v = pj["bufferViews"][i], &x = v["extensions"]["EXT_meshopt_compression"];
            assert_int_equal(v["buffer"].get<int>(), 1);
            // tinygltf leaves out a byteOffset of 0.
            const size_t offset = v.value("byteOffset", size_t{0});
            assert_int_equal(offset, uj["bufferViews"][i].value("byteOffset", size_t{0}));
            const size_t count = x["count"], stride = x["byteStride"], at = x["byteOffset"],
                         length = x["byteLength"];
            assert_int_equal(x["buffer"].get<int>(), 0);
            assert_int_equal(at % 4, 0);
            assert_true(at + length <= pbin.size());
            assert_int_equal(count * stride, v["byteLength"].get<size_t>());
            std::vector<uint8_t> out(count * stride);
            int rc;
            if (x["mode"] == "TRIANGLES") {
                index_views++;
                rc = meshopt_decodeIndexBuffer(out.data(), count, stride, pbin.data() + at, length);
                assert_int_equal(rc, 0);
                unrotate(out, ubin.data() + offset, count, stride);
            } else if (x["mode"] == "INDICES") {  // twig lines: every index kept as it is
                line_views++;
                rc = meshopt_decodeIndexSequence(out.data(), count, stride, pbin.data() + at, length);
            } else {
                assert_true(x["mode"] == "ATTRIBUTES");
                rc = meshopt_decodeVertexBuffer(out.data(), count, stride, pbin.data() + at, length);
            }
            assert_int_equal(rc, 0);
            if (std::memcmp(out.data(), ubin.data() + offset, out.size()) != 0)
                fail_msg("bufferView %zu (%s) decodes to other bytes", i, x["mode"].get<std::string>().c_str());
        }
        assert_int_equal(index_views, m->bark.chunk_count + m->leaves.chunk_count);
        uint32_t twig_chunks = 0;
        for (uint32_t c = 0; c < m->bark.chunk_count; c++)
            twig_chunks += m->bark.chunks[c].twig;
        assert_int_equal(line_views, twig_chunks);
        assert_true(variant < 2 || twig_chunks > 0);
        mer_mesh_free(m);
    }
    // Compression is for GLB only; unknown modes are refused.
    mer_mesh *m = mesh_of(s);
    uint8_t *bytes = nullptr;
    size_t size = 0;
    mer_error err{};
    mer_gltf_options bad{};
    bad.compression = MER_GLTF_MESHOPT;
    bad.format = MER_GLTF_EMBEDDED;
    assert_int_equal(mer_gltf_write_tree(m, nullptr, &bad, &bytes, &size, &err), MER_ERR_RANGE);
    assert_string_equal(err.field, "compression");
    bad.format = MER_GLTF_BINARY;
    bad.compression = 7;
    assert_int_equal(mer_gltf_write_tree(m, nullptr, &bad, &bytes, &size, &err), MER_ERR_RANGE);
    assert_null(bytes);
    mer_mesh_free(m);
    mer_scene_free(twiggy);
    mer_scene_free(s);
}

// no_uvs: the same geometry without UVs, and no TEXCOORD_0 in the GLB.
void test_no_uvs(void **)
{
    mer_scene *s = grow("default", 12, 3);
    mer_mesh_options with{}, without{};
    with.leaves = without.leaves = 1;
    without.no_uvs = 1;
    mer_mesh *a = mesh_of(s, with), *b = mesh_of(s, without);
    assert_non_null(a->bark.uvs);
    assert_null(b->bark.uvs);
    assert_null(b->leaves.uvs);
    // Rings lose their seam vertex: fewer vertices, the same triangles in the same
    // order, each with the same corners and the same internode on its first vertex.
    assert_true(b->bark.vertex_count < a->bark.vertex_count);
    assert_int_equal(a->bark.index_count, b->bark.index_count);
    assert_int_equal(a->bark.chunk_count, 1);
    assert_int_equal(b->bark.chunk_count, 1);
    for (uint32_t i = 0; i < a->bark.index_count; i++) {
        const uint32_t ia = a->bark.indices[i], ib = b->bark.indices[i];
        assert_memory_equal(a->bark.positions + 3 * ia, b->bark.positions + 3 * ib, 3 * sizeof(float));
        if (i % 3 == 0)
            assert_int_equal(a->bark.node_ids[ia], b->bark.node_ids[ib]);
    }
    assert_int_equal(a->leaves.vertex_count, b->leaves.vertex_count);
    tinygltf::Model model = load(glb_of(b));
    for (const tinygltf::Primitive &p : model.meshes.at(0).primitives)
        assert_int_equal(p.attributes.count("TEXCOORD_0"), 0);
    without.no_uvs = 2;
    expect_refused(s, without, "no_uvs");
    mer_mesh_free(a);
    mer_mesh_free(b);
    mer_scene_free(s);
}

// Twig lines (mesh.h): the same triangles, the twigs last and in chunks of their
// own, and one line segment per twig internode along its prism, on the vertices
// of its chunk; in the GLB a LINES primitive on its chunk's POSITION accessor.
void test_twig_lines(void **)
{
    mer_scene *s = grow("fig7-bh-0.52", 14, 3);
    mer_mesh_options plain{}, lod{};
    plain.no_uvs = lod.no_uvs = 1;
    plain.leaves = lod.leaves = 1;
    lod.twig_lines = 1;
    mer_mesh *a = mesh_of(s, plain), *b = mesh_of(s, lod);
    assert_int_equal(a->bark.line_index_count, 0);
    assert_null(a->bark.line_indices);
    for (uint32_t c = 0; c < a->bark.chunk_count; c++)
        assert_int_equal(a->bark.chunks[c].twig, 0);

    // The same triangles, each with its corners and its internode, in another order.
    using Key = std::array<float, 10>;
    auto triangles = [](const mer_mesh_part &p) {
        std::vector<Key> out;
        for (uint32_t c = 0; c < p.chunk_count; c++) {
            const mer_mesh_chunk &ch = p.chunks[c];
            for (uint32_t i = ch.first_index; i < ch.first_index + ch.index_count; i += 3) {
                std::array<std::array<float, 3>, 3> corner;
                uint32_t node = UINT32_MAX;
                for (int k = 0; k < 3; k++) {
                    uint32_t v = ch.first_vertex + p.indices[i + k];
                    std::memcpy(corner[k].data(), p.positions + 3 * v, sizeof corner[k]);
                    node = std::min(node, p.node_ids[v]);
                }
                std::sort(corner.begin(), corner.end());
                Key key{static_cast<float>(node)};
                for (int k = 0; k < 9; k++)
                    key[1 + k] = corner[k / 3][k % 3];
                out.push_back(key);
            }
        }
        std::sort(out.begin(), out.end());
        return out;
    };
    assert_int_equal(a->bark.vertex_count, b->bark.vertex_count);
    assert_true(triangles(a->bark) == triangles(b->bark));
    assert_int_equal(a->leaves.vertex_count, b->leaves.vertex_count);

    // Thicker axes first; the twigs, thin, after them; lines only on twig chunks.
    const mer_mesh_part &bark = b->bark;
    uint32_t twig_chunks = 0;
    float thickest = 0.0f;
    std::map<uint32_t, int> covered;  // twig internode -> segments covering it
    for (uint32_t c = 0; c < bark.chunk_count; c++) {
        const mer_mesh_chunk &ch = bark.chunks[c];
        if (!ch.twig) {
            assert_int_equal(twig_chunks, 0);
            assert_int_equal(ch.line_index_count, 0);
            continue;
        }
        twig_chunks++;
        for (uint32_t v = ch.first_vertex; v < ch.first_vertex + ch.vertex_count; v++) {
            mer_node n{};
            assert_int_equal(mer_scene_node(s, bark.node_ids[v], &n, nullptr), MER_OK);
            thickest = std::max(thickest, n.diameter);
            covered.emplace(n.id, 0);
        }
        for (uint32_t i = ch.first_line_index; i < ch.first_line_index + ch.line_index_count; i += 2) {
            const uint32_t u = ch.first_vertex + bark.line_indices[i],
                           w = ch.first_vertex + bark.line_indices[i + 1];
            assert_true(bark.line_indices[i] < ch.vertex_count && bark.line_indices[i + 1] < ch.vertex_count);
            // The segment covers the internode its smaller id names: from its base
            // ring to its end (the next ring or the apex), within the twig's radius.
            mer_node n{};
            assert_int_equal(mer_scene_node(s, std::min(bark.node_ids[u], bark.node_ids[w]), &n, nullptr), MER_OK);
            covered[n.id]++;
            const float end[3] = {n.base[0] + n.length * n.dir[0], n.base[1] + n.length * n.dir[1],
                                  n.base[2] + n.length * n.dir[2]};
            auto dist = [](const float *p, const float *q) {
                return std::sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                                 (p[2] - q[2]) * (p[2] - q[2]));
            };
            assert_true(dist(bark.positions + 3 * u, n.base) <= 0.5f * b->twig_diameter_max + 1e-4f);
            assert_true(dist(bark.positions + 3 * w, end) <= 0.5f * b->twig_diameter_max + 1e-4f);
        }
    }
    assert_true(twig_chunks >= 1 && twig_chunks < bark.chunk_count);
    assert_true(bark.chunks[0].twig == 0);
    assert_true(b->twig_diameter_max > 0.0f && thickest <= b->twig_diameter_max);
    assert_int_equal(bark.line_index_count, 2 * covered.size());
    for (const auto &kv : covered)
        if (kv.second != 1)
            fail_msg("twig internode %u has %d line segments", kv.first, kv.second);

    // The GLB: each twig chunk's triangles, then its lines on the same positions.
    mer_gltf_options z{};
    z.compression = MER_GLTF_MESHOPT;
    save_artifact("mesh-twig-lines.glb", glb_of(b, &z));
    tinygltf::Model model = load(glb_of(b));
    const std::vector<tinygltf::Primitive> &prims = model.meshes.at(0).primitives;
    uint32_t lines = 0;
    for (size_t i = 0; i < prims.size(); i++) {
        const tinygltf::Primitive &p = prims[i];
        const bool twig = p.extras.Has("twig") && p.extras.Get("twig").Get<bool>();
        if (p.mode == TINYGLTF_MODE_LINE) {
            lines++;
            assert_true(i > 0 && prims[i - 1].extras.Has("twig"));
            assert_int_equal(p.attributes.at("POSITION"), prims[i - 1].attributes.at("POSITION"));
            assert_int_equal(p.attributes.count("NORMAL"), 0);
            assert_string_equal(model.materials.at(static_cast<size_t>(p.material)).name.c_str(), "twig");
            assert_float_equal(p.extras.Get("twig_diameter_max").GetNumberAsDouble(),
                               b->twig_diameter_max, 1e-7);
        } else if (twig) {
            assert_true(i + 1 < prims.size() && prims[i + 1].mode == TINYGLTF_MODE_LINE);
        }
    }
    assert_int_equal(lines, twig_chunks);
    // The writer refuses line indices that run past their array, or on leaves.
    {
        uint8_t *bytes = nullptr;
        size_t size = 0;
        mer_error err{};
        mer_mesh_chunk &twig = b->bark.chunks[b->bark.chunk_count - 1];
        const uint32_t kept = twig.line_index_count;
        twig.line_index_count = UINT32_MAX - 1;
        assert_int_equal(mer_gltf_write_tree(b, nullptr, nullptr, &bytes, &size, &err), MER_ERR_INVALID);
        assert_string_equal(err.field, "mesh.bark.line_indices");
        twig.line_index_count = kept;
        b->leaves.line_indices = b->bark.line_indices;
        b->leaves.line_index_count = 2;
        assert_int_equal(mer_gltf_write_tree(b, nullptr, nullptr, &bytes, &size, &err), MER_ERR_INVALID);
        assert_string_equal(err.field, "mesh.leaves.line_indices");
        assert_null(bytes);
        b->leaves.line_indices = nullptr;
        b->leaves.line_index_count = 0;
    }
    // Without the option, the GLB has no twig primitives at all.
    const tinygltf::Model without = load(glb_of(a));
    for (const tinygltf::Primitive &p : without.meshes.at(0).primitives)
        assert_true(p.mode == TINYGLTF_MODE_TRIANGLES && !p.extras.Has("twig"));
    lod.twig_lines = 2;
    expect_refused(s, lod, "twig_lines");
    mer_mesh_free(a);
    mer_mesh_free(b);
    mer_scene_free(s);
}

}  // namespace

int main()
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_normals_are_unit),
        cmocka_unit_test(test_straight_tube_radius),
        cmocka_unit_test(test_uv_v_monotonic_and_u_around),
        cmocka_unit_test(test_tip_has_cap_closed_tube),
        cmocka_unit_test(test_no_length_no_flat_bands),
        cmocka_unit_test(test_no_length_names_no_band),
        cmocka_unit_test(test_cut_has_flat_cap),
        cmocka_unit_test(test_node_ids_live_and_first_vertex),
        cmocka_unit_test(test_sides_fall_with_diameter_and_detail),
        cmocka_unit_test(test_chunks_tile_and_fit_in_16_bits),
        cmocka_unit_test(test_round_trip_tinygltf),
        cmocka_unit_test(test_quantization_error_is_bounded),
        cmocka_unit_test(test_colors_and_embedded),
        cmocka_unit_test(test_same_skeleton_same_bytes),
        cmocka_unit_test(test_read_triangles_round_trip),
        cmocka_unit_test(test_meshopt_decodes_to_the_uncompressed_bytes),
        cmocka_unit_test(test_no_uvs),
        cmocka_unit_test(test_twig_lines),
    };
    return cmocka_run_group_tests_name("mesh", tests, nullptr, nullptr);
}
