/* meristem — symmetric copies of brush dabs (edit.h, mer_symmetry). */
#include "config.h"

#include <assert.h>
#include <string.h>

#include "core/vec.h"
#include "symmetry.h"

mer_result merp_symmetry_resolve(const mer_symmetry *sym, merp_symmetry *out, mer_error *err)
{
    assert(out != NULL);
    memset(out, 0, sizeof *out);
    out->sym = sym;
    out->rot = out->tiles0 = out->tiles1 = 1;
    out->n[0] = 1.0f;
    if (sym == NULL)
        return MER_OK;
    out->rot = sym->rotational > 1 ? sym->rotational : 1;
    if (out->rot > MERP_SYM_ROTATIONAL_MAX)
        return mer_error_set(err, MER_ERR_RANGE, "rotational",
                             "rotational must be from 0 to %u, got %u",
                             MERP_SYM_ROTATIONAL_MAX, (unsigned)out->rot);
    out->tiles0 = sym->tiles[0] > 1 ? sym->tiles[0] : 1;
    out->tiles1 = sym->tiles[1] > 1 ? sym->tiles[1] : 1;
    if ((uint64_t)out->tiles0 * out->tiles1 > MERP_SYM_TILES_MAX)
        return mer_error_set(err, MER_ERR_RANGE, "tiles", "tiles[0]·tiles[1] must be at most %u",
                             MERP_SYM_TILES_MAX);
    out->mirror = sym->mirror != 0;
    if (out->mirror) {
        memcpy(out->n, sym->mirror_normal, sizeof out->n);
        if (!v3_normalize(out->n))
            return mer_error_set(err, MER_ERR_RANGE, "mirror_normal",
                                 "mirror_normal must not be the zero vector");
    }
    return MER_OK;
}

size_t merp_symmetry_copies(const merp_symmetry *y)
{
    return (size_t)y->rot * (y->mirror ? 2u : 1u) * y->tiles0 * y->tiles1;
}

static void mirror_point(const float *p, const float *o, const float *n, float *out)
{
    float d = (p[0] - o[0]) * n[0] + (p[1] - o[1]) * n[1] + (p[2] - o[2]) * n[2];
    for (int a = 0; a < 3; a++)
        out[a] = p[a] - 2.0f * d * n[a];
}

/* The r-th of the rotational copies of p0. */
static void rotated(const merp_symmetry *y, const float p0[3], uint32_t r, float out[3])
{
    const mer_symmetry *sym = y->sym;
    if (r == 0 || sym == NULL) {
        memcpy(out, p0, 3 * sizeof *out);
        return;
    }
    const float up[3] = {0.0f, 1.0f, 0.0f};
    float rel[3] = {p0[0] - sym->center[0], p0[1] - sym->center[1], p0[2] - sym->center[2]};
    v3_rotate(rel, up, MERP_TWO_PI * (float)r / (float)y->rot, rel);
    for (int a = 0; a < 3; a++)
        out[a] = sym->center[a] + rel[a];
}

void merp_symmetry_apply(const merp_symmetry *y, const float p[3], float *out)
{
    assert(y != NULL && p != NULL && out != NULL);
    const mer_symmetry *sym = y->sym;
    size_t w = 0;
    for (uint32_t r = 0; r < y->rot; r++) {
        float pr3[3];
        rotated(y, p, r, pr3);
        for (uint32_t m = 0; m <= y->mirror; m++) {
            float pm[3];
            if (m == 0)
                memcpy(pm, pr3, sizeof pm);
            else
                mirror_point(pr3, sym->mirror_point, y->n, pm);
            for (uint32_t t0 = 0; t0 < y->tiles0; t0++)
                for (uint32_t t1 = 0; t1 < y->tiles1; t1++) {
                    float *o = out + 3 * w++;
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
