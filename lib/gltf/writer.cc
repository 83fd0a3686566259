// meristem — the Writer: bufferViews and accessors over the mesh's own arrays,
// and the BIN bytes they become, converted or quantized on the way.
#include "config.h"

#include "gltf/gltf_private.h"

#include <algorithm>
#include <cfloat>
#include <cstring>
#include <system_error>
#include <thread>

#include <meristem/version.h>

namespace merp_gltf {

namespace {

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

}  // namespace

Writer::Writer()
{
    model.asset.version = "2.0";
    model.asset.generator = std::string("meristem ") + mer_version();
    model.buffers.resize(1);
}

int Writer::view(const void *src, size_t count, size_t elem, Fill fill, int target, int stride,
                 bool triangles)
{
    Blob b{src, count, elem, fill, bin_size, count * out_elem(fill, elem), triangles};
    bin_size += padded4(b.size);
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

int Writer::accessor(int view_index, size_t byte_offset, int component, int type, size_t count)
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

int Writer::vertex_view(const void *src, size_t vertices, int components, Fill fill)
{
    if (fill == Fill::QuantizePosition || fill == Fill::QuantizeNormal ||
        fill == Fill::QuantizeColor) {
        size_t stride = out_elem(fill, 0);
        return view(src, vertices, 0, fill, TINYGLTF_TARGET_ARRAY_BUFFER, static_cast<int>(stride));
    }
    return view(src, vertices * static_cast<size_t>(components), 4, fill,
                TINYGLTF_TARGET_ARRAY_BUFFER, 4 * components);
}

Box box_of(const float *p, size_t first, size_t count)
{
    Box b = {{FLT_MAX, FLT_MAX, FLT_MAX}, {-FLT_MAX, -FLT_MAX, -FLT_MAX}};
    for (size_t i = first; i < first + count; i++)
        for (size_t k = 0; k < 3; k++) {
            const float x = p[3 * i + k];
            b.lo[k] = x < b.lo[k] ? x : b.lo[k];
            b.hi[k] = x > b.hi[k] ? x : b.hi[k];
        }
    return b;
}

// POSITION needs min and max (glTF 2.0 §3.7.2.1), in the stored values: grid
// integers when quantized.
int Writer::positions(int view_index, const Box &box, size_t first, size_t count, bool quantize)
{
    int a = quantize ? accessor(view_index, first * 8, TINYGLTF_COMPONENT_TYPE_SHORT,
                                TINYGLTF_TYPE_VEC3, count)
                     : accessor(view_index, first * 12, TINYGLTF_COMPONENT_TYPE_FLOAT,
                                TINYGLTF_TYPE_VEC3, count);
    // Quantization is monotonic, so the bounds of the stored integers are the
    // quantized float bounds.
    std::vector<double> lo(3), hi(3);
    for (int k = 0; k < 3; k++) {
        size_t kk = static_cast<size_t>(k);
        lo[kk] = quantize ? quantize_position(box.lo[kk], grid, k) : static_cast<double>(box.lo[kk]);
        hi[kk] = quantize ? quantize_position(box.hi[kk], grid, k) : static_cast<double>(box.hi[kk]);
    }
    model.accessors[static_cast<size_t>(a)].minValues = lo;
    model.accessors[static_cast<size_t>(a)].maxValues = hi;
    return a;
}

int Writer::indices(const uint32_t *idx, size_t count, size_t vertex_count, bool triangles)
{
    bool narrow = vertex_count <= 0xFFFF;
    int v = view(idx, count, 4, narrow ? Fill::U32ToU16 : Fill::Copy,
                 TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER, 0, triangles);
    return accessor(v, 0, narrow ? TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT
                                 : TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT,
                    TINYGLTF_TYPE_SCALAR, count);
}

void Writer::fill(uint8_t *bin) const
{
    // Copying and quantizing run at about 3 GB/s: under 1 MiB, a second
    // thread costs more than it saves.
    each_blob([&](size_t i) { fill(blobs[i], bin); }, size_t{1} << 20);
}

void Writer::each_blob(const std::function<void(size_t)> &fn, size_t two_threads_from) const
{
    const size_t n = blobs.size();
    std::vector<size_t> order(n);
    for (size_t i = 0; i < n; i++)
        order[i] = i;
    if (n < 2 || bin_size < two_threads_from) {
        for (size_t i : order)
            fn(i);
        return;
    }
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return blobs[a].size > blobs[b].size; });
    std::vector<size_t> mine, theirs;
    size_t my_bytes = 0, their_bytes = 0;
    for (size_t i : order) {
        (my_bytes <= their_bytes ? mine : theirs).push_back(i);
        (my_bytes <= their_bytes ? my_bytes : their_bytes) += blobs[i].size;
    }
    std::thread helper;
    try {
        helper = std::thread([&]() {
            for (size_t i : theirs)
                fn(i);
        });
    } catch (const std::system_error &) {
        mine.insert(mine.end(), theirs.begin(), theirs.end());
    }
    for (size_t i : mine)
        fn(i);
    if (helper.joinable())
        helper.join();
}

// One blob's bytes (and the padding after them) at its offset in `bin`.
void Writer::fill(const Blob &b, uint8_t *bin) const
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
    std::memset(dst + b.size, 0, padded4(b.size) - b.size);
}

}  // namespace merp_gltf
