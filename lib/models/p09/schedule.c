/* meristem — P09's developmental schedule (P09 Fig. 10, 11, 13, 20): apical
 * control per branch order, and λ and η over time as piecewise-linear keyframes. */
#include "config.h"

#include <assert.h>

#include <meristem/params.h>

float mer_params_lambda_at(const mer_params *p, uint32_t step)
{
    assert(p != NULL);
    return mer_keyframes_eval(p->schedule.lambda_keys, p->schedule.lambda_key_count,
                              (float)step, p->lambda);
}

float mer_params_eta_at(const mer_params *p, uint32_t step, uint32_t order)
{
    assert(p != NULL);
    uint32_t k = order < MER_ORDERS_MAX ? order : MER_ORDERS_MAX - 1;
    return mer_keyframes_eval(p->schedule.eta_keys, p->schedule.eta_key_count, (float)step,
                              p->eta) * p->schedule.eta_order_scale[k];
}

int mer_params_apical_at(const mer_params *p, uint32_t step, uint32_t order)
{
    assert(p != NULL);
    uint32_t k = order < MER_ORDERS_MAX ? order : MER_ORDERS_MAX - 1;
    return step < p->schedule.apical_off[k];
}
