/* meristem — shedding (P09 §4.4, after Takenaka): a lateral branch whose light per
 * internode falls below the threshold does not pay for itself and is shed. */
#include "config.h"

#include <assert.h>

#include "models/p09/p09.h"

mer_result merp_p09_shed(merp_model *m, const merp_world *w, uint32_t *count, mer_error *err)
{
    assert(m != NULL && w != NULL && count != NULL && m->n == w->sk->n);
    merp_skeleton *sk = w->sk;
    *count = 0;
    float th = w->p->shed_threshold;
    for (uint32_t i = 0; i < sk->n; i++) {
        if (!sk->alive[i] || sk->slot[i] == 0 || sk->parent[i] == MER_NO_NODE)
            continue;
        if (sk->q[i] / (float)m->sub[i].nint < th) {
            mer_result rc = merp_skel_kill(sk, i, err);
            if (rc != MER_OK)
                return rc;
            (*count)++;
        }
    }
    return MER_OK;
}
