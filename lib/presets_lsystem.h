/* meristem — the L-system presets (presets_lsystem.c): each a cpfg text and the
 * turtle parameters its figure gives. presets.c lists them after P09's. Not
 * installed. */
#ifndef MERISTEM_PRESETS_LSYSTEM_H
#define MERISTEM_PRESETS_LSYSTEM_H

#include <stddef.h>

#include <meristem/params.h>

typedef struct merp_ls_preset {
    const char *name, *description, *source;
    float delta, step, width_scale, elasticity; /* ls_delta, ls_step, ls_width_scale, ls_elasticity */
} merp_ls_preset;

size_t merp_ls_preset_count(void);
/* The i-th preset, NULL past the last. */
const merp_ls_preset *merp_ls_preset_at(size_t i);
/* Sets the model and the turtle parameters of `ps` in `p` (defaults otherwise). */
void merp_ls_preset_apply(const merp_ls_preset *ps, mer_params *p);

#endif
