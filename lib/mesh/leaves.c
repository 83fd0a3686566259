/* meristem — leaf cards: one per lateral bud of the youngest internodes,
 * pointing the way the bud points, or one per node sized by its model
 * (mer_node.leaf) (meristem/mesh.h, Leaves). */
#include "config.h"

#include "mesh_private.h"
#include "core/vec.h"

static bool has_leaf_at(const merp_builder *b, const mer_node *n)
{
    if (n->leaf != 0.0f)
        return n->alive && n->leaf > 0.0f;
    return n->alive && b->newest - n->born < b->opt.leaf_age;
}

/* A node sized by its model bears one leaf (G04 §4.3: "each metamer will
 * produce a lateral leaf"); otherwise one per lateral bud. */
static uint32_t leaves_at(const merp_builder *b, const mer_node *n)
{
    if (n->leaf > 0.0f)
        return 1u;
    return mer_scene_params(b->scene)->buds_per_node >= 2 ? 2u : 1u;
}

uint64_t merp_mesh_leaf_count(const merp_builder *b)
{
    uint64_t count = 0;
    if (b->opt.leaves)
        for (uint32_t id = 0; id < b->node_count; id++)
            count += has_leaf_at(b, &b->nodes[id]) ? leaves_at(b, &b->nodes[id]) : 0;
    return count;
}

/* A rhombus card at the end of `n` along `dir_in` (the bud's direction), facing
 * up as far as that direction allows. */
static mer_result mesh_leaf(merp_builder *b, const mer_node *n, const float dir_in[3], mer_error *err)
{
    assert(n->alive);
    float d[3] = {dir_in[0], dir_in[1], dir_in[2]};
    if (!v3_normalize(d))
        return MER_OK;
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
    merp_tip_of(n, base);
    float len = n->leaf > 0.0f ? n->leaf : b->opt.leaf_size, half_w = 0.25f * len;
    for (int i = 0; i < 3; i++) {
        tip[i] = base[i] + d[i] * len;
        left[i] = base[i] + d[i] * 0.5f * len - w[i] * half_w;
        right[i] = base[i] + d[i] * 0.5f * len + w[i] * half_w;
    }
    merp_cursor *c = &b->leaves;
    mer_result rc = merp_mesh_begin_group(c, 4, err);
    if (rc != MER_OK)
        return rc;
    uint32_t v0 = merp_put_vertex(c, base, face, 0.5f, 0.0f, n);
    merp_put_vertex(c, right, face, 1.0f, 0.5f, n);
    merp_put_vertex(c, tip, face, 0.5f, 1.0f, n);
    merp_put_vertex(c, left, face, 0.0f, 0.5f, n);
    merp_mesh_color(b, c->part, v0, 4, n);
    // (d, w, face) is right-handed, so base → right → tip turns about +face.
    merp_put_triangle(c, v0, v0 + 1, v0 + 2);
    merp_put_triangle(c, v0, v0 + 2, v0 + 3);
    return MER_OK;
}

mer_result merp_mesh_leaves(merp_builder *b, mer_error *err)
{
    for (uint32_t id = 0; id < b->node_count; id++) {
        const mer_node *n = &b->nodes[id];
        if (!has_leaf_at(b, n))
            continue;
        // bud_dir[k - 1] is lateral bud k's direction (phyllotaxis, P09 §4.3).
        for (uint32_t k = 1; k <= leaves_at(b, n); k++) {
            mer_result rc = mesh_leaf(b, n, n->bud_dir[k - 1], err);
            if (rc != MER_OK)
                return rc;
        }
    }
    return MER_OK;
}
