/* meristem — mer_mesh_build: options, the scene's nodes, the mesh's exact size
 * (mesh_bound), allocation, and the parts meshed in order (meristem/mesh.h). */
#include "config.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>

#include "core/alloc.h"
#include "mesh_private.h"

/* A twig (mesh.h, Twig lines) is at most 1/TWIG_EXTENT_FRACTION of the tree's
 * largest extent (at least TWIG_EXTENT_MIN) thick at its base. */
#define TWIG_EXTENT_FRACTION 400.0f
#define TWIG_EXTENT_MIN 8.0f
#define LEAF_AGE_DEFAULT 3 /* what leaf_age 0 means */

static mer_result resolve_options(const mer_mesh_options *in, const mer_params *p,
                                  mer_mesh_options *out, mer_error *err)
{
    *out = in != NULL ? *in : (mer_mesh_options){0};
    if (out->detail == 0)
        out->detail = MER_MESH_DETAIL_DEFAULT;
    if (out->detail > MER_MESH_DETAIL_MAX)
        return mer_error_set(err, MER_ERR_RANGE, "detail", "detail must be from 1 to %d, got %u",
                             MER_MESH_DETAIL_MAX, out->detail);
    if (out->leaves > 1 || out->markers > 1 || out->no_uvs > 1 || out->twig_lines > 1)
        return mer_error_set(err, MER_ERR_RANGE,
                             out->leaves > 1    ? "leaves"
                             : out->markers > 1 ? "markers"
                             : out->no_uvs > 1  ? "no_uvs"
                                                : "twig_lines",
                             "must be 0 or 1");
    if (out->color > MER_COLOR_AGE)
        return mer_error_set(err, MER_ERR_RANGE, "color",
                             "colour mode must be none, order, light or age (0 to 3), got %u",
                             out->color);
    if (!(out->leaf_size >= 0.0f && out->leaf_size <= 1000.0f))
        return mer_error_set(err, MER_ERR_RANGE, "leaf_size",
                             "leaf size must be from 0 to 1000, got %g", (double)out->leaf_size);
    if (out->junctions > MER_JUNCTIONS_IMPLICIT)
        return mer_error_set(err, MER_ERR_RANGE, "junctions",
                             "junctions must be tubes or implicit (0 or 1), got %u", out->junctions);
    if (!(out->junction_diameter >= 0.0f && out->junction_diameter <= 1000.0f))
        return mer_error_set(err, MER_ERR_RANGE, "junction_diameter",
                             "junction diameter must be from 0 to 1000, got %g",
                             (double)out->junction_diameter);
    if (out->threads > MERP_MESH_THREADS_MAX)
        return mer_error_set(err, MER_ERR_RANGE, "threads", "threads must be from 0 to %d, got %u",
                             MERP_MESH_THREADS_MAX, out->threads);
    if (out->leaf_size == 0.0f)
        out->leaf_size = 0.8f * p->internode_length;
    if (out->leaf_age == 0)
        out->leaf_age = LEAF_AGE_DEFAULT;
    return MER_OK;
}

mer_result merp_mesh_begin_group(merp_cursor *c, uint32_t vertices, mer_error *err)
{
    mer_mesh_part *part = c->part;
    assert(c->v + vertices <= part->vertex_count);
    mer_mesh_chunk *cur = part->chunk_count ? &part->chunks[part->chunk_count - 1] : NULL;
    if (cur != NULL && cur->twig == c->twig && cur->vertex_count + vertices <= MER_MESH_CHUNK_VERTICES)
        return MER_OK;
    if (part->chunk_count == c->chunk_cap) {
        uint32_t cap = c->chunk_cap ? 2 * c->chunk_cap : 8;
        mer_mesh_chunk *grown = merp_realloc(part->chunks, cap * sizeof *grown);
        if (grown == NULL)
            return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for mesh chunks");
        part->chunks = grown;
        c->chunk_cap = cap;
    }
    part->chunks[part->chunk_count++] = (mer_mesh_chunk){c->v, 0, c->i, 0, c->twig, c->line_i, 0};
    return MER_OK;
}

static mer_result load_nodes(merp_builder *b, mer_error *err)
{
    b->node_count = mer_scene_node_bound(b->scene);
    b->nodes = b->node_count ? merp_malloc((size_t)b->node_count * sizeof *b->nodes) : NULL;
    if (b->node_count && b->nodes == NULL)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for %u nodes", b->node_count);
    float lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0}; /* bounds of the living internodes */
    bool none_yet = true;
    for (uint32_t id = 0; id < b->node_count; id++) {
        mer_result rc = mer_scene_node(b->scene, id, &b->nodes[id], err);
        if (rc != MER_OK)
            return rc;
        const mer_node *n = &b->nodes[id];
        if (!n->alive)
            continue;
        float e[3];
        merp_tip_of(n, e);
        for (int k = 0; k < 3; k++) {
            float low = fminf(n->base[k], e[k]), high = fmaxf(n->base[k], e[k]);
            lo[k] = none_yet || low < lo[k] ? low : lo[k];
            hi[k] = none_yet || high > hi[k] ? high : hi[k];
        }
        none_yet = false;
        if (n->diameter > b->max_diameter)
            b->max_diameter = n->diameter;
        if (n->q > b->max_q)
            b->max_q = n->q;
        if (n->born > b->newest)
            b->newest = n->born;
    }
    float extent = TWIG_EXTENT_MIN;
    for (int k = 0; k < 3; k++)
        extent = fmaxf(extent, hi[k] - lo[k]);
    b->twig_limit = extent / TWIG_EXTENT_FRACTION;
    return MER_OK;
}

/* The mesh's exact size, known once the axes are: meshing writes exactly this
 * many vertices and indices (asserted at the end of mer_mesh_build). */
typedef struct mesh_size {
    uint64_t bark_vertices, bark_indices, line_indices, leaves, internodes, junctions, smooth;
    float twig_diameter_max;
} mesh_size;

static void mesh_bound(const merp_builder *b, mesh_size *out)
{
    *out = (mesh_size){0};
    for (uint32_t i = 0; i < b->axis_count; i++) {
        const merp_axis *a = &b->axes[i];
        out->bark_vertices += merp_axis_vertices(a, !b->opt.no_uvs);
        out->bark_indices += merp_axis_indices(a);
        out->internodes += a->count;
        if (merp_mesh_is_twig(b, a)) {
            out->line_indices += 2 * (uint64_t)a->count;
            float d = b->nodes[a->first].diameter;
            out->twig_diameter_max = d > out->twig_diameter_max ? d : out->twig_diameter_max;
        }
    }
    out->leaves = merp_mesh_leaf_count(b);
    if (b->joints != NULL) {
        uint64_t v, i;
        merp_mesh_joints_size(b, &v, &i);
        out->bark_vertices += v;
        out->bark_indices += i;
        for (uint32_t k = 0; k < b->joint_count; k++) {
            /* forks: a run's patch serves several */
            uint32_t forks = merp_joint_forks(&b->joints[k]);
            out->junctions += b->joints[k].ok ? forks : 0;
            out->smooth += b->joints[k].ok && b->joints[k].smooth ? forks : 0;
        }
    }
}

static mer_result allocate_part(mer_mesh_part *part, uint64_t vertices, uint64_t indices,
                                bool colors, bool uvs, mer_error *err)
{
    if (vertices > UINT32_MAX || indices > UINT32_MAX)
        return mer_error_set(err, MER_ERR_LIMIT, NULL,
                             "the mesh would have more than 2^32 - 1 vertices; lower the detail");
    part->vertex_count = (uint32_t)vertices;
    part->index_count = (uint32_t)indices;
    if (vertices == 0)
        return MER_OK;
    part->positions = merp_malloc(vertices * 3 * sizeof(float));
    part->normals = merp_malloc(vertices * 3 * sizeof(float));
    part->uvs = uvs ? merp_malloc(vertices * 2 * sizeof(float)) : NULL;
    part->node_ids = merp_malloc(vertices * sizeof(uint32_t));
    part->indices = merp_malloc(indices * sizeof(uint32_t));
    part->colors = colors ? merp_malloc(vertices * 4 * sizeof(float)) : NULL;
    if (!part->positions || !part->normals || (uvs && !part->uvs) || !part->node_ids ||
        !part->indices || (colors && !part->colors))
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for %llu vertices",
                             (unsigned long long)vertices);
    return MER_OK;
}

/* Sizes the mesh (mesh_bound) and allocates every array of it. */
static mer_result allocate_mesh(merp_builder *b, mer_error *err)
{
    mesh_size size;
    mesh_bound(b, &size);
    mer_mesh *m = b->mesh;
    m->twig_diameter_max = size.twig_diameter_max;
    bool colors = b->opt.color != MER_COLOR_NONE, uvs = !b->opt.no_uvs;
    mer_result rc = allocate_part(&m->bark, size.bark_vertices, size.bark_indices, colors, uvs, err);
    if (rc == MER_OK)
        rc = allocate_part(&m->leaves, 4 * size.leaves, 6 * size.leaves, colors, uvs, err);
    if (rc != MER_OK)
        return rc;
    if (b->opt.junctions == MER_JUNCTIONS_IMPLICIT && m->bark.vertex_count > 0) {
        m->bark.ridge = merp_calloc(m->bark.vertex_count, sizeof(float));
        if (m->bark.ridge == NULL)
            return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for ridge values");
    }
    m->junctions = (uint32_t)size.junctions;
    if (m->junctions > 0) {
        m->junction_forks = merp_malloc(m->junctions * sizeof *m->junction_forks);
        if (m->junction_forks == NULL)
            return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for the junctions' forks");
        uint32_t n = 0;
        for (uint32_t id = 0; id < b->node_count; id++) /* ascending */
            if (merp_joint_at(b, id) != NULL && !merp_joint_elbow(merp_joint_at(b, id), id))
                m->junction_forks[n++] = id;
        assert(n == m->junctions);
    }
    m->junctions_open = b->joints_open;
    m->junctions_unfit = b->joints_unfit;
    m->junctions_smooth = (uint32_t)size.smooth;
    if (size.line_indices > 0) {
        m->bark.line_indices = merp_malloc(size.line_indices * sizeof(uint32_t));
        if (m->bark.line_indices == NULL)
            return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for twig lines");
        m->bark.line_index_count = (uint32_t)size.line_indices;
    }
    b->bark.part = &m->bark;
    b->leaves.part = &m->leaves;
    m->axes = b->axis_count;
    m->internodes = (uint32_t)size.internodes;
    return MER_OK;
}

static mer_result add_markers(merp_builder *b, mer_error *err)
{
    size_t count = mer_scene_marker_count(b->scene);
    if (count == 0)
        return MER_OK;
    b->mesh->points = merp_malloc(count * 3 * sizeof(float));
    if (b->mesh->points == NULL)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for markers");
    b->mesh->point_count = (uint32_t)mer_scene_markers(b->scene, b->mesh->points, count);
    return MER_OK;
}

mer_result mer_mesh_build(const mer_scene *scene, const mer_mesh_options *options,
                          mer_mesh **out, mer_error *err)
{
    if (out == NULL || scene == NULL)
        return mer_error_set(err, MER_ERR_INVALID, NULL, "no scene or output given");
    *out = NULL;
    merp_builder b = {.scene = scene, .step = mer_scene_step_index(scene)};
    mer_result rc = resolve_options(options, mer_scene_params(scene), &b.opt, err);
    if (rc != MER_OK)
        return rc;
    b.mesh = merp_calloc(1, sizeof *b.mesh);
    if (b.mesh == NULL)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for a mesh");
    if ((rc = load_nodes(&b, err)) == MER_OK && (rc = merp_mesh_collect_axes(&b, err)) == MER_OK &&
        (b.opt.junctions != MER_JUNCTIONS_IMPLICIT || (rc = merp_mesh_joints(&b, err)) == MER_OK) &&
        (rc = allocate_mesh(&b, err)) == MER_OK && (rc = merp_mesh_bark(&b, err)) == MER_OK &&
        (!b.opt.leaves || (rc = merp_mesh_leaves(&b, err)) == MER_OK) &&
        (!b.opt.markers || (rc = add_markers(&b, err)) == MER_OK)) {
        // mesh_bound sized every array; meshing must have filled exactly them,
        // but for the rings that repeat the last (tube.c), which the bark ends short of.
        assert(b.bark.v + b.bark.merged_v == b.mesh->bark.vertex_count &&
               b.bark.i + b.bark.merged_i == b.mesh->bark.index_count);
        b.mesh->bark.vertex_count = b.bark.v;
        b.mesh->bark.index_count = b.bark.i;
        assert(b.bark.line_i == b.mesh->bark.line_index_count);
        assert(b.leaves.v == b.mesh->leaves.vertex_count &&
               b.leaves.i == b.mesh->leaves.index_count);
        *out = b.mesh;
        b.mesh = NULL; // handed over: the cleanup below must not free it
    }
    merp_free(b.nodes);
    merp_free(b.axes);
    merp_free(b.chain);
    merp_free(b.radii);
    merp_mesh_joints_free(&b);
    mer_mesh_free(b.mesh);
    return rc;
}

static void free_part(mer_mesh_part *part)
{
    merp_free(part->chunks);
    merp_free(part->positions);
    merp_free(part->normals);
    merp_free(part->uvs);
    merp_free(part->colors);
    merp_free(part->node_ids);
    merp_free(part->indices);
    merp_free(part->line_indices);
    merp_free(part->ridge);
}

void mer_mesh_free(mer_mesh *mesh)
{
    if (mesh == NULL)
        return;
    free_part(&mesh->bark);
    free_part(&mesh->leaves);
    merp_free(mesh->points);
    merp_free(mesh->junction_forks);
    merp_free(mesh);
}
