/* meristem — named parameter sets after the figures of Palubicki et al. 2009, and
 * L-system presets after Prusinkiewicz & Lindenmayer's ABOP (model "lsystem",
 * with a definition text: mer_preset_definition), and the inverse model's trees
 * after Galbraith et al. 2004 (model "inverse", also with a definition text).
 *
 * Each preset is the defaults (params.h) with a few fields changed; the paper
 * gives λ, α, w_max, w_min and κ for Figs. 7 and 9, and only qualitative settings
 * for the others, so those values are ours (documented per preset in presets.c and
 * in mer_preset_description). Every preset grows a non-trivial tree from its
 * seedling in a few tens of steps (tests/unit/test_presets.c).
 */
#ifndef MERISTEM_PRESETS_H
#define MERISTEM_PRESETS_H

#include <stddef.h>

#include <meristem/params.h>
#include <meristem/result.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The number of presets, and the i-th one's name ("fig7-bh-0.46", ...) and a one-line
 * description; static strings, NULL when i is out of range. */
size_t mer_preset_count(void);
const char *mer_preset_name(size_t i);
const char *mer_preset_description(size_t i);

/* Fills `*out` (not NULL) with preset `name`. MER_ERR_INVALID (field "preset") for
 * an unknown name; the message lists no names, mer_preset_name does. O(presets). */
mer_result mer_preset_params(const char *name, mer_params *out, mer_error *err);

/* The definition text of preset `name` (a static string) for a model defined by
 * a text: the cpfg source of an L-system preset ("abop-1.24a", ...), the
 * definition of an inverse-model preset ("populus-deltoides": "species: ..."), to give to
 * mer_scene_set_definition after mer_scene_new with mer_preset_params. NULL for
 * the presets of P09 and unknown names. O(presets). */
const char *mer_preset_definition(const char *name);

#ifdef __cplusplus
}
#endif

#endif
