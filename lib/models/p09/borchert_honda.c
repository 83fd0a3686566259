/* meristem — extended Borchert-Honda allocation, the acropetal pass (P09 §4.2,
 * Fig. 8a): the resource entering each node is split between its main and lateral
 * continuations by their light, biased by λ. */
#include "config.h"

#include <assert.h>

#include <meristem/fate.h>

#include "models/p09/p09.h"

void merp_p09_allocate_bh(merp_model *m, const merp_world *w)
{
    assert(m != NULL && w != NULL && m->n == w->sk->n);
    const merp_skeleton *sk = w->sk;
    float lambda = mer_params_lambda_at(w->p, w->step);
    for (uint32_t i = 0; i < sk->n; i++) {
        if (i + MERP_P09_AHEAD < sk->n)
            merp_p09_fetch_children(m, sk, i + MERP_P09_AHEAD, 1);
        if (!sk->alive[i])
            continue;
        if (sk->parent[i] == MER_NO_NODE)
            m->vin[i] = w->p->alpha * sk->q[i]; /* v_base = α·Q_base */
        if (m->vin[i] == 0.0f) {
            /* Nothing to share (most of a crown under space colonization): the
             * children get 0 and the buds keep the 0 the environment gave them. */
            for (int k = 0; k < 3; k++)
                if (sk->child[3 * i + k] != MER_NO_NODE)
                    m->vin[sk->child[3 * i + k]] = 0.0f;
            continue;
        }
        float q[3];
        for (int k = 0; k < 3; k++) {
            uint32_t c = sk->child[3 * i + k];
            q[k] = c != MER_NO_NODE ? sk->q[c] : m->qb[3 * i + k];
        }
        float v[3];
        mer_bh_split2(m->vin[i], lambda, q[0], q + 1, &v[0], v + 1);
        for (int k = 0; k < 3; k++) {
            uint32_t c = sk->child[3 * i + k];
            if (c != MER_NO_NODE)
                m->vin[c] = v[k];
            else
                m->vb[3 * i + k] = v[k];
        }
    }
}
