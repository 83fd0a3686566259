// meristem — mer_gltf_read_triangles: the triangles of a glTF asset's default
// scene in world space, for obstacles and marker volumes.
#include "config.h"

#include "core/alloc.h"
#include "gltf/gltf_private.h"

#include <array>
#include <cstdlib>
#include <cstring>

using merp_gltf::guarded;

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
    case TINYGLTF_COMPONENT_TYPE_FLOAT: { float f; std::memcpy(&f, p, 4); return static_cast<double>(f); }
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
        float *copy = static_cast<float *>(merp_malloc(reader.xyz.size() * sizeof(float)));
        if (copy == nullptr)
            return mer_error_set(err, MER_ERR_NOMEM, nullptr, "out of memory for triangles");
        std::memcpy(copy, reader.xyz.data(), reader.xyz.size() * sizeof(float));
        *out_xyz = copy;
        *out_triangles = reader.xyz.size() / 9;
        return MER_OK;
    });
}

