/* meristem — Perlin noise that perturbs growth, for every model (the survey's
 * §VII-A: "the height, width, and bending of tree branches"). Not installed.
 *
 * A model calls merp_noise_internode where it makes a node's direction and
 * length, before the node exists (so markers, shadows and obstacles see the
 * perturbed node); radii are perturbed where the public node view is read
 * (mer_scene_node), so meshes and the skeleton's readers agree. Each quantity
 * reads the noise field (core/perlin.h, the scene's permutation) at the node's
 * base times noise_scale, through its own fixed offset so that the quantities
 * are not correlated:
 *   direction  d + A·(N(q), N(q + o₁), N(q + o₂)), normalized
 *   length     l · max(0.1, 1 + A·N(q + o₃))
 *   diameter   d · max(0.1, 1 + A·N(q + o₄))
 * with A = noise_amplitude, N the fBm of noise_octaves octaves, and the bits of
 * noise_targets choosing the quantities. A = 0 (the default) changes nothing:
 * not a bit of any scene, with no noise evaluated. */
#ifndef MERISTEM_ENV_NOISE_H
#define MERISTEM_ENV_NOISE_H

#include <meristem/params.h>

#include "core/perlin.h"

/* Perturbs the unit direction `d` and the length `*l` of a new internode based
 * at `base`, as the header says. `n` may be NULL (no noise). O(octaves). */
void merp_noise_internode(const merp_perlin *n, const mer_params *p, const float base[3],
                          float d[3], float *l);

/* The factor of the diameter of an internode based at `base`: 1 when off. */
float merp_noise_diameter(const merp_perlin *n, const mer_params *p, const float base[3]);

#endif
