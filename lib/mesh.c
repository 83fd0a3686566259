/* meristem — tree geometry (see meristem/mesh.h for the choices). */
#include "config.h"

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include <meristem/mesh.h>

#include "scene_private.h"
#include "vec_private.h"

#define TWO_PI 6.28318530717958647692f

#define MAX_SIDES 16
/* A twig (mesh.h, Twig lines) is at most this fraction of the tree's largest
 * extent (at least TWIG_EXTENT_MIN) thick at its base: 1/400 is about 1.4 px
 * where the brush client frames the whole tree in a 750-px view. */
#define TWIG_EXTENT_FRACTION 400.0f
#define TWIG_EXTENT_MIN 8.0f

static const uint32_t max_sides_by_detail[MER_MESH_DETAIL_MAX + 1] = {0, 4, 6, 8, 12, MAX_SIDES};

enum axis_end { END_TIP, END_CUT };

typedef struct axis {
    uint32_t first;   /* id of its first internode */
    uint32_t count;   /* internodes along it */
    uint32_t sides;
    uint8_t end;      /* enum axis_end */
    uint8_t base_cap; /* 1 for a plant's trunk */
} axis;

/* Where the next vertex and index of a part go, and the chunk being filled. */
typedef struct cursor {
    mer_mesh_part *part;
    uint32_t v, i;
    uint32_t chunk_cap;
    uint32_t twig;     /* the `twig` flag of the chunks being made */
    uint32_t line_i;   /* next twig line index (bark only) */
} cursor;

typedef struct builder {
    const mer_scene *scene;
    mer_node *nodes;        /* by id */
    uint32_t node_count;
    mer_mesh_options opt;
    uint32_t step;
    uint32_t newest;        /* latest step in which a living internode was made */
    float max_diameter;
    float max_q;
    float twig_limit;       /* with twig_lines: the largest base diameter of a twig */
    axis *axes;
    uint32_t axis_count;
    mer_mesh *mesh;
    uint32_t *chain;        /* scratch: one axis's node ids */
    float *radii;           /* scratch: its ring radii */
    uint32_t chain_cap;
    cursor bark, leaves;    /* write positions */
} builder;

static float clampf(float x, float lo, float hi) { return x < lo ? lo : x > hi ? hi : x; }

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
    if (out->leaf_size == 0.0f)
        out->leaf_size = 0.8f * p->internode_length;
    if (out->leaf_age == 0)
        out->leaf_age = 3;
    return MER_OK;
}

static bool alive(const builder *b, uint32_t id)
{
    return id != MER_NO_NODE && id < b->node_count && b->nodes[id].alive;
}

static uint32_t sides_for(const builder *b, float diameter)
{
    uint32_t max = max_sides_by_detail[b->opt.detail];
    float f = b->max_diameter > 0.0f ? clampf(diameter / b->max_diameter, 0.0f, 1.0f) : 1.0f;
    return 3u + (uint32_t)lrintf((float)(max - 3u) * f);
}

/* A twig (mesh.h, Twig lines): a 3-sided axis no thicker than twig_limit. */
static bool is_twig(const builder *b, const axis *a)
{
    return b->opt.twig_lines && a->sides == 3 && b->nodes[a->first].diameter <= b->twig_limit;
}

/* Finds every axis: a living node whose parent is absent (a trunk) or whose
 * parent continues elsewhere (a branch). Ascending ids keep the output stable. */
static mer_result collect_axes(builder *b, mer_error *err)
{
    uint32_t cap = 0;
    for (uint32_t id = 0; id < b->node_count; id++) {
        const mer_node *n = &b->nodes[id];
        if (!n->alive)
            continue;
        bool trunk = n->parent == MER_NO_NODE;
        if (!trunk && (!alive(b, n->parent) || b->nodes[n->parent].main_child == id))
            continue;
        if (b->axis_count == cap) {
            cap = cap ? 2 * cap : 256;
            axis *grown = realloc(b->axes, cap * sizeof *grown);
            if (grown == NULL)
                return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for axes");
            b->axes = grown;
        }
        axis *a = &b->axes[b->axis_count++];
        a->first = id;
        a->count = 1;
        a->base_cap = trunk;
        uint32_t last = id;
        while (alive(b, b->nodes[last].main_child)) {
            last = b->nodes[last].main_child;
            a->count++;
        }
        // A tip still has its terminal bud (dormant, flowered or aborted); a
        // pruned or shed continuation leaves neither child nor bud: a cut.
        const mer_node *end = &b->nodes[last];
        a->end = end->main_child == MER_NO_NODE && end->terminal_bud != MER_BUD_NONE ? END_TIP
                                                                                     : END_CUT;
        a->sides = sides_for(b, n->diameter);
    }
    return MER_OK;
}

static bool has_leaf_at(const builder *b, const mer_node *n)
{
    return n->alive && b->newest - n->born < b->opt.leaf_age;
}

static uint32_t leaves_per_node(const builder *b)
{
    return mer_scene_params(b->scene)->buds_per_node >= 2 ? 2u : 1u;
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
    part->positions = malloc(vertices * 3 * sizeof(float));
    part->normals = malloc(vertices * 3 * sizeof(float));
    part->uvs = uvs ? malloc(vertices * 2 * sizeof(float)) : NULL;
    part->node_ids = malloc(vertices * sizeof(uint32_t));
    part->indices = malloc(indices * sizeof(uint32_t));
    part->colors = colors ? malloc(vertices * 4 * sizeof(float)) : NULL;
    if (!part->positions || !part->normals || (uvs && !part->uvs) || !part->node_ids ||
        !part->indices || (colors && !part->colors))
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for %llu vertices",
                             (unsigned long long)vertices);
    return MER_OK;
}

/* ------------------------------------------------------------------ colours */

static void color_of(const builder *b, const mer_node *n, float out[4])
{
    static const float palette[6][3] = {{0.45f, 0.25f, 0.10f}, {0.80f, 0.35f, 0.10f},
                                        {0.90f, 0.75f, 0.15f}, {0.35f, 0.70f, 0.20f},
                                        {0.15f, 0.55f, 0.75f}, {0.55f, 0.30f, 0.75f}};
    out[3] = 1.0f;
    switch (b->opt.color) {
    case MER_COLOR_ORDER: {
        const float *c = palette[n->order % 6];
        memcpy(out, c, 3 * sizeof(float));
        return;
    }
    case MER_COLOR_LIGHT: {
        float t = b->max_q > 0.0f ? clampf(n->q / b->max_q, 0.0f, 1.0f) : 0.0f;
        out[0] = 0.05f + 0.95f * t;
        out[1] = 0.05f + 0.85f * t;
        out[2] = 0.45f - 0.35f * t;
        return;
    }
    case MER_COLOR_AGE: {
        float t = b->step > 0 ? clampf((float)(b->step - n->born) / (float)b->step, 0.0f, 1.0f) : 0.0f;
        out[0] = 0.30f + 0.15f * t;
        out[1] = 0.75f - 0.50f * t;
        out[2] = 0.20f - 0.10f * t;
        return;
    }
    default:
        out[0] = out[1] = out[2] = 1.0f;
        return;
    }
}

/* ------------------------------------------------------------------- bark */

/* Makes room for a group of `vertices` that triangles will join: when the
 * current chunk cannot take them all under MER_MESH_CHUNK_VERTICES, or has
 * another `twig` flag than the cursor's, a new chunk starts here. */
static mer_result begin_group(cursor *c, uint32_t vertices, mer_error *err)
{
    mer_mesh_part *part = c->part;
    mer_mesh_chunk *cur = part->chunk_count ? &part->chunks[part->chunk_count - 1] : NULL;
    if (cur != NULL && cur->twig == c->twig && cur->vertex_count + vertices <= MER_MESH_CHUNK_VERTICES)
        return MER_OK;
    if (part->chunk_count == c->chunk_cap) {
        uint32_t cap = c->chunk_cap ? 2 * c->chunk_cap : 8;
        mer_mesh_chunk *grown = realloc(part->chunks, cap * sizeof *grown);
        if (grown == NULL)
            return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for mesh chunks");
        part->chunks = grown;
        c->chunk_cap = cap;
    }
    part->chunks[part->chunk_count++] = (mer_mesh_chunk){c->v, 0, c->i, 0, c->twig, c->line_i, 0};
    return MER_OK;
}

static inline uint32_t put_vertex(builder *b, cursor *c, const float p[3], const float nrm[3], float u,
                           float v, const mer_node *node)
{
    mer_mesh_part *part = c->part;
    uint32_t k = c->v++;
    memcpy(part->positions + 3 * k, p, 3 * sizeof(float));
    memcpy(part->normals + 3 * k, nrm, 3 * sizeof(float));
    if (part->uvs != NULL) {
        part->uvs[2 * k] = u;
        part->uvs[2 * k + 1] = v;
    }
    part->node_ids[k] = node->id;
    if (part->colors != NULL)
        color_of(b, node, part->colors + 4 * k);
    part->chunks[part->chunk_count - 1].vertex_count++;
    return k;
}

/* A triangle of absolute vertex numbers, stored relative to its chunk. */
static inline void put_triangle(cursor *c, uint32_t a, uint32_t a1, uint32_t a2)
{
    mer_mesh_part *part = c->part;
    mer_mesh_chunk *chunk = &part->chunks[part->chunk_count - 1];
    uint32_t *t = part->indices + c->i;
    t[0] = a - chunk->first_vertex;
    t[1] = a1 - chunk->first_vertex;
    t[2] = a2 - chunk->first_vertex;
    c->i += 3;
    chunk->index_count += 3;
}

/* A twig line segment of absolute vertex numbers, stored relative to its chunk. */
static inline void put_line(cursor *c, uint32_t a, uint32_t a1)
{
    mer_mesh_part *part = c->part;
    mer_mesh_chunk *chunk = &part->chunks[part->chunk_count - 1];
    part->line_indices[c->line_i++] = a - chunk->first_vertex;
    part->line_indices[c->line_i++] = a1 - chunk->first_vertex;
    chunk->line_index_count += 2;
}

static float radius_of(const mer_node *n) { return 0.5f * n->diameter; }

static void node_end(const mer_node *n, float out[3])
{
    for (int k = 0; k < 3; k++)
        out[k] = n->base[k] + n->dir[k] * n->length;
}

/* Carries the frame normal `normal` from tangent `from` to tangent `to` by the
 * rotation between them: discrete parallel transport, hence no twist. Rodrigues
 * with the rotation's cosine and sine taken straight from dot and cross. */
static void transport(float normal[3], const float from[3], const float to[3])
{
    float k[3];
    v3_cross(from, to, k);
    float s = v3_len(k);
    if (s > 1e-7f) {
        float c = v3_dot(from, to);
        k[0] /= s;
        k[1] /= s;
        k[2] /= s;
        float kxn[3];
        v3_cross(k, normal, kxn);
        float d = v3_dot(k, normal) * (1.0f - c);
        for (int i = 0; i < 3; i++)
            normal[i] = normal[i] * c + kxn[i] * s + k[i] * d;
    }
    // Re-orthogonalize against rounding drift along long axes.
    float d = v3_dot(normal, to);
    for (int i = 0; i < 3; i++)
        normal[i] -= d * to[i];
    if (!v3_normalize(normal))
        v3_any_perp(to, normal);
}

static uint64_t axis_vertices(const axis *a, bool seam);

/* The vertex after j on a ring of `stride` vertices: with a seam vertex the ring
 * never wraps (j + 1 ≤ sides < stride); without one, the last joins the first. */
static inline uint32_t next_on_ring(uint32_t j, uint32_t stride)
{
    return j + 1 < stride ? j + 1 : 0;
}

static mer_result chain_of(builder *b, const axis *a, mer_error *err)
{
    if (a->count > b->chain_cap) {
        uint32_t cap = a->count > 2 * b->chain_cap ? a->count : 2 * b->chain_cap;
        uint32_t *grown = realloc(b->chain, cap * sizeof *grown);
        float *radii = realloc(b->radii, (cap + 1) * sizeof *radii);
        if (grown != NULL)
            b->chain = grown;
        if (radii != NULL)
            b->radii = radii;
        if (grown == NULL || radii == NULL)
            return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for an axis");
        b->chain_cap = cap;
    }
    uint32_t id = a->first;
    for (uint32_t i = 0; i < a->count; i++, id = b->nodes[id].main_child)
        b->chain[i] = id;
    // Ring i sits below internode i and has its radius; the tip ring the last one's.
    for (uint32_t i = 0; i <= a->count; i++)
        b->radii[i] = radius_of(&b->nodes[b->chain[i < a->count ? i : a->count - 1]]);
    return MER_OK;
}

static mer_result mesh_axis(builder *b, const axis *a, const float *cos_t, const float *sin_t,
                            mer_error *err)
{
    mer_result rc = chain_of(b, a, err);
    if (rc == MER_OK)
        rc = begin_group(&b->bark, (uint32_t)axis_vertices(a, !b->opt.no_uvs), err);
    if (rc != MER_OK)
        return rc;
    cursor *c = &b->bark;
    // A ring repeats its first vertex at u = 1 for the UV seam; without UVs it need not.
    const bool seam = !b->opt.no_uvs;
    const uint32_t sides = a->sides, stride = seam ? sides + 1 : sides, count = a->count;
    const mer_node *first = &b->nodes[b->chain[0]];
    const mer_node *last = &b->nodes[b->chain[count - 1]];
    const float *r = b->radii;
    // A living tip's last internode is a cone to its end point; a cut keeps its ring.
    const uint32_t rings = a->end == END_TIP ? count : count + 1;

    float t_prev[3], normal[3];
    memcpy(t_prev, first->dir, sizeof t_prev);
    // A deterministic start frame: horizontal where it can be.
    const float up[3] = {0.0f, 1.0f, 0.0f};
    v3_cross(up, t_prev, normal);
    if (!v3_normalize(normal))
        v3_any_perp(t_prev, normal);

    const uint32_t ring0 = c->v;
    float v = 0.0f;
    for (uint32_t i = 0; i < rings; i++) {
        const mer_node *owner = &b->nodes[b->chain[i < count ? i : count - 1]];
        float center[3], t[3];
        if (i == 0) {
            memcpy(center, first->base, sizeof center);
            memcpy(t, first->dir, sizeof t);
        } else {
            const mer_node *below = &b->nodes[b->chain[i - 1]];
            node_end(below, center);
            for (int k = 0; k < 3; k++)
                t[k] = below->dir[k] + owner->dir[k];
            if (!v3_normalize(t))
                memcpy(t, owner->dir, sizeof t);
            float circumference = TWO_PI * 0.5f * (r[i - 1] + r[i]);
            v += circumference > 0.0f ? below->length / circumference : 0.0f;
        }
        transport(normal, t_prev, t);
        memcpy(t_prev, t, sizeof t_prev);
        float bin[3];
        v3_cross(t, normal, bin);

        // Tilt normals by the local taper (central difference of the radii), so a
        // cone shades as a cone.
        uint32_t lo = i > 0 ? i - 1 : 0, hi = i < count ? i + 1 : count;
        float span = 0.0f;
        for (uint32_t k = lo; k < hi; k++)
            span += b->nodes[b->chain[k < count ? k : count - 1]].length;
        float slope = span > 0.0f ? (r[lo] - r[hi]) / span : 0.0f;
        // radial ⊥ t and both are unit, so |radial + slope·t| is the same all round.
        const float inv = 1.0f / sqrtf(1.0f + slope * slope);

        for (uint32_t j = 0; j < stride; j++) {
            uint32_t jj = j == sides ? 0 : j;
            float radial[3], p[3], nrm[3];
            for (int k = 0; k < 3; k++) {
                radial[k] = cos_t[jj] * normal[k] + sin_t[jj] * bin[k];
                p[k] = center[k] + r[i] * radial[k];
                nrm[k] = (radial[k] + slope * t[k]) * inv;
            }
            put_vertex(b, c, p, nrm, (float)j / (float)sides, v, owner);
        }
        if (i > 0) {
            uint32_t below_ring = ring0 + (i - 1) * stride, this_ring = ring0 + i * stride;
            for (uint32_t j = 0; j < sides; j++) {
                uint32_t k = next_on_ring(j, stride);
                put_triangle(c, below_ring + j, below_ring + k, this_ring + k);
                put_triangle(c, below_ring + j, this_ring + k, this_ring + j);
            }
        }
    }

    const uint32_t top_ring = ring0 + (rings - 1) * stride;
    // A twig's line runs along its prism's first edge: at under a pixel wide, the
    // edge and the centre line are the same pixels.
    if (c->twig)
        for (uint32_t i = 0; i + 1 < rings; i++)
            put_line(c, ring0 + i * stride, ring0 + (i + 1) * stride);
    float tip[3];
    node_end(last, tip);
    if (a->end == END_TIP) {
        float circumference = TWO_PI * 0.5f * r[count - 1];
        v += circumference > 0.0f ? last->length / circumference : 0.0f;
        uint32_t apex = put_vertex(b, c, tip, last->dir, 0.5f, v, last);
        for (uint32_t j = 0; j < sides; j++)
            put_triangle(c, top_ring + j, top_ring + next_on_ring(j, stride), apex);
        if (c->twig)
            put_line(c, top_ring, apex);
    } else {
        uint32_t center_id = put_vertex(b, c, tip, t_prev, 0.5f, 0.5f, last);
        uint32_t rim = c->v;
        for (uint32_t j = 0; j < sides; j++) {
            float p[3];
            memcpy(p, c->part->positions + 3 * (top_ring + j), sizeof p);
            put_vertex(b, c, p, t_prev, 0.5f + 0.5f * cos_t[j], 0.5f + 0.5f * sin_t[j], last);
        }
        for (uint32_t j = 0; j < sides; j++)
            put_triangle(c, center_id, rim + j, rim + (j + 1) % sides);
    }
    if (a->base_cap) {
        const float down[3] = {-first->dir[0], -first->dir[1], -first->dir[2]};
        uint32_t center_id = put_vertex(b, c, first->base, down, 0.5f, 0.5f, first);
        uint32_t rim = c->v;
        for (uint32_t j = 0; j < sides; j++) {
            float p[3];
            memcpy(p, c->part->positions + 3 * (ring0 + j), sizeof p);
            put_vertex(b, c, p, down, 0.5f + 0.5f * cos_t[j], 0.5f - 0.5f * sin_t[j], first);
        }
        // Seen from below the ring runs clockwise: reverse it to face outwards.
        for (uint32_t j = 0; j < sides; j++)
            put_triangle(c, center_id, rim + (j + 1) % sides, rim + j);
    }
    return MER_OK;
}

static uint64_t axis_vertices(const axis *a, bool seam)
{
    const uint64_t ring = seam ? a->sides + 1 : a->sides, cap = a->sides + 1;  // cap: centre + rim
    const uint64_t v = a->end == END_TIP ? a->count * ring + 1 : (a->count + 1) * ring + cap;
    return a->base_cap ? v + cap : v;
}

static uint64_t axis_indices(const axis *a)
{
    uint64_t quads = a->end == END_TIP ? a->count - 1 : a->count;
    uint64_t i = quads * a->sides * 6 + (uint64_t)a->sides * 3;
    return a->base_cap ? i + (uint64_t)a->sides * 3 : i;
}

/* ----------------------------------------------------------------- leaves */

static mer_result mesh_leaf(builder *b, const mer_node *n, const float dir_in[3], mer_error *err)
{
    float d[3] = {dir_in[0], dir_in[1], dir_in[2]};
    if (!v3_normalize(d))
        return MER_OK;
    // Face up as far as the leaf's direction allows.
    const float up[3] = {0.0f, 1.0f, 0.0f};
    float face[3];
    float k = v3_dot(up, d);
    for (int i = 0; i < 3; i++)
        face[i] = up[i] - k * d[i];
    if (!v3_normalize(face))
        v3_any_perp(d, face);
    float w[3];
    v3_cross(d, face, w);

    float base[3], left[3], right[3], tip[3];
    node_end(n, base);
    float len = b->opt.leaf_size, half_w = 0.25f * len;
    for (int i = 0; i < 3; i++) {
        tip[i] = base[i] + d[i] * len;
        left[i] = base[i] + d[i] * 0.5f * len - w[i] * half_w;
        right[i] = base[i] + d[i] * 0.5f * len + w[i] * half_w;
    }
    cursor *c = &b->leaves;
    mer_result rc = begin_group(c, 4, err);
    if (rc != MER_OK)
        return rc;
    uint32_t v0 = put_vertex(b, c, base, face, 0.5f, 0.0f, n);
    put_vertex(b, c, right, face, 1.0f, 0.5f, n);
    put_vertex(b, c, tip, face, 0.5f, 1.0f, n);
    put_vertex(b, c, left, face, 0.0f, 0.5f, n);
    // (d, w, face) is right-handed, so base → right → tip turns about +face.
    put_triangle(c, v0, v0 + 1, v0 + 2);
    put_triangle(c, v0, v0 + 2, v0 + 3);
    return MER_OK;
}

/* -------------------------------------------------------------- assembly */

static mer_result load_nodes(builder *b, mer_error *err)
{
    b->node_count = mer_scene_node_bound(b->scene);
    b->nodes = b->node_count ? malloc((size_t)b->node_count * sizeof *b->nodes) : NULL;
    if (b->node_count && b->nodes == NULL)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for %u nodes", b->node_count);
    float lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0}; /* bounds of the living internodes */
    bool none_yet = true;
    for (uint32_t id = 0; id < b->node_count; id++) {
        mer_result rc = mer_scene_node(b->scene, id, &b->nodes[id], err);
        if (rc != MER_OK)
            return rc;
        const mer_node *n = &b->nodes[id];
        if (n->alive) {
            float e[3];
            node_end(n, e);
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
    }
    float extent = TWIG_EXTENT_MIN;
    for (int k = 0; k < 3; k++)
        extent = fmaxf(extent, hi[k] - lo[k]);
    b->twig_limit = extent / TWIG_EXTENT_FRACTION;
    return MER_OK;
}

mer_result mer_mesh_build(const mer_scene *scene, const mer_mesh_options *options,
                          mer_mesh **out, mer_error *err)
{
    if (out == NULL || scene == NULL)
        return mer_error_set(err, MER_ERR_INVALID, NULL, "no scene or output given");
    *out = NULL;
    builder b = {.scene = scene, .step = mer_scene_step_index(scene)};
    mer_result rc = resolve_options(options, mer_scene_params(scene), &b.opt, err);
    if (rc != MER_OK)
        return rc;
    b.mesh = calloc(1, sizeof *b.mesh);
    if (b.mesh == NULL)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for a mesh");
    if ((rc = load_nodes(&b, err)) != MER_OK || (rc = collect_axes(&b, err)) != MER_OK)
        goto done;

    uint64_t bark_v = 0, bark_i = 0, internodes = 0, line_i = 0;
    for (uint32_t i = 0; i < b.axis_count; i++) {
        const axis *a = &b.axes[i];
        bark_v += axis_vertices(a, !b.opt.no_uvs);
        bark_i += axis_indices(a);
        internodes += a->count;
        if (is_twig(&b, a)) {
            line_i += 2 * (uint64_t)a->count;
            float d = b.nodes[a->first].diameter;
            b.mesh->twig_diameter_max = d > b.mesh->twig_diameter_max ? d : b.mesh->twig_diameter_max;
        }
    }
    uint64_t leaf_count = 0;
    if (b.opt.leaves)
        for (uint32_t id = 0; id < b.node_count; id++)
            leaf_count += has_leaf_at(&b, &b.nodes[id]) ? leaves_per_node(&b) : 0;
    bool colors = b.opt.color != MER_COLOR_NONE, uvs = !b.opt.no_uvs;
    if ((rc = allocate_part(&b.mesh->bark, bark_v, bark_i, colors, uvs, err)) != MER_OK ||
        (rc = allocate_part(&b.mesh->leaves, 4 * leaf_count, 6 * leaf_count, colors, uvs, err)) !=
            MER_OK)
        goto done;
    if (line_i > 0) {
        b.mesh->bark.line_indices = malloc(line_i * sizeof(uint32_t));
        if (b.mesh->bark.line_indices == NULL) {
            rc = mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for twig lines");
            goto done;
        }
        b.mesh->bark.line_index_count = (uint32_t)line_i;
    }
    b.bark.part = &b.mesh->bark;
    b.leaves.part = &b.mesh->leaves;
    b.mesh->axes = b.axis_count;
    b.mesh->internodes = (uint32_t)internodes;

    float cos_t[MAX_SIDES], sin_t[MAX_SIDES];
    uint32_t table_sides = 0;
    // With twig lines, thicker axes first, then the twigs in chunks of their own.
    const uint32_t passes = b.opt.twig_lines ? 2 : 1;
    for (uint32_t pass = 0; pass < passes; pass++) {
        b.bark.twig = pass == 1;
        for (uint32_t i = 0; i < b.axis_count; i++) {
            const axis *a = &b.axes[i];
            if (passes == 2 && is_twig(&b, a) != (pass == 1))
                continue;
            if (a->sides != table_sides) {
                for (uint32_t j = 0; j < a->sides; j++) {
                    float angle = TWO_PI * (float)j / (float)a->sides;
                    cos_t[j] = cosf(angle);
                    sin_t[j] = sinf(angle);
                }
                table_sides = a->sides;
            }
            if ((rc = mesh_axis(&b, a, cos_t, sin_t, err)) != MER_OK)
                goto done;
        }
    }

    if (b.opt.leaves) {
        uint32_t per_node = leaves_per_node(&b);
        for (uint32_t id = 0; id < b.node_count; id++) {
            if (!has_leaf_at(&b, &b.nodes[id]))
                continue;
            for (uint32_t k = 1; k <= per_node; k++) {
                float d[3];
                merp_bud_dir(scene, id, k, d);
                if ((rc = mesh_leaf(&b, &b.nodes[id], d, err)) != MER_OK)
                    goto done;
            }
        }
    }

    if (b.opt.markers) {
        size_t count = mer_scene_marker_count(scene);
        if (count > 0) {
            b.mesh->points = malloc(count * 3 * sizeof(float));
            if (b.mesh->points == NULL) {
                rc = mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for markers");
                goto done;
            }
            b.mesh->point_count = (uint32_t)mer_scene_markers(scene, b.mesh->points, count);
        }
    }

    // The counts were computed before meshing; meshing must have filled exactly them.
    if (b.bark.v != b.mesh->bark.vertex_count || b.bark.i != b.mesh->bark.index_count ||
        b.leaves.v != b.mesh->leaves.vertex_count || b.leaves.i != b.mesh->leaves.index_count ||
        b.bark.line_i != b.mesh->bark.line_index_count) {
        rc = mer_error_set(err, MER_ERR_INTERNAL, NULL,
                           "meshing wrote %u of %u bark vertices, %u of %u bark indices, %u of %u "
                           "twig line indices, %u of %u leaf vertices",
                           b.bark.v, b.mesh->bark.vertex_count, b.bark.i, b.mesh->bark.index_count,
                           b.bark.line_i, b.mesh->bark.line_index_count, b.leaves.v,
                           b.mesh->leaves.vertex_count);
        goto done;
    }

    *out = b.mesh;
    b.mesh = NULL; // handed over: the cleanup below must not free it

done:
    free(b.nodes);
    free(b.axes);
    free(b.chain);
    free(b.radii);
    mer_mesh_free(b.mesh);
    return rc;
}

static void free_part(mer_mesh_part *part)
{
    free(part->chunks);
    free(part->positions);
    free(part->normals);
    free(part->uvs);
    free(part->colors);
    free(part->node_ids);
    free(part->indices);
    free(part->line_indices);
}

void mer_mesh_free(mer_mesh *mesh)
{
    if (mesh == NULL)
        return;
    free_part(&mesh->bark);
    free_part(&mesh->leaves);
    free(mesh->points);
    free(mesh);
}
