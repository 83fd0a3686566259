/* meristem — the inverse model's presets (G04 §4–5): the Populus deltoides of
 * G04 §5 over 27 years, and two trees of our own that show the model's range.
 * A step is one year; each grows to its y_max. */
#include "config.h"

#include <string.h>

#include "presets_inverse.h"

static const merp_inv_preset presets[] = {
    {"populus-deltoides",
     "G04 §5: Populus deltoides (eastern cottonwood) over 27 years, a broom-stick sapling "
     "that turns into a rounded crown; one step is one year",
     "species: populus-deltoides\n"},
    {"inverse-conifer",
     "An excurrent conifer by the inverse model (G04 §4): a spire of level branches in tiers; "
     "one step is one year",
     "species: conifer\n"},
    {"inverse-weeping",
     "A weeping form by the inverse model (G04 §4): long branches that arch over and hang; "
     "one step is one year",
     "species: weeping\n"},
};

#define NPRESETS (sizeof presets / sizeof presets[0])

size_t merp_inv_preset_count(void) { return NPRESETS; }

const merp_inv_preset *merp_inv_preset_at(size_t i) { return i < NPRESETS ? &presets[i] : NULL; }

const merp_inv_preset *merp_inv_preset_find(const char *name)
{
    for (size_t i = 0; name != NULL && i < NPRESETS; i++)
        if (strcmp(presets[i].name, name) == 0)
            return &presets[i];
    return NULL;
}

void merp_inv_preset_apply(const merp_inv_preset *ps, mer_params *p)
{
    (void)ps;
    p->model = MER_MODEL_INVERSE;
}
