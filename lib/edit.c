/* meristem — prune, bend, brush, growth constraint (P09 §5). */
#include "config.h"

#include <stdlib.h>
#include <string.h>

#include <meristem/edit.h>

#include "scene_private.h"
#include "vec_private.h"

static mer_result live_node(const mer_scene *s, uint32_t node, mer_error *err)
{
    if (node >= s->n)
        return mer_error_set(err, MER_ERR_NOT_FOUND, "node",
                             "node %u was never part of this tree (ids are 0 to %u)",
                             (unsigned)node, s->n ? (unsigned)(s->n - 1) : 0u);
    if (!s->alive[node])
        return mer_error_set(err, MER_ERR_GONE, "node", "node %u was pruned or shed",
                             (unsigned)node);
    return MER_OK;
}

mer_result mer_scene_prune(mer_scene *s, uint32_t node, mer_error *err)
{
    mer_result rc = live_node(s, node, err);
    if (rc != MER_OK)
        return rc;
    return merp_kill(s, node, err);
}

static void cast_subtree(mer_scene *s, size_t cnt, int sign)
{
    if (s->shadow == NULL)
        return;
    for (size_t t = 0; t < cnt; t++) {
        uint32_t i = s->stack[t];
        float e[3];
        merp_node_end(s, i, e);
        for (int k = 0; k < 3; k++)
            if (s->bud[3 * i + k] == MER_BUD_DORMANT)
                mer_shadow_cast_at(s->shadow, e, sign);
    }
}

mer_result mer_scene_bend(mer_scene *s, uint32_t node, const float axis[3], float angle,
                          mer_error *err)
{
    mer_result rc = live_node(s, node, err);
    if (rc != MER_OK)
        return rc;
    float ax[3] = {axis[0], axis[1], axis[2]};
    if (!v3_normalize(ax))
        return mer_error_set(err, MER_ERR_RANGE, "axis", "axis must not be the zero vector");
    if (!(angle == angle))
        return mer_error_set(err, MER_ERR_RANGE, "angle", "angle must be a number");
    size_t cnt;
    rc = merp_subtree(s, node, &cnt, err);
    if (rc != MER_OK)
        return rc;
    float o[3];
    memcpy(o, s->pos + 3 * node, sizeof o);
    float rad = angle * MER_DEG2RAD;
    cast_subtree(s, cnt, -1);
    for (size_t t = 0; t < cnt; t++) {
        uint32_t i = s->stack[t];
        float rel[3] = {s->pos[3 * i] - o[0], s->pos[3 * i + 1] - o[1], s->pos[3 * i + 2] - o[2]};
        v3_rotate(rel, ax, rad, rel);
        for (int a = 0; a < 3; a++)
            s->pos[3 * i + a] = o[a] + rel[a];
        v3_rotate(s->dir + 3 * i, ax, rad, s->dir + 3 * i);
        v3_normalize(s->dir + 3 * i);
        v3_rotate(s->side + 3 * i, ax, rad, s->side + 3 * i);
        v3_normalize(s->side + 3 * i);
    }
    cast_subtree(s, cnt, 1);
    s->env_epoch++; /* moved buds see other markers */
    return MER_OK;
}

static void mirror_point(const float *p, const float *o, const float *n, float *out)
{
    float d = (p[0] - o[0]) * n[0] + (p[1] - o[1]) * n[1] + (p[2] - o[2]) * n[2];
    for (int a = 0; a < 3; a++)
        out[a] = p[a] - 2.0f * d * n[a];
}

mer_result mer_scene_brush(mer_scene *s, const mer_brush *brush, const mer_symmetry *sym,
                           size_t *added, mer_error *err)
{
    if (added != NULL)
        *added = 0;
    if (!(brush->radius > 0.0f && brush->radius <= 1000.0f))
        return mer_error_set(err, MER_ERR_RANGE, "radius", "radius must be in (0, 1000], got %g",
                             (double)brush->radius);
    if (!(brush->pressure > 0.0f && brush->pressure <= 1.0f))
        return mer_error_set(err, MER_ERR_RANGE, "pressure", "pressure must be in (0, 1], got %g",
                             (double)brush->pressure);
    uint32_t max_count = brush->max_count ? brush->max_count : 50;
    if (max_count > 100000)
        return mer_error_set(err, MER_ERR_RANGE, "max_count",
                             "max_count must be from 1 to 100000, got %u", (unsigned)max_count);
    uint32_t rot = 1, tiles0 = 1, tiles1 = 1, mirror = 0;
    float n[3] = {1.0f, 0.0f, 0.0f};
    if (sym != NULL) {
        rot = sym->rotational > 1 ? sym->rotational : 1;
        if (rot > 64)
            return mer_error_set(err, MER_ERR_RANGE, "rotational",
                                 "rotational must be from 0 to 64, got %u", (unsigned)rot);
        tiles0 = sym->tiles[0] > 1 ? sym->tiles[0] : 1;
        tiles1 = sym->tiles[1] > 1 ? sym->tiles[1] : 1;
        if ((uint64_t)tiles0 * tiles1 > 1024)
            return mer_error_set(err, MER_ERR_RANGE, "tiles",
                                 "tiles[0]·tiles[1] must be at most 1024");
        mirror = sym->mirror != 0;
        if (mirror) {
            memcpy(n, sym->mirror_normal, sizeof n);
            if (!v3_normalize(n))
                return mer_error_set(err, MER_ERR_RANGE, "mirror_normal",
                                     "mirror_normal must not be the zero vector");
        }
    }
    float pr = brush->pressure;
    uint32_t count = 1 + (uint32_t)lroundf((float)(max_count - 1) * pr * pr);
    float spread = brush->radius * (0.1f + 0.9f * pr);
    size_t copies = (size_t)rot * (mirror ? 2u : 1u) * tiles0 * tiles1;
    size_t total = (size_t)count * copies;
    if (total > MER_BRUSH_MARKERS_MAX)
        return mer_error_set(err, MER_ERR_LIMIT, "max_count",
                             "a dab would make %zu markers with its copies, more than %u",
                             total, (unsigned)MER_BRUSH_MARKERS_MAX);
    float *xyz = malloc(total * 3 * sizeof *xyz);
    if (xyz == NULL)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for brush markers");
    size_t w = 0;
    const float up[3] = {0.0f, 1.0f, 0.0f};
    for (uint32_t c = 0; c < count; c++) {
        float u[3];
        do {
            for (int a = 0; a < 3; a++)
                u[a] = mer_rng_range(&s->rng, -1.0f, 1.0f);
        } while (v3_dot(u, u) > 1.0f);
        float p0[3];
        for (int a = 0; a < 3; a++)
            p0[a] = brush->center[a] + spread * u[a];
        for (uint32_t r = 0; r < rot; r++) {
            float pr3[3];
            if (r == 0 || sym == NULL) {
                memcpy(pr3, p0, sizeof pr3);
            } else {
                float rel[3] = {p0[0] - sym->center[0], p0[1] - sym->center[1], p0[2] - sym->center[2]};
                v3_rotate(rel, up, 6.2831853071795865f * (float)r / (float)rot, rel);
                for (int a = 0; a < 3; a++)
                    pr3[a] = sym->center[a] + rel[a];
            }
            for (uint32_t m = 0; m <= mirror; m++) {
                float pm[3];
                if (m == 0)
                    memcpy(pm, pr3, sizeof pm);
                else
                    mirror_point(pr3, sym->mirror_point, n, pm);
                for (uint32_t t0 = 0; t0 < tiles0; t0++)
                    for (uint32_t t1 = 0; t1 < tiles1; t1++) {
                        float *o = xyz + 3 * w++;
                        for (int a = 0; a < 3; a++) {
                            o[a] = pm[a];
                            if (sym != NULL)
                                o[a] += (float)t0 * sym->tile_step[0][a] +
                                        (float)t1 * sym->tile_step[1][a];
                        }
                    }
            }
        }
    }
    size_t before = mer_scene_marker_count(s);
    mer_result rc = mer_scene_add_markers(s, xyz, w, err);
    free(xyz);
    if (rc == MER_OK && added != NULL)
        *added = mer_scene_marker_count(s) - before;
    return rc;
}

mer_result mer_scene_constrain(mer_scene *s, uint32_t node, uint32_t slot, mer_error *err)
{
    mer_result rc = live_node(s, node, err);
    if (rc != MER_OK)
        return rc;
    if (slot > s->p.buds_per_node)
        return mer_error_set(err, MER_ERR_RANGE, "slot", "slot must be from 0 to %u, got %u",
                             (unsigned)s->p.buds_per_node, (unsigned)slot);
    uint8_t st = s->bud[3 * node + slot];
    if (st != MER_BUD_DORMANT && s->child[3 * node + slot] == MER_NO_NODE)
        return mer_error_set(err, MER_ERR_RANGE, "slot",
                             "bud %u of node %u is neither dormant nor grown out",
                             (unsigned)slot, (unsigned)node);
    s->con_node = node;
    s->con_slot = slot;
    return MER_OK;
}

void mer_scene_unconstrain(mer_scene *s) { s->con_node = MER_NO_NODE; }

int mer_scene_constraint(const mer_scene *s, uint32_t *node, uint32_t *slot)
{
    if (s->con_node == MER_NO_NODE)
        return 0;
    if (node != NULL)
        *node = s->con_node;
    if (slot != NULL)
        *slot = s->con_slot;
    return 1;
}
