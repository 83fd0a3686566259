/* meristem — the checks across P09's parameters that the table's ranges cannot
 * express: the priority weights' order, the λ and η keyframes (P09 §4.2, Fig. 11,
 * 13). Its fields are the rows tagged P in params.c. */
#include "config.h"

#include <assert.h>

#include "models/p09/p09.h"

static mer_result check_keys(const mer_keyframe *k, uint32_t n, const char *name,
                             double lo, double hi, mer_error *err)
{
    if (n > MER_KEYS_MAX)
        return mer_error_set(err, MER_ERR_RANGE, name, "%s count must be from 0 to %d, got %u",
                             name, MER_KEYS_MAX, (unsigned)n);
    for (uint32_t i = 0; i < n; i++) {
        if (!(k[i].step >= 0.0f) || (i > 0 && !(k[i].step > k[i - 1].step)))
            return mer_error_set(err, MER_ERR_RANGE, name,
                                 "%s keyframe steps must be >= 0 and strictly increasing", name);
        if (!((double)k[i].value >= lo && (double)k[i].value <= hi))
            return mer_error_set(err, MER_ERR_RANGE, name,
                                 "%s keyframe values must be in [%g, %g], got %g", name, lo, hi,
                                 (double)k[i].value);
    }
    return MER_OK;
}mer_result merp_p09_validate(const mer_params *p, mer_error *err)
{
    assert(p != NULL);
    if (p->w_min > p->w_max)
        return mer_error_set(err, MER_ERR_RANGE, "w_min", "w_min must be at most w_max (%g), got %g",
                             (double)p->w_max, (double)p->w_min);
    mer_result rc = check_keys(p->schedule.lambda_keys, p->schedule.lambda_key_count,
                               "schedule.lambda_keys", 0.0, 1.0, err);
    if (rc == MER_OK)
        rc = check_keys(p->schedule.eta_keys, p->schedule.eta_key_count, "schedule.eta_keys",
                        -100.0, 100.0, err);
    return rc;
}
