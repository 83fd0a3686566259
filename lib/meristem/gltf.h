/* meristem — glTF 2.0 encoding behind a plain C API.
 *
 * lib/gltf/ wraps tinygltf (Debian's libtinygltf-dev, header-only here, with
 * image loading compiled out) and meshoptimizer. Nothing C++ crosses this
 * header: every entry point catches all exceptions and maps them to a mer_result.
 *
 * Threads and process state. mer_gltf_write_tree may use one extra thread,
 * started and joined within the call (all on the caller's thread when none
 * can be started): with MER_GLTF_MESHOPT always, to encode, and otherwise
 * when the BIN chunk is 1 MiB or more, to fill it (copying and quantizing
 * the attributes). The bytes are the same either way. meristem/scene.h says
 * the library has no global mutable state; MER_GLTF_MESHOPT is the exception:
 * the first such call sets meshoptimizer's encoder versions process-wide
 * (index codec 1, vertex codec 0, as EXT_meshopt_compression requires), once
 * and thread-safely. A program that also calls meshoptimizer's encoders
 * itself shares those settings.
 */
#ifndef MERISTEM_GLTF_H
#define MERISTEM_GLTF_H

#include <stddef.h>
#include <stdint.h>

#include <meristem/mesh.h>
#include <meristem/result.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Node ids travel in the `_NODE_ID` vertex attribute as FLOAT, because glTF 2.0
 * allows UNSIGNED_INT only for indices (accessor.componentType). float32 holds
 * every integer below 2^24 exactly; larger ids are refused. */
#define MER_GLTF_NODE_ID_LIMIT (1u << 24)

typedef enum mer_gltf_format {
    MER_GLTF_BINARY = 0,   /* .glb: JSON chunk + BIN chunk */
    MER_GLTF_EMBEDDED = 1  /* .gltf: JSON with the buffer as a base64 data URI, for debugging */
} mer_gltf_format;

/* What a snapshot says about its own origin, written to asset.extras so that a
 * GLB tells how to grow it again. Strings may be NULL (then left out). Every
 * written meta also has asset.extras.units: {"length": "metre", "up": "+Y",
 * "internode_length": l0}: one unit of the file is one metre (glTF's own unit),
 * the plants stand on y = 0 with their first internode's base at their seed
 * point (the origin for one plant), and an internode grows l0 units long. */
typedef struct mer_gltf_meta {
    const char *session;  /* session id */
    uint64_t revision;
    uint32_t step;
    const char *preset;
    uint64_t seed;        /* written as a number below 2^53, else as a decimal string */
    uint32_t detail;      /* the mesh options it was made with, for the record */
    uint32_t leaves;
    uint32_t markers;
    uint32_t color;
    double internode_length; /* the tree's l0 in units, for asset.extras.units; 0: left out */
} mer_gltf_meta;

typedef enum mer_gltf_compression {
    MER_GLTF_UNCOMPRESSED = 0,
    MER_GLTF_MESHOPT = 1   /* EXT_meshopt_compression (GLB only); see mer_gltf_write_tree */
} mer_gltf_compression;

/* How to write. All-zero: GLB with quantized vertices, uncompressed. The
 * daemon's and the offline command's default is unquantized (every importer
 * reads float positions at an identity node transform; assimp and Blender
 * versions without KHR_mesh_quantization do not read the quantized form). */
typedef struct mer_gltf_options {
    uint32_t format;      /* mer_gltf_format; default MER_GLTF_BINARY */
    uint32_t unquantized; /* 1: float positions and normals, no extension; 0: quantized */
    uint32_t compression; /* mer_gltf_compression; default MER_GLTF_UNCOMPRESSED */
} mer_gltf_options;

/* Encodes a tree mesh: node "tree" with mesh "tree" holding the bark primitive
 * (material "bark") and, when present, the leaves (material "leaf",
 * double-sided); node "markers" with a POINTS primitive when the mesh has
 * markers. Attributes: POSITION (with min/max), NORMAL, TEXCOORD_0, COLOR_0
 * (when the mesh has colours), `_NODE_ID` and, with implicit junctions, `_RIDGE`
 * (FLOAT, b = F_b: 0 on tubes, up to 1 on a branch bark ridge, for a renderer
 * to darken and roughen the bark there; mesh.h, Junctions); indices UNSIGNED_SHORT when a
 * chunk has at most 65535 vertices (every chunk is one primitive), else
 * UNSIGNED_INT. A twig chunk (mesh.h, Twig lines) has extras {"twig": true}
 * and is followed by a LINES primitive of its line segments (material "twig",
 * POSITION and COLOR_0 the chunk's own accessors, no NORMAL or `_NODE_ID`,
 * extras {"twig_diameter_max": d}); in compressed GLBs its indices take the
 * INDICES mode. Materials are PBR metallic-roughness. asset.generator is
 * "meristem VERSION"; `meta` (may be NULL) goes to asset.extras. `options` may
 * be NULL (defaults).
 *
 * Unquantized: FLOAT positions and normals in world units, and the "tree" node
 * has no transform (the identity), so an importer places the tree at unit scale
 * with its base at the origin.
 *
 * Quantized (the all-zero options, KHR_mesh_quantization, listed as required): bark and
 * leaf positions are SHORT integers on a uniform grid over the tree's bounding
 * box, with the "tree" node's translation and uniform scale mapping them back
 * (a step of the largest half-extent / 32767: 0.3 mm on a 20 m tree), and
 * normals are normalized BYTEs. That takes a vertex from 36 to 24 bytes; three.js
 * and Blender read the extension. Colours become normalized UNSIGNED_BYTE RGBA
 * (core glTF), 4 bytes instead of 16. Markers stay FLOAT.
 *
 * Compressed (MER_GLTF_MESHOPT, EXT_meshopt_compression, listed as required):
 * every bufferView keeps its uncompressed layout in buffer 1, a fallback buffer
 * with no data, and names its compressed bytes in buffer 0, the BIN chunk:
 * vertex streams in ATTRIBUTES mode (vertex codec 0, no filter), indices in
 * TRIANGLES mode (the index buffer codec, version 1: on a tree about a third
 * fewer bytes than the INDICES mode's sequence codec). Decoding gives back exactly
 * the bytes of the uncompressed GLB's BIN chunk, except that a triangle's
 * corners may come back rotated (same triangle, same winding): the node-id rule
 * does not depend on their order (see mesh.h, Picking). A tree
 * without UVs takes about a third of the bytes of the default snapshot. three.js reads it with its MeshoptDecoder; Blender's
 * importer does not, so snapshots for artists stay uncompressed. Refused
 * (MER_ERR_RANGE, "compression") with MER_GLTF_EMBEDDED.
 *
 * For MER_GLTF_BINARY, tinygltf writes the JSON and the big arrays go straight
 * from the mesh into the returned bytes: they are copied once. On MER_OK the
 * caller frees *out with mer_gltf_free(). Deterministic: the same mesh and meta
 * give the same bytes. Cost O(vertices + indices). */
mer_result mer_gltf_write_tree(const mer_mesh *mesh, const mer_gltf_meta *meta,
                               const mer_gltf_options *options, uint8_t **out, size_t *out_size,
                               mer_error *err);

/* Reads every TRIANGLES primitive (indexed or not) of the default scene of a
 * glTF 2.0 asset, GLB or JSON with embedded (data URI) buffers, and returns its
 * triangles in world space (node transforms applied) as a flat array of
 * 9 floats per triangle: for an obstacle or a marker volume. External files
 * are refused (lib does no I/O). Quantized and normalized position accessors are
 * decoded; sparse accessors are refused. On MER_OK *out_xyz (free with
 * mer_gltf_free) holds *out_triangles triangles. MER_ERR_FORMAT with tinygltf's
 * message for a file that is not glTF; MER_ERR_LIMIT past `max_triangles`.
 * Cost O(file size + triangles). */
mer_result mer_gltf_read_triangles(const uint8_t *bytes, size_t size, size_t max_triangles,
                                   float **out_xyz, size_t *out_triangles, mer_error *err);

/* Frees bytes returned by this module. NULL is fine. */
void mer_gltf_free(void *bytes);

#ifdef __cplusplus
}
#endif

#endif
