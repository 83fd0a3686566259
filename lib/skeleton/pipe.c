/* meristem — the pipe model with memory (P09 §4.5): d^n = d1^n + d2^n, summed
 * basipetally from leaf-bearing tips. "Branch width is not decreased when leaves
 * and branches are shed or pruned": the root of a removed subtree keeps the d^n it
 * had when it was removed (dead nodes are never updated), and that term stays in
 * its parent's sum, hence in every ancestor's, for good. The skeleton stores d^n,
 * so every growth model gets diameters by calling merp_pipe_update after its step. */
#include "config.h"

#include <assert.h>
#include <math.h>

#include "skeleton/skeleton.h"

/* How many nodes ahead of the basipetal sum a parent's d^n is asked for. */
#define AHEAD 16

float merp_pipe_leaf(const merp_skeleton *sk, const mer_params *p)
{
    return powf(p->leaf_diameter, sk->pipe_n);
}

/* Whether node i is the root of a removed subtree under a living node: its frozen
 * d^n is the memory of the removed pipes. */
static int is_remembered(const merp_skeleton *sk, uint32_t i)
{
    uint32_t p = sk->parent[i];
    return !sk->alive[i] && p != MER_NO_NODE && sk->alive[p];
}

void merp_pipe_update(merp_skeleton *sk, const mer_params *p)
{
    assert(sk != NULL && p != NULL);
    float leaf = merp_pipe_leaf(sk, p);
    /* Children have higher ids than their parents: a reverse pass sees every node
     * after all its children. dn of a living node is its accumulator, summing the
     * children pushed into it; dead nodes keep theirs. */
    for (uint32_t i = 0; i < sk->n; i++)
        if (sk->alive[i])
            sk->dn[i] = 0.0f;
    for (uint32_t i = sk->n; i-- > 0;) {
        /* a node's parent may lie far below it: ask for its sum early */
        if (i >= AHEAD && sk->parent[i - AHEAD] != MER_NO_NODE)
            __builtin_prefetch(sk->dn + sk->parent[i - AHEAD], 1);
        uint32_t up = sk->parent[i];
        if (sk->alive[i]) {
            if (sk->child[3 * i] == MER_NO_NODE)
                sk->dn[i] += leaf; /* a tip bears the leaves */
            if (up != MER_NO_NODE)
                sk->dn[up] += sk->dn[i];
        } else if (is_remembered(sk, i)) {
            sk->dn[up] += sk->dn[i];
        }
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
