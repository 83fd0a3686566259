/* meristem — the axes of a tree: each a trunk, or a branch grown from a lateral
 * bud, followed along its main continuations (meristem/mesh.h, Bark), with the
 * sides its tube gets (Level of detail), and one axis's chain of nodes and ring
 * radii for tube.c. What an axis costs is in mesh_private.h. */
#include "config.h"

#include <math.h>
#include <stdlib.h>

#include "core/alloc.h"
#include "mesh_private.h"

static const uint32_t max_sides_by_detail[MER_MESH_DETAIL_MAX + 1] = {0, 4, 6, 8, 12, MERP_MAX_SIDES};

static bool alive(const merp_builder *b, uint32_t id)
{
    return id != MER_NO_NODE && id < b->node_count && b->nodes[id].alive;
}

static uint32_t sides_for(const merp_builder *b, float diameter)
{
    assert(b->opt.detail >= 1 && b->opt.detail <= MER_MESH_DETAIL_MAX);
    uint32_t max = max_sides_by_detail[b->opt.detail];
    float f = b->max_diameter > 0.0f ? merp_clampf(diameter / b->max_diameter, 0.0f, 1.0f) : 1.0f;
    return 3u + (uint32_t)lrintf((float)(max - 3u) * f);
}

static mer_result grow_axes(merp_builder *b, uint32_t *cap, mer_error *err)
{
    *cap = *cap ? 2 * *cap : 256;
    merp_axis *grown = merp_realloc(b->axes, *cap * sizeof *grown);
    if (grown == NULL)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for axes");
    b->axes = grown;
    return MER_OK;
}

/* An axis is a living node whose parent is absent (a trunk) or whose parent
 * continues elsewhere (a branch). Ascending ids keep the output stable. */
mer_result merp_mesh_collect_axes(merp_builder *b, mer_error *err)
{
    uint32_t cap = 0;
    for (uint32_t id = 0; id < b->node_count; id++) {
        const mer_node *n = &b->nodes[id];
        if (!n->alive)
            continue;
        bool trunk = n->parent == MER_NO_NODE;
        if (!trunk && (!alive(b, n->parent) || b->nodes[n->parent].main_child == id))
            continue;
        mer_result rc = b->axis_count == cap ? grow_axes(b, &cap, err) : MER_OK;
        if (rc != MER_OK)
            return rc;
        merp_axis *a = &b->axes[b->axis_count++];
        a->first = id;
        a->count = 1;
        a->base_cap = trunk;
        a->extra_rings = 0;
        a->lost_bands = 0;
        a->ends_in = 0;
        uint32_t last = id;
        float length = n->length;
        while (alive(b, b->nodes[last].main_child)) {
            last = b->nodes[last].main_child;
            length += b->nodes[last].length;
            a->count++;
        }
        // A branch of no length at all (a guiding-vector shoot of hops of
        // none) is no tube: its rings would lie one on the other under a
        // disk, bands of no area. Its own branches are axes of their own.
        if (!trunk && !(length > 0.0f)) {
            b->axis_count--;
            continue;
        }
        // A tip still has its terminal bud (dormant, flowered or aborted); a
        // pruned or shed continuation leaves neither child nor bud: a cut.
        const mer_node *end = &b->nodes[last];
        a->end = end->main_child == MER_NO_NODE && end->terminal_bud != MER_BUD_NONE
                     ? MERP_END_TIP
                     : MERP_END_CUT;
        a->sides = sides_for(b, n->diameter);
    }
    return MER_OK;
}

mer_result merp_mesh_chain(merp_builder *b, const merp_axis *a, mer_error *err)
{
    assert(a->count >= 1);
    if (a->count > b->chain_cap) {
        uint32_t cap = a->count > 2 * b->chain_cap ? a->count : 2 * b->chain_cap;
        uint32_t *grown = merp_realloc(b->chain, cap * sizeof *grown);
        float *radii = merp_realloc(b->radii, (cap + 1) * sizeof *radii);
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
        b->radii[i] = 0.5f * b->nodes[b->chain[i < a->count ? i : a->count - 1]].diameter;
    return MER_OK;
}
