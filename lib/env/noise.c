/* meristem — Perlin noise perturbation of directions, lengths and diameters
 * (noise.h). */
#include "config.h"

#include <assert.h>
#include <math.h>
#include <string.h>

#include "core/vec.h"
#include "env/noise.h"

/* Offsets of the independent channels, far apart in noise cells. */
static const float offsets[5][3] = {
    {0.0f, 0.0f, 0.0f},
    {31.416f, 47.853f, 12.934f},
    {-17.319f, 5.127f, 63.701f},
    {83.117f, -29.561f, -41.243f},
    {-59.773f, 71.389f, 23.557f},
};

static int on(const merp_perlin *n, const mer_params *p, uint32_t target)
{
    return n != NULL && p->noise_amplitude > 0.0f && (p->noise_targets & target) != 0;
}

static float channel(const merp_perlin *n, const mer_params *p, const float base[3], int c)
{
    float q[3];
    for (int a = 0; a < 3; a++)
        q[a] = base[a] * p->noise_scale + offsets[c][a];
    return merp_perlin_fbm(n, q, p->noise_octaves);
}

void merp_noise_internode(const merp_perlin *n, const mer_params *p, const float base[3],
                          float d[3], float *l)
{
    assert(p != NULL && base != NULL && d != NULL && l != NULL);
    float A = p->noise_amplitude;
    if (on(n, p, MER_NOISE_DIRECTIONS)) {
        float e[3];
        for (int a = 0; a < 3; a++)
            e[a] = d[a] + A * channel(n, p, base, a);
        if (v3_normalize(e))
            memcpy(d, e, sizeof e);
    }
    if (on(n, p, MER_NOISE_LENGTHS))
        *l *= fmaxf(0.1f, 1.0f + A * channel(n, p, base, 3));
}

float merp_noise_diameter(const merp_perlin *n, const mer_params *p, const float base[3])
{
    assert(p != NULL && base != NULL);
    if (!on(n, p, MER_NOISE_RADII))
        return 1.0f;
    return fmaxf(0.1f, 1.0f + p->noise_amplitude * channel(n, p, base, 4));
}
