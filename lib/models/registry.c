/* meristem — the growth models a scene can run, by mer_model_kind. */
#include "config.h"

#include <string.h>

#include "models/model.h"

static const merp_model_ops *const models[] = {
    [MER_MODEL_P09] = &merp_p09_ops,
    [MER_MODEL_RUNIONS] = &merp_runions_ops,
    [MER_MODEL_LSYSTEM] = &merp_lsystem_ops,
    [MER_MODEL_INVERSE] = &merp_inverse_ops,
    [MER_MODEL_GUIDING] = &merp_guiding_ops,
    [MER_MODEL_FOREST] = &merp_forest_ops,
};

#define NMODELS (sizeof models / sizeof models[0])

const merp_model_ops *merp_model_ops_of(uint32_t kind)
{
    return kind < NMODELS ? models[kind] : NULL;
}

const char *mer_model_name(uint32_t model)
{
    const merp_model_ops *ops = merp_model_ops_of(model);
    return ops != NULL ? ops->name : NULL;
}

mer_result mer_model_parse(const char *name, uint32_t *model, mer_error *err)
{
    for (uint32_t k = 0; name != NULL && k < NMODELS; k++)
        if (strcmp(models[k]->name, name) == 0) {
            if (model != NULL)
                *model = k;
            return MER_OK;
        }
    char list[128] = "";
    for (uint32_t k = 0; k < NMODELS; k++) {
        if (k > 0)
            strncat(list, ", ", sizeof list - strlen(list) - 1);
        strncat(list, models[k]->name, sizeof list - strlen(list) - 1);
    }
    return mer_error_set(err, MER_ERR_INVALID, "model", "unknown model '%s'; use one of %s",
                         name != NULL ? name : "(null)", list);
}
