// Unit tests for lib/gltf/: write a mesh, read it back with tinygltf, compare.
// The GLB is also left in $MER_ARTIFACTS for the glTF conformance test.
#include "config.h"

#include <cmath>
#include <cstdarg>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <setjmp.h>
#include <string>
#include <vector>

extern "C" {
#include <cmocka.h>
}

#include "gltf/tinygltf_private.h"

#include <meristem/gltf.h>

#include "plain_glb.h"

namespace {

// A unit cube: 24 vertices (4 per face, so each face has its own normal), 12 triangles.
struct cube {
    std::vector<float> positions, normals;
    std::vector<uint32_t> node_ids, indices;
};

cube make_cube()
{
    cube c;
    const float n[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (int f = 0; f < 6; f++) {
        // Two axes spanning the face, chosen so (u × v) = n and triangles face outwards.
        float u[3], v[3];
        const float *nn = n[f];
        float a[3] = {std::fabs(nn[1]) > 0.5f ? 1.0f : 0.0f, std::fabs(nn[1]) > 0.5f ? 0.0f : 1.0f, 0};
        u[0] = a[1] * nn[2] - a[2] * nn[1];
        u[1] = a[2] * nn[0] - a[0] * nn[2];
        u[2] = a[0] * nn[1] - a[1] * nn[0];
        v[0] = nn[1] * u[2] - nn[2] * u[1];
        v[1] = nn[2] * u[0] - nn[0] * u[2];
        v[2] = nn[0] * u[1] - nn[1] * u[0];
        uint32_t base = static_cast<uint32_t>(c.positions.size() / 3);
        const float corners[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
        for (const auto &k : corners) {
            for (int i = 0; i < 3; i++) {
                c.positions.push_back(0.5f * (nn[i] + k[0] * u[i] + k[1] * v[i]));
                c.normals.push_back(nn[i]);
            }
            c.node_ids.push_back(static_cast<uint32_t>(f) + 100u);
        }
        const uint32_t tri[6] = {0, 1, 2, 0, 2, 3};
        for (uint32_t t : tri)
            c.indices.push_back(base + t);
    }
    return c;
}

plain_mesh view_of(const cube &c)
{
    plain_mesh m{};
    m.positions = c.positions.data();
    m.normals = c.normals.data();
    m.node_ids = c.node_ids.data();
    m.vertex_count = c.positions.size() / 3;
    m.indices = c.indices.data();
    m.index_count = c.indices.size();
    return m;
}

void save_artifact(const char *name, const uint8_t *bytes, size_t size)
{
    const char *dir = std::getenv("MER_ARTIFACTS");
    if (dir == nullptr || *dir == '\0')
        return;
    std::string path = std::string(dir) + "/" + name;
    FILE *f = std::fopen(path.c_str(), "wb");
    assert_non_null(f);
    assert_int_equal(std::fwrite(bytes, 1, size, f), size);
    std::fclose(f);
}

template <typename T>
std::vector<T> read_accessor(const tinygltf::Model &model, int index)
{
    const tinygltf::Accessor &accessor = model.accessors.at(static_cast<size_t>(index));
    const tinygltf::BufferView &view = model.bufferViews.at(static_cast<size_t>(accessor.bufferView));
    const tinygltf::Buffer &buffer = model.buffers.at(static_cast<size_t>(view.buffer));
    size_t components = static_cast<size_t>(tinygltf::GetNumComponentsInType(static_cast<uint32_t>(accessor.type)));
    std::vector<T> out(accessor.count * components);
    assert_true(view.byteOffset + accessor.byteOffset + out.size() * sizeof(T) <= buffer.data.size());
    std::memcpy(out.data(), buffer.data.data() + view.byteOffset + accessor.byteOffset,
                out.size() * sizeof(T));
    return out;
}

void test_round_trip(void **)
{
    cube c = make_cube();
    plain_mesh m = view_of(c);
    uint8_t *glb = nullptr;
    size_t size = 0;
    mer_error err{};
    assert_int_equal(write_plain_glb(&m, &glb, &size, &err), MER_OK);
    assert_non_null(glb);
    assert_true(size > 20);
    assert_memory_equal(glb, "glTF", 4);
    save_artifact("unit-cube.glb", glb, size);

    tinygltf::TinyGLTF loader;
    tinygltf::Model model;
    std::string error, warning;
    bool ok = loader.LoadBinaryFromMemory(&model, &error, &warning, glb, static_cast<unsigned>(size));
    mer_gltf_free(glb);
    if (!ok)
        fail_msg("tinygltf could not read our GLB: %s", error.c_str());

    assert_string_equal(model.asset.version.c_str(), "2.0");
    assert_true(model.asset.generator.rfind("meristem", 0) == 0);
    assert_int_equal(model.meshes.size(), 1);
    const tinygltf::Primitive &p = model.meshes[0].primitives.at(0);
    assert_int_equal(p.mode, TINYGLTF_MODE_TRIANGLES);

    auto positions = read_accessor<float>(model, p.attributes.at("POSITION"));
    auto normals = read_accessor<float>(model, p.attributes.at("NORMAL"));
    auto ids = read_accessor<float>(model, p.attributes.at("_NODE_ID"));
    auto indices = read_accessor<uint16_t>(model, p.indices);
    assert_int_equal(model.accessors[static_cast<size_t>(p.indices)].componentType,
                     TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
    assert_int_equal(positions.size(), c.positions.size());
    assert_memory_equal(positions.data(), c.positions.data(), positions.size() * sizeof(float));
    assert_memory_equal(normals.data(), c.normals.data(), normals.size() * sizeof(float));
    assert_int_equal(ids.size(), c.node_ids.size());
    for (size_t i = 0; i < ids.size(); i++)
        assert_int_equal(static_cast<uint32_t>(ids[i]), c.node_ids[i]);
    assert_int_equal(indices.size(), c.indices.size());
    for (size_t i = 0; i < indices.size(); i++)
        assert_int_equal(indices[i], c.indices[i]);

    const tinygltf::Accessor &pa = model.accessors[static_cast<size_t>(p.attributes.at("POSITION"))];
    assert_int_equal(pa.minValues.size(), 3);
    for (int k = 0; k < 3; k++) {
        assert_true(pa.minValues[static_cast<size_t>(k)] == -0.5);
        assert_true(pa.maxValues[static_cast<size_t>(k)] == 0.5);
    }
}

// Past 65535 vertices the indices must widen to UNSIGNED_INT. At 70,000
// vertices with normals and node ids the BIN chunk is over 1 MiB, which the
// writer fills on two threads (Writer::each_blob): every attribute must read
// back as written.
void test_wide_indices(void **)
{
    const size_t n = 70000;
    std::vector<float> positions(3 * n), normals(3 * n);
    std::vector<uint32_t> ids(n);
    for (size_t i = 0; i < n; i++) {
        positions[3 * i] = static_cast<float>(i % 100);
        positions[3 * i + 1] = static_cast<float>(i / 100);
        positions[3 * i + 2] = 0.0f;
        const float a = 0.001f * static_cast<float>(i);
        normals[3 * i] = std::cos(a), normals[3 * i + 1] = 0.0f, normals[3 * i + 2] = std::sin(a);
        ids[i] = static_cast<uint32_t>(i * 7 % 65521);
    }
    std::vector<uint32_t> indices = {0, 1, 100, 69998, 69999, 69899};
    plain_mesh m{};
    m.positions = positions.data();
    m.normals = normals.data();
    m.node_ids = ids.data();
    m.vertex_count = n;
    m.indices = indices.data();
    m.index_count = indices.size();
    uint8_t *glb = nullptr;
    size_t size = 0;
    assert_int_equal(write_plain_glb(&m, &glb, &size, nullptr), MER_OK);
    assert_true(size > (size_t{1} << 20));
    save_artifact("unit-wide-indices.glb", glb, size);
    tinygltf::TinyGLTF loader;
    tinygltf::Model model;
    std::string error, warning;
    assert_true(loader.LoadBinaryFromMemory(&model, &error, &warning, glb, static_cast<unsigned>(size)));
    mer_gltf_free(glb);
    const tinygltf::Primitive &p = model.meshes.at(0).primitives.at(0);
    assert_int_equal(model.accessors[static_cast<size_t>(p.indices)].componentType,
                     TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT);
    auto back = read_accessor<uint32_t>(model, p.indices);
    assert_memory_equal(back.data(), indices.data(), indices.size() * sizeof(uint32_t));
    auto pos = read_accessor<float>(model, p.attributes.at("POSITION"));
    auto nrm = read_accessor<float>(model, p.attributes.at("NORMAL"));
    auto id = read_accessor<float>(model, p.attributes.at("_NODE_ID"));
    assert_memory_equal(pos.data(), positions.data(), positions.size() * sizeof(float));
    assert_memory_equal(nrm.data(), normals.data(), normals.size() * sizeof(float));
    for (size_t i = 0; i < n; i++)
        assert_int_equal(static_cast<uint32_t>(id[i]), ids[i]);
}

// Quantized positions are (p − centre) / step rounded half away from zero,
// the quotient rounded once: these three vertices' box puts the third's z at
// an exact half-step, which a multiplication by 1 / step (rounded twice)
// takes to the other integer (-16383, not -16384).
void test_quantized_positions_round_once(void **)
{
    const float p[9] = {-16.9476681f, 11.1967506f, -2.46363068f, -10.05023f, 20.8340206f, 26.8852348f,
                        -12.0f, 15.0f, 4.8735857f};
    uint32_t idx[3] = {0, 1, 2}, ids[3] = {0, 1, 2};
    mer_mesh mesh{};
    mesh.bark.vertex_count = 3;
    mesh.bark.index_count = 3;
    mesh.bark.positions = const_cast<float *>(p);
    mesh.bark.node_ids = ids;
    mesh.bark.indices = idx;
    mer_mesh_chunk whole{0, 3, 0, 3, 0, 0, 0};
    mesh.bark.chunks = &whole;
    mesh.bark.chunk_count = 1;
    uint8_t *glb = nullptr;
    size_t size = 0;
    mer_error err{};
    assert_int_equal(mer_gltf_write_tree(&mesh, nullptr, nullptr, &glb, &size, &err), MER_OK);
    tinygltf::TinyGLTF loader;
    tinygltf::Model model;
    std::string error, warning;
    assert_true(loader.LoadBinaryFromMemory(&model, &error, &warning, glb, static_cast<unsigned>(size)));
    mer_gltf_free(glb);
    const tinygltf::Primitive &prim = model.meshes.at(0).primitives.at(0);
    const tinygltf::Accessor &a = model.accessors.at(static_cast<size_t>(prim.attributes.at("POSITION")));
    const tinygltf::BufferView &v = model.bufferViews.at(static_cast<size_t>(a.bufferView));
    assert_int_equal(a.componentType, TINYGLTF_COMPONENT_TYPE_SHORT);
    double lo[3], hi[3], centre[3], half = 0;
    for (int k = 0; k < 3; k++) {
        lo[k] = std::fmin(std::fmin(p[k], p[3 + k]), p[6 + k]);
        hi[k] = std::fmax(std::fmax(p[k], p[3 + k]), p[6 + k]);
        centre[k] = 0.5 * (lo[k] + hi[k]);
        half = std::fmax(half, 0.5 * (hi[k] - lo[k]));
    }
    const double step = half / 32767.0;
    for (size_t i = 0; i < 3; i++)
        for (size_t k = 0; k < 3; k++) {
            int16_t q;
            std::memcpy(&q, model.buffers[0].data.data() + v.byteOffset + a.byteOffset + 8 * i + 2 * k, 2);
            const double x = (static_cast<double>(p[3 * i + k]) - centre[k]) / step;
            const double r = x >= 0 ? std::floor(x + 0.5) : -std::floor(0.5 - x);
            assert_int_equal(q, static_cast<int>(r));
        }
    int16_t z;
    std::memcpy(&z, model.buffers[0].data.data() + v.byteOffset + a.byteOffset + 8 * 2 + 4, 2);
    assert_int_equal(z, -16384);
}

void test_same_mesh_same_bytes(void **)
{
    cube c = make_cube();
    plain_mesh m = view_of(c);
    uint8_t *a = nullptr, *b = nullptr;
    size_t na = 0, nb = 0;
    assert_int_equal(write_plain_glb(&m, &a, &na, nullptr), MER_OK);
    assert_int_equal(write_plain_glb(&m, &b, &nb, nullptr), MER_OK);
    assert_int_equal(na, nb);
    assert_memory_equal(a, b, na);
    mer_gltf_free(a);
    mer_gltf_free(b);
}

void test_refuses_bad_meshes(void **)
{
    cube c = make_cube();
    uint8_t *glb = reinterpret_cast<uint8_t *>(1);
    size_t size = 7;
    mer_error err{};

    plain_mesh m = view_of(c);
    m.index_count = 7;  // not a multiple of 3
    assert_int_equal(write_plain_glb(&m, &glb, &size, &err), MER_ERR_INVALID);
    assert_null(glb);
    assert_int_equal(size, 0);
    assert_string_equal(err.field, "mesh.bark.indices");

    c.indices[5] = 24;  // one past the last vertex
    m = view_of(c);
    assert_int_equal(write_plain_glb(&m, &glb, &size, &err), MER_ERR_RANGE);
    assert_non_null(std::strstr(err.message, "past the last vertex"));

    c = make_cube();
    c.node_ids[3] = MER_GLTF_NODE_ID_LIMIT;
    m = view_of(c);
    assert_int_equal(write_plain_glb(&m, &glb, &size, &err), MER_ERR_RANGE);
    assert_string_equal(err.field, "mesh.bark.node_ids");

    c = make_cube();
    c.positions[4] = NAN;
    m = view_of(c);
    assert_int_equal(write_plain_glb(&m, &glb, &size, &err), MER_ERR_RANGE);
    assert_string_equal(err.field, "mesh.bark.positions");

    assert_int_equal(mer_gltf_write_tree(nullptr, nullptr, nullptr, &glb, &size, &err), MER_ERR_INVALID);
    assert_int_equal(write_plain_glb(&m, nullptr, &size, &err), MER_ERR_INVALID);
}

}  // namespace

int main()
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_round_trip),
        cmocka_unit_test(test_wide_indices),
        cmocka_unit_test(test_quantized_positions_round_once),
        cmocka_unit_test(test_same_mesh_same_bytes),
        cmocka_unit_test(test_refuses_bad_meshes),
    };
    return cmocka_run_group_tests_name("gltf", tests, nullptr, nullptr);
}
