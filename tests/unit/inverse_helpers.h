/* Helpers shared by the inverse model's unit tests (test_inverse.c,
 * test_inverse_edits.c): a scene of the model's default definition and a node
 * found by its key. Include after <cmocka.h> and scene_private.h. */
#ifndef MERISTEM_TEST_INVERSE_HELPERS_H
#define MERISTEM_TEST_INVERSE_HELPERS_H

#include "models/inverse/inverse.h"

/* An inverse-model scene (the Populus of G04 §5) from `seed`, not grown. */
static inline mer_scene *inverse_scene(uint64_t seed)
{
    mer_scene *s = NULL;
    mer_error err;
    if (merp_scene_new_with(&merp_inverse_ops, NULL, seed, &s, &err) != MER_OK)
        fail_msg("merp_scene_new_with: %s", err.message);
    return s;
}

/* The alive node of key `key`, or MER_NO_NODE. */
static inline uint32_t node_of_key(const mer_scene *s, uint64_t key)
{
    for (uint32_t i = 0; i < s->sk.n; i++)
        if (s->sk.alive[i] && merp_inverse_node_key(s, i) == key)
            return i;
    return MER_NO_NODE;
}

#endif
