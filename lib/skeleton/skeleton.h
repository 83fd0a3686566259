/* meristem — the skeleton every growth model shares: metamers (internodes with their
 * buds) as a struct of arrays, plants, the pipe model's diameters and the brush
 * constraint (P09 §3, §4.5, §5). Not installed. Models add nodes with
 * merp_skel_node_new and change bud states with merp_skel_bud_set; prune, bend,
 * the brush constraint and meshing read and write only this, whatever model grew it. */
#ifndef MERISTEM_SKELETON_H
#define MERISTEM_SKELETON_H

#include <assert.h>
#include <stddef.h>
#include <stdint.h>

#include <meristem/params.h>
#include <meristem/result.h>
#include <meristem/rng.h>
#include <meristem/scene.h>

/* Told when a dormant bud appears (sign +1) or goes (-1) at point p: the
 * environment's shadow follows the buds (P09 §4.1). */
typedef void (*merp_bud_fn)(void *ctx, const float p[3], int sign);

typedef struct merp_skeleton {
    /* Nodes (metamers), indexed by id; ids are never reused. Slot k of a node: 0 is
     * the main continuation / terminal bud, 1 and 2 the lateral ones. The links of
     * a living node agree both ways: a child it lists lives and names it as parent
     * in that slot, its parent lives and lists it (a removed subtree's root is
     * unlisted, merp_skel_kill). A checkpoint that says otherwise is refused. */
    uint32_t n, cap;
    uint32_t mapped;   /* the pages of nodes [0, mapped) are mapped (merp_prefault) */
    uint32_t *parent;
    uint32_t *child;   /* 3 per node: main, lateral 1, lateral 2 (MER_NO_NODE) */
    uint8_t *bud;      /* 3 per node: mer_bud_state of terminal, lateral 1, lateral 2 */
    uint8_t *slot;     /* which slot of the parent this node grew from */
    uint8_t *alive;
    uint32_t *plant, *order, *born;
    float *pos, *dir, *side; /* 3 per node: base, unit direction, phyllotactic side */
    float *len;
    float *q;          /* light Q of the subtree as the model last saw it (mer_node.q) */
    float *dn;         /* d^n of the pipe model; a dead subtree root keeps its own (memory) */
    float pipe_n;      /* the n that dn was computed with */
    float cos_beta, sin_beta; /* of the branch angle: lateral bud directions */

    uint32_t nplants, cap_plants;
    uint32_t *roots;

    uint32_t con_node, con_slot; /* brush constraint; con_node == MER_NO_NODE: none */

    uint32_t *stack;   /* merp_skel_subtree's output (front half) and work stack */
    size_t stack_cap;

    merp_bud_fn on_bud;
    void *on_bud_ctx;
} merp_skeleton;

/* The per-node arrays, in the order a checkpoint writes them (scene_io.c): where
 * each one's pointer lies in merp_skeleton and its bytes a node. Growing,
 * copying, mapping, freeing, saving and loading go over this one list, so an
 * array added to the skeleton is added here once. */
typedef struct merp_skel_array {
    size_t at;    /* offsetof(merp_skeleton, its pointer) */
    size_t bytes; /* a node's elements: 3 floats for pos, 1 byte for alive */
} merp_skel_array;
#define MERP_SKEL_ARRAYS 14
extern const merp_skel_array merp_skel_arrays[MERP_SKEL_ARRAYS];
/* The address of per-node array a's pointer in sk: for merp_array_resize,
 * merp_array_dup and merp_get_array, which copy pointers through it. */
static inline void *merp_skel_array_slot(merp_skeleton *sk, size_t a)
{
    assert(a < MERP_SKEL_ARRAYS);
    return (char *)sk + merp_skel_arrays[a].at;
}
/* Per-node array a of sk itself. */
void *merp_skel_array_data(const merp_skeleton *sk, size_t a);

/* An empty skeleton with the branch angle and pipe exponent of `p` (resolved). */
void merp_skel_init(merp_skeleton *sk, const mer_params *p, merp_bud_fn on_bud, void *ctx);
void merp_skel_free(merp_skeleton *sk);
/* A deep copy of `src` into `dst` (whose old contents are ignored) that tells
 * `on_bud`/`ctx` of its buds. MER_ERR_NOMEM (dst is empty then). O(nodes). */
mer_result merp_skel_clone(const merp_skeleton *src, merp_skeleton *dst, merp_bud_fn on_bud,
                           void *ctx, mer_error *err);
/* Takes the branch angle of `p` (resolved) for the lateral bud directions. */
void merp_skel_init_angles(merp_skeleton *sk, const mer_params *p);
/* A new node born at `step`, unlinked, zeroed, with no buds. MER_ERR_LIMIT past
 * MER_NODES_MAX, MER_ERR_NOMEM. Amortized O(1). */
mer_result merp_skel_node_new(merp_skeleton *sk, uint32_t step, uint32_t *id, mer_error *err);
/* A new plant: its first internode at `base` pointing up, with length l0, the leaf
 * diameter and dormant buds. Its phyllotactic side is drawn from `rng` (one draw,
 * after the node is made): seeds give differently turned seedlings, hence
 * different trees, under shadow propagation too. */
mer_result merp_skel_add_plant(merp_skeleton *sk, const mer_params *p, uint32_t step,
                               const float base[3], mer_rng *rng, uint32_t *root,
                               mer_error *err);
/* Dead node `id` made again as merp_skel_node_new makes a node, born at `step`:
 * for a model that rebuilds its tree and gives a node back its id. O(1). */
void merp_skel_node_renew(merp_skeleton *sk, uint32_t id, uint32_t step);
/* Makes node `id` (no parent) the root of a new plant: its plant index is set.
 * MER_ERR_NOMEM. Amortized O(1). */
mer_result merp_skel_add_root(merp_skeleton *sk, uint32_t id, mer_error *err);
/* Empties the skeleton for a model that rebuilds it whole each step (L-systems):
 * every dormant bud goes first (on_bud is told), then ids start again at 0 and
 * the plants and the brush constraint are dropped; memory is kept. O(nodes). */
void merp_skel_reset(merp_skeleton *sk);
/* The end point of node i: pos + dir·len. Inline: every step reads it for
 * every live bud. */
static inline void merp_skel_node_end(const merp_skeleton *sk, uint32_t i, float out[3])
{
    assert(i < sk->n);
    for (int a = 0; a < 3; a++)
        out[a] = sk->pos[3 * i + a] + sk->dir[3 * i + a] * sk->len[i];
}
/* The direction of bud k of node i: the internode's for k = 0, else turned by the
 * branch angle towards (k = 1) or away from (k = 2) the phyllotactic side. */
void merp_skel_bud_dir(const merp_skeleton *sk, uint32_t i, uint32_t k, float out[3]);
/* Sets bud k of node i and tells on_bud when a live node's dormant bud comes or goes. */
void merp_skel_bud_set(merp_skeleton *sk, uint32_t i, uint32_t k, uint8_t state);
/* 1 if bud k of node i is dormant and exists under buds_per_node. Inline: the
 * per-step walks ask it for every slot of every live node. */
static inline int merp_skel_bud_exists(const merp_skeleton *sk, uint32_t i, uint32_t k,
                                       uint32_t buds_per_node)
{
    return sk->bud[3 * i + k] == MER_BUD_DORMANT && (k == 0 || k <= buds_per_node);
}
/* Tells on_bud (+1) of every dormant bud of every live node, in id order. O(nodes). */
void merp_skel_cast_buds(const merp_skeleton *sk);
/* The live subtree of `root` (root first, then depth-first) into
 * sk->stack[0..count). O(subtree). */
mer_result merp_skel_subtree(merp_skeleton *sk, uint32_t root, size_t *count, mer_error *err);
/* Kills the subtree of `root` (its buds go first) and unlinks it from its parent;
 * drops a constraint inside it. O(subtree). */
mer_result merp_skel_kill(merp_skeleton *sk, uint32_t root, mer_error *err);
/* The side vector of the next metamer along direction d: the previous one carried
 * onto the plane normal to d, then turned by the divergence angle (phyllotaxis). */
void merp_side_next(const float side_prev[3], const float d[3], float divergence_deg,
                    float out[3]);
/* Folds every node's fields into the FNV-1a `h`, in mer_scene_hash's order. O(nodes). */
uint64_t merp_skel_hash(const merp_skeleton *sk, uint64_t h);

/* pipe.c: the pipe model with memory (P09 §4.5), d^n = d1^n + d2^n. */
/* d^n of a leaf-bearing tip. */
float merp_pipe_leaf(const merp_skeleton *sk, const mer_params *p);
/* Basipetal update after a step: each living node's d^n becomes the sum of its
 * living children's, plus the leaf's at a tip, plus the d^n its removed (pruned or
 * shed) children had when they were removed: the memory of P09 §4.5, so d^n never
 * shrinks while leaf_diameter and n stay. O(nodes). */
void merp_pipe_update(merp_skeleton *sk, const mer_params *p);
/* Re-expresses the stored d^n under a new exponent n. O(nodes). */
void merp_pipe_set_n(merp_skeleton *sk, float n);
/* The diameter d of node i. */
float merp_pipe_diameter(const merp_skeleton *sk, uint32_t i);

#endif
