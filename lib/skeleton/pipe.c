/* meristem — the pipe model with memory (P09 §4.5): d^n = d1^n + d2^n, summed
 * basipetally from leaf-bearing tips, never shrinking. The skeleton stores d^n, so
 * every growth model gets diameters by calling merp_pipe_update after its step. */
#include "config.h"

#include <assert.h>
#include <math.h>

#include "skeleton/skeleton.h"

float merp_pipe_leaf(const merp_skeleton *sk, const mer_params *p)
{
    return powf(p->leaf_diameter, sk->pipe_n);
}

void merp_pipe_update(merp_skeleton *sk, const mer_params *p)
{
    assert(sk != NULL && p != NULL);
    float leaf = merp_pipe_leaf(sk, p);
    for (uint32_t i = sk->n; i-- > 0;) {
        if (!sk->alive[i])
            continue;
        uint32_t m = sk->child[3 * i];
        float sum = m != MER_NO_NODE ? sk->dn[m] : leaf;
        for (int k = 1; k < 3; k++) {
            uint32_t c = sk->child[3 * i + k];
            if (c != MER_NO_NODE)
                sum += sk->dn[c];
        }
        if (sum > sk->dn[i])
            sk->dn[i] = sum;
    }
}

void merp_pipe_set_n(merp_skeleton *sk, float n)
{
    assert(n >= 1.0f);
    if (n == sk->pipe_n)
        return;
    for (uint32_t i = 0; i < sk->n; i++)
        if (sk->dn[i] > 0.0f)
            sk->dn[i] = powf(powf(sk->dn[i], 1.0f / sk->pipe_n), n);
    sk->pipe_n = n;
}

float merp_pipe_diameter(const merp_skeleton *sk, uint32_t i)
{
    assert(i < sk->n);
    return sk->dn[i] > 0.0f ? powf(sk->dn[i], 1.0f / sk->pipe_n) : 0.0f;
}
