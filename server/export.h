/* meristem — a scene as a glTF file, the one way meristemd's snapshots and the
 * offline command write one: mesh it, describe where it came from, encode. */
#ifndef MERISTEM_EXPORT_H
#define MERISTEM_EXPORT_H

#include <stddef.h>
#include <stdint.h>

#include <meristem/gltf.h>
#include <meristem/mesh.h>
#include <meristem/scene.h>

/* Where a tree came from, for the file's asset.extras. */
typedef struct merd_origin {
    const char *session; /* NULL outside a session */
    uint64_t revision;
    const char *preset;
    uint64_t seed;
} merd_origin;

/* The cores this process may run on (its CPU affinity's, else the online
 * ones; no more than its control groups' CPU quota allows, cpu_quota.h), at
 * least 1 and at most the library's 64 threads: all of them for one mesh's
 * implicit junction patches, or the pool meristemd lends its snapshots
 * (cores.h). Cost: a system call and a few small file reads. */
uint32_t merd_export_cores(void);

/* What a mesh held, for a summary: triangles, and its implicit junctions
 * (mer_mesh's counts of the same names; all 0 with tubes). */
typedef struct merd_export_counts {
    size_t triangles;
    uint32_t junctions, junctions_smooth, junctions_open, junctions_unfit;
} merd_export_counts;

/* Meshes `scene` with `mesh` options (implicit junctions on all the machine's
 * cores, merd_export_cores(), when `mesh` asks for no thread count:
 * one offline export) and encodes it with `gltf` options into
 * *bytes (*size; caller frees with mer_gltf_free). `*counts` (may be NULL)
 * gets the mesh's counts once it is built, also on an encoding failure
 * (triangles stay 0 when meshing fails). MER_OK, or the library's failure
 * with `err` filled. Costs a full mesh build. */
mer_result merd_export_tree(const mer_scene *scene, const mer_mesh_options *mesh,
                            const mer_gltf_options *gltf, const merd_origin *origin,
                            uint8_t **bytes, size_t *size, merd_export_counts *counts, mer_error *err);

#endif
