/* meristem — what the inverse model remembers of a tree across rebuilds (G04
 * §4 rebuilds the tree whole at every t): the ids of its nodes by key, the
 * bends in a node's own frame, and when the ids must be renumbered. */
#include "config.h"

#include <assert.h>
#include <string.h>

#include "core/alloc.h"
#include <meristem/rng.h>

#include "core/vec.h"
#include "models/inverse/inverse.h"

static uint32_t slot_of(uint64_t key, uint32_t mask)
{
    uint64_t s = key;
    return (uint32_t)mer_splitmix64(&s) & mask;
}

mer_result merp_inv_map_build(merp_inv_map *map, const merp_inv_keys *keys,
                              const merp_skeleton *sk, mer_error *err)
{
    assert(map != NULL && keys != NULL && sk != NULL);
    uint32_t live = 0, n = sk->n < keys->used ? sk->n : keys->used;
    for (uint32_t i = 0; i < n; i++)
        live += sk->alive[i] && keys->of[i] != 0;
    uint32_t slots = 16;
    while (slots < 2 * live)
        slots *= 2;
    if (slots - 1 != map->mask) {
        merp_inv_map_free(map);
        map->key = merp_malloc((size_t)slots * sizeof *map->key);
        map->id = merp_malloc((size_t)slots * sizeof *map->id);
        if (map->key == NULL || map->id == NULL) {
            merp_inv_map_free(map);
            return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for node ids");
        }
        map->mask = slots - 1;
    }
    for (uint32_t k = 0; k < slots; k++)
        map->id[k] = MER_NO_NODE;
    for (uint32_t i = 0; i < n; i++) {
        if (!sk->alive[i] || keys->of[i] == 0)
            continue;
        uint32_t k = slot_of(keys->of[i], map->mask);
        while (map->id[k] != MER_NO_NODE)
            k = (k + 1) & map->mask;
        map->key[k] = keys->of[i];
        map->id[k] = i;
    }
    return MER_OK;
}

void merp_inv_map_free(merp_inv_map *map)
{
    merp_free(map->key);
    merp_free(map->id);
    memset(map, 0, sizeof *map);
}

uint32_t merp_inv_map_find(const merp_inv_map *map, uint64_t key)
{
    if (map == NULL || map->id == NULL)
        return MER_NO_NODE;
    for (uint32_t k = slot_of(key, map->mask);; k = (k + 1) & map->mask) {
        if (map->id[k] == MER_NO_NODE)
            return MER_NO_NODE;
        if (map->key[k] == key)
            return map->id[k];
    }
}

/* The node's frame: its direction, its side, and direction × side. */
static void frame_of(const merp_skeleton *sk, uint32_t id, float f[3][3])
{
    memcpy(f[0], sk->dir + 3 * id, sizeof f[0]);
    memcpy(f[1], sk->side + 3 * id, sizeof f[1]);
    v3_cross(f[0], f[1], f[2]);
}

merp_inv_bend merp_inv_bend_record(const merp_skeleton *sk, uint32_t id, uint64_t key,
                                   const float ax[3], float angle, uint32_t spread)
{
    assert(id < sk->n);
    float f[3][3];
    frame_of(sk, id, f);
    merp_inv_bend b = {.key = key, .angle = angle, .spread = spread};
    for (int k = 0; k < 3; k++)
        b.axis[k] = v3_dot(ax, f[k]);
    return b;
}

void merp_inv_bend_axis(const merp_skeleton *sk, uint32_t id, const merp_inv_bend *b,
                        float out[3])
{
    assert(id < sk->n);
    float f[3][3];
    frame_of(sk, id, f);
    for (int a = 0; a < 3; a++)
        out[a] = b->axis[0] * f[0][a] + b->axis[1] * f[1][a] + b->axis[2] * f[2][a];
    if (!v3_normalize(out))
        memcpy(out, f[1], sizeof f[1]);
}

int merp_inv_needs_renumbering(const merp_skeleton *sk)
{
    uint32_t live = 0;
    for (uint32_t i = 0; i < sk->n; i++) {
        if (!sk->alive[i])
            continue;
        live++;
        if (sk->parent[i] != MER_NO_NODE && sk->parent[i] > i)
            return 1;
    }
    return sk->n - live > live + 1024u;
}
