// meristem — what the glTF files of lib/gltf/ share: the Writer that lays a
// tree mesh out as a tinygltf model plus the runs of BIN bytes it will copy
// from the mesh, the quantizers, and the GLB framing. C++; not installed.
#ifndef MERISTEM_GLTF_PRIVATE_H
#define MERISTEM_GLTF_PRIVATE_H

#include "gltf/tinygltf_private.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <new>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <meristem/gltf.h>
#include <meristem/mesh.h>

namespace merp_gltf {

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

// The bounding box of some positions, per axis.
struct Box {
    float lo[3], hi[3];
};

// The box of positions p[first .. first + count) (a NaN is passed over).
Box box_of(const float *p, size_t first, size_t count);

// The uniform grid quantized positions live on: p = center + scale · q.
struct Grid {
    double center[3] = {0, 0, 0};
    double scale = 1;
};

// Round half away from zero, clamped: inline and without a branch on the
// sign (a normal's components change sign at random, and a mispredicted
// branch per component made quantizing the normals the GLB's slowest step).
// For x < 0, x − 0.5 is −(0.5 − x) exactly, and the conversion truncates
// towards zero, as the branch's −(int)(0.5 − x) did.
inline int round_clamped(double x, int limit)
{
    x = std::max(-static_cast<double>(limit), std::min(static_cast<double>(limit), x));
    return static_cast<int>(x + std::copysign(0.5, x));
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

// Bytes in the BIN chunk, views starting 4-aligned.
inline size_t padded4(size_t size)
{
    return (size + 3u) & ~size_t{3};
}

// The model being laid out (writer.cc) and the blobs that fill its BIN chunk:
// bufferView i is filled by blobs[i].
struct Writer {
    tinygltf::Model model;
    std::vector<Blob> blobs;
    size_t bin_size = 0;
    bool quantized = false;
    Grid grid;

    Writer();
    // A bufferView of `count` elements from `src`, appended to the BIN chunk.
    int view(const void *src, size_t count, size_t elem, Fill fill, int target, int stride = 0,
             bool triangles = false);
    int accessor(int view_index, size_t byte_offset, int component, int type, size_t count);
    // A vertex attribute of a whole part: one bufferView that every chunk's
    // accessor reads at its own offset (hence a byteStride, glTF 2.0 §3.6.2.4).
    int vertex_view(const void *src, size_t vertices, int components, Fill fill = Fill::Copy);
    // The POSITION accessor of vertices [first, first + count), with min and
    // max: the box of those positions.
    int positions(int view_index, const Box &box, size_t first, size_t count, bool quantize);
    // An index accessor: UNSIGNED_SHORT when the chunk's vertices allow it.
    int indices(const uint32_t *idx, size_t count, size_t vertex_count, bool triangles);
    // Every blob's bytes into `bin` (bin_size bytes; each_blob), or one blob's
    // at its offset.
    void fill(uint8_t *bin) const;
    void fill(const Blob &b, uint8_t *bin) const;
    // Calls fn(i) once for every blob i: on two threads, the biggest first,
    // each to whichever of this thread and one more has less work so far (a
    // split fixed by the sizes; fn(i) must write only blob i's own bytes, so
    // they are the same every time); in blob order on this thread alone when
    // there is one blob, the BIN chunk is under `two_threads_from` bytes, or
    // a thread cannot be started.
    void each_blob(const std::function<void(size_t)> &fn, size_t two_threads_from = 0) const;
};

// tree.cc: lays out the whole scene graph; the BIN bytes stay in the mesh's arrays.
void build_tree(Writer &w, const mer_mesh &mesh, const mer_gltf_meta *meta);

// glb.cc: the glTF JSON of `w`, as tinygltf writes it, with buffer 0 the BIN chunk.
nlohmann::json json_of(Writer &w);
// Allocates a GLB of `doc` and a BIN chunk of `bin_size` bytes (glTF 2.0 §4.4)
// into *out; *bin points at the BIN bytes for the caller to write (NULL when
// bin_size is 0).
mer_result assemble_glb(const nlohmann::json &doc, size_t bin_size, uint8_t **out,
                        size_t *out_size, uint8_t **bin, mer_error *err);

// meshopt.cc: a GLB with every bufferView compressed (see gltf.h).
mer_result write_meshopt(Writer &w, uint8_t **out, size_t *out_size, mer_error *err);

// Runs `body`, mapping any exception to a mer_result: nothing C++ crosses the C API.
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

}  // namespace merp_gltf

#endif
