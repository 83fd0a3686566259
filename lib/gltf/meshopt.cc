// meristem — EXT_meshopt_compression: every bufferView of a laid-out tree
// encoded with meshoptimizer (see MER_GLTF_MESHOPT in meristem/gltf.h).
#include "config.h"

#include "gltf/gltf_private.h"

#include <meshoptimizer.h>

#include <cstring>
#include <memory>
#include <mutex>

namespace merp_gltf {

namespace {

// EXT_meshopt_compression asks for index codec 1 and vertex codec 0; the
// library's version switches are process-wide, so they are set once (gltf.h
// says so).
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

bool is_index_view(const Writer &w, size_t i)
{
    return w.model.bufferViews[i].target == TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER;
}

// Each view's element layout and its worst-case encoded size, and where that
// worst case starts in one scratch area (region[n] is its total).
struct Plan {
    std::vector<size_t> bound, region, stride, count, written;
};

Plan plan_for(const Writer &w)
{
    const size_t n = w.blobs.size();
    Plan p{std::vector<size_t>(n), std::vector<size_t>(n + 1, 0), std::vector<size_t>(n),
           std::vector<size_t>(n), std::vector<size_t>(n, 0)};
    for (size_t i = 0; i < n; i++) {
        const Blob &b = w.blobs[i];
        const bool indices = is_index_view(w, i);
        assert(b.count > 0);  // check_part refuses empty parts and chunks
        p.stride[i] = indices ? b.size / b.count : w.model.bufferViews[i].byteStride;
        p.count[i] = indices ? b.count : b.size / p.stride[i];
        p.bound[i] = 3 + (!indices      ? meshopt_encodeVertexBufferBound(p.count[i], p.stride[i])
                          : b.triangles ? meshopt_encodeIndexBufferBound(b.count, index_bound(b))
                                        : meshopt_encodeIndexSequenceBound(b.count, index_bound(b)));
        p.region[i + 1] = p.region[i] + p.bound[i];
    }
    return p;
}

// Encodes view i into its region of `packed`, laying its raw bytes out in `raw`.
void encode(const Writer &w, Plan &p, size_t i, uint8_t *raw, uint8_t *packed)
{
    const Blob &b = w.blobs[i];
    w.fill(b, raw);
    uint8_t *dst = packed + p.region[i];
    if (is_index_view(w, i)) {
        // The encoder reads 32-bit indices: the caller's own array. TRIANGLES
        // mode may rotate a triangle's corners (keeping its winding); the
        // node-id rule does not depend on the order (see mesh.h, Picking).
        // Line segments take INDICES mode, which keeps every index as it is.
        const uint32_t *src = static_cast<const uint32_t *>(b.src);
        p.written[i] = b.triangles ? meshopt_encodeIndexBuffer(dst, p.bound[i], src, p.count[i])
                                   : meshopt_encodeIndexSequence(dst, p.bound[i], src, p.count[i]);
    } else {
        p.written[i] = meshopt_encodeVertexBuffer(dst, p.bound[i], raw + b.offset, p.count[i],
                                                  p.stride[i]);
    }
}

// Moves the encoded views together in view order, 4-aligned, and points each
// bufferView of `doc` at its bytes; returns the packed size, or 0 with *rc set
// when a view could not be encoded.
size_t pack(const Writer &w, const Plan &p, uint8_t *packed, nlohmann::json &doc, mer_result *rc,
            mer_error *err)
{
    size_t at = 0;
    for (size_t i = 0; i < w.blobs.size(); i++) {
        if (p.written[i] == 0) {
            *rc = mer_error_set(err, MER_ERR_INTERNAL, nullptr,
                                "meshoptimizer could not encode bufferView %zu", i);
            return 0;
        }
        std::memmove(packed + at, packed + p.region[i], p.written[i]);
        const size_t padded = padded4(p.written[i]);
        std::memset(packed + at + p.written[i], 0, padded - p.written[i]);
        nlohmann::json ext = {{"buffer", 0},
                              {"byteOffset", at},
                              {"byteLength", p.written[i]},
                              {"byteStride", p.stride[i]},
                              {"count", p.count[i]},
                              {"mode", !is_index_view(w, i)    ? "ATTRIBUTES"
                                       : w.blobs[i].triangles ? "TRIANGLES"
                                                              : "INDICES"}};
        nlohmann::json &v = doc["bufferViews"][i];
        v["buffer"] = 1;
        v["extensions"]["EXT_meshopt_compression"] = ext;
        at += padded;
    }
    *rc = MER_OK;
    return at;
}

}  // namespace

// Each view is laid out uncompressed, then encoded, into a region of its own
// sized for the worst case, on two threads; the regions are then packed in
// view order. Encoding is most of a compressed snapshot's time, and views do
// not depend on each other.
mer_result write_meshopt(Writer &w, uint8_t **out, size_t *out_size, mer_error *err)
{
    assert(w.blobs.size() == w.model.bufferViews.size());
    meshopt_versions();
    nlohmann::json doc = json_of(w);
    Plan p = plan_for(w);
    std::unique_ptr<uint8_t[]> raw(new uint8_t[w.bin_size + 1]);
    std::unique_ptr<uint8_t[]> packed(new uint8_t[p.region[w.blobs.size()] + 1]);
    w.each_blob([&](size_t i) { encode(w, p, i, raw.get(), packed.get()); });
    mer_result rc;
    const size_t at = pack(w, p, packed.get(), doc, &rc, err);
    if (rc != MER_OK)
        return rc;
    doc["buffers"] = nlohmann::json::array(
        {{{"byteLength", at}},
         {{"byteLength", w.bin_size}, {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}}});
    doc["extensionsUsed"].push_back("EXT_meshopt_compression");
    doc["extensionsRequired"].push_back("EXT_meshopt_compression");
    uint8_t *bin = nullptr;
    rc = assemble_glb(doc, at, out, out_size, &bin, err);
    if (rc == MER_OK && at > 0)
        std::memcpy(bin, packed.get(), at);
    return rc;
}

}  // namespace merp_gltf
