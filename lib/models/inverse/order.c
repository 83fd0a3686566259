/* meristem — the length scaling of higher branch orders (G04 §4.2, eq (12)).
 * Eq (12) changes eq (7) for branches of higher order: orders 2
 * and up. The trunk and order 1 keep eq (7) as §4.1 gives it. */
#include "config.h"

#include "models/inverse/inverse.h"

float merp_inv_order_scale(uint32_t order)
{
    return order >= 2 ? 1.0f / (0.5f * (float)order + 1.0f) : 1.0f;
}
