/* meristem — reading a scene: nodes and the summary (scene.h). */
#include "config.h"

#include <assert.h>
#include <string.h>

#include "env/noise.h"
#include "scene_private.h"

uint32_t mer_scene_node_bound(const mer_scene *s) { return s->sk.n; }

mer_result mer_scene_node(const mer_scene *s, uint32_t id, mer_node *out, mer_error *err)
{
    assert(s != NULL && out != NULL);
    const merp_skeleton *sk = &s->sk;
    if (id >= sk->n)
        return mer_error_set(err, MER_ERR_RANGE, "node", "node must be from 0 to %u, got %u",
                             sk->n ? (unsigned)(sk->n - 1) : 0u, (unsigned)id);
    memset(out, 0, sizeof *out);
    out->id = id;
    out->parent = sk->parent[id];
    out->plant = sk->plant[id];
    out->order = sk->order[id];
    out->alive = sk->alive[id];
    out->born = sk->born[id];
    out->main_child = sk->child[3 * id];
    out->lateral_child[0] = sk->child[3 * id + 1];
    out->lateral_child[1] = sk->child[3 * id + 2];
    out->terminal_bud = sk->bud[3 * id];
    out->lateral_bud[0] = sk->bud[3 * id + 1];
    out->lateral_bud[1] = sk->bud[3 * id + 2];
    memcpy(out->base, sk->pos + 3 * id, sizeof out->base);
    memcpy(out->dir, sk->dir + 3 * id, sizeof out->dir);
    merp_skel_bud_dir(sk, id, 1, out->bud_dir[0]);
    merp_skel_bud_dir(sk, id, 2, out->bud_dir[1]);
    out->length = sk->len[id];
    out->diameter = merp_pipe_diameter(sk, id) * merp_noise_diameter(&s->noise, &s->p, out->base);
    out->q = sk->q[id];
    out->leaf = s->ops->leaf != NULL ? s->ops->leaf(s->model, sk, id) : 0.0f;
    return MER_OK;
}

/* The lowest base of the plants. */
static float base_height(const merp_skeleton *sk)
{
    float base_y = 0.0f;
    int any_root = 0;
    for (uint32_t r = 0; r < sk->nplants; r++) {
        float y = sk->pos[3 * sk->roots[r] + 1];
        if (!any_root || y < base_y)
            base_y = y;
        any_root = 1;
    }
    return base_y;
}

void mer_scene_summary(const mer_scene *s, mer_summary *out)
{
    assert(s != NULL && out != NULL);
    const merp_skeleton *sk = &s->sk;
    memset(out, 0, sizeof *out);
    out->step = s->step;
    out->plants = sk->nplants;
    out->node_bound = sk->n;
    out->markers = (uint32_t)mer_markers_count(s->env.markers);
    float lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    float base_y = base_height(sk), crown = 0.0f;
    int any = 0, any_branch = 0;
    for (uint32_t i = 0; i < sk->n; i++) {
        if (!sk->alive[i])
            continue;
        out->internodes++;
        for (int k = 0; k < 3; k++) {
            out->buds += sk->bud[3 * i + k] == MER_BUD_DORMANT;
            out->flowers += sk->bud[3 * i + k] == MER_BUD_FLOWER;
        }
        float e[3];
        merp_skel_node_end(sk, i, e);
        const float *b = sk->pos + 3 * i;
        for (int a = 0; a < 3; a++) {
            float mn = b[a] < e[a] ? b[a] : e[a], mx = b[a] < e[a] ? e[a] : b[a];
            if (!any || mn < lo[a])
                lo[a] = mn;
            if (!any || mx > hi[a])
                hi[a] = mx;
        }
        any = 1;
        if (sk->slot[i] != 0 && (!any_branch || b[1] < crown)) {
            crown = b[1];
            any_branch = 1;
        }
    }
    memcpy(out->bbox_min, lo, sizeof lo);
    memcpy(out->bbox_max, hi, sizeof hi);
    if (any) {
        out->height = hi[1] - base_y;
        float wx = hi[0] - lo[0], wz = hi[2] - lo[2];
        out->crown_width = wx > wz ? wx : wz;
        out->crown_base = any_branch ? crown - base_y : out->height;
        out->crown_depth = out->height - out->crown_base;
    }
}
