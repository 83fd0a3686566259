/* meristem — debug colours of bark and leaves (meristem/mesh.h, Colours). */
#include "config.h"

#include "mesh_private.h"

static void color_of(const merp_builder *b, const mer_node *n, float out[4])
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
        float t = b->max_q > 0.0f ? merp_clampf(n->q / b->max_q, 0.0f, 1.0f) : 0.0f;
        out[0] = 0.05f + 0.95f * t;
        out[1] = 0.05f + 0.85f * t;
        out[2] = 0.45f - 0.35f * t;
        return;
    }
    case MER_COLOR_AGE: {
        float t = b->step > 0 ? merp_clampf((float)(b->step - n->born) / (float)b->step, 0.0f, 1.0f)
                              : 0.0f;
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

void merp_mesh_color_run(const merp_builder *b, mer_mesh_part *part, uint32_t first,
                         uint32_t count, const mer_node *n)
{
    assert(first + count <= part->vertex_count);
    float rgba[4];
    color_of(b, n, rgba);
    for (uint32_t k = first; k < first + count; k++)
        memcpy(part->colors + 4 * k, rgba, sizeof rgba);
}
