/* meristem — the inverse model's presets (presets_inverse.c): each a definition
 * text (models/inverse/text.c) naming one of its species. */
#ifndef MERISTEM_PRESETS_INVERSE_H
#define MERISTEM_PRESETS_INVERSE_H

#include <stddef.h>

#include <meristem/params.h>

typedef struct merp_inv_preset {
    const char *name, *description, *definition;
} merp_inv_preset;

size_t merp_inv_preset_count(void);
/* The i-th preset, NULL past the last. */
const merp_inv_preset *merp_inv_preset_at(size_t i);
/* The preset named `name`, NULL when none is. */
const merp_inv_preset *merp_inv_preset_find(const char *name);
/* Sets the model (defaults otherwise): the tree is the definition's. */
void merp_inv_preset_apply(const merp_inv_preset *ps, mer_params *p);

#endif
