/* meristem — the space colonization algorithm of Runions, Lane & Prusinkiewicz
 * 2007 ("R07"), the original one that P09 §7 contrasts with its own (P09 Fig.
 * 21a): no buds, no light, no apical control, only competition for space. Not
 * installed.
 *
 * One step is one iteration of R07's loop:
 *  1. every attraction point (a marker of the environment: the marker volumes,
 *     the brush) within d_k of a tree node is removed;
 *  2. every other point associates with the closest tree node within the radius
 *     of influence d_i;
 *  3. every node with points grows one new node at distance D along the
 *     normalized sum of the unit vectors towards its points (both through the
 *     scene's Perlin noise, env/noise.h, which is off by default);
 *  4. the points within d_k of the new nodes are removed.
 * Growth ends when no point is associated (the step report says no-markers) or
 * when the client stops stepping.
 *
 * Onto the shared skeleton: a tree node is the end point of an internode (the
 * plant's first internode, l0 long, is the root). A new node is a new internode
 * from its parent's end, D long; it takes the parent's first free child slot:
 * slot 0 (the main continuation, same branch order) first, then the laterals 1
 * and 2 (order + 1). A node sprouts at most three shoots, as a bud-bearing node
 * does: once its three slots are taken it no longer takes part in association,
 * and its points go to the closest node within d_i that has a free slot. Points
 * it is within d_k of are still removed (step 1). A tip (no slot-0 child) keeps
 * a dormant terminal bud in the skeleton, so that the step report and the pipe
 * model (leaves at tips) read it as every model's tip; R07 itself has no buds.
 *
 * Choices where R07 is open:
 *  - Ties (a point at the same distance from two nodes) go to the lower node id.
 *  - A node whose directions sum to zero (points in perfect balance) does not
 *    grow in that step.
 *  - A new node that would end below the ground or inside an obstacle is not
 *    made; its points stay.
 *  - Under the brush constraint only the constrained node and its subtree grow.
 *
 * Closest-node queries go through a uniform grid of the node ends with cells of
 * edge d_i, and only the markers near the tree are read, from the marker grid
 * (associate.c): a step costs O(nodes + points near the tree · nodes per 27
 * cells), not O(points · nodes), nor O(points). */
#ifndef MERISTEM_RUNIONS_H
#define MERISTEM_RUNIONS_H

#include <stddef.h>
#include <stdint.h>

#include "models/model.h"

/* The per-step scratch; R07 keeps no state between steps (the tree and the
 * points are the skeleton's and the environment's). */
struct merp_model {
    /* per node, by id */
    float *sum;        /* 3 per node: sum of the unit vectors towards its points */
    uint32_t *count;   /* its associated points */
    uint8_t *ok;       /* 1: may take part in association (alive, free slot, not constrained out) */
    size_t node_cap;
    /* the grid of node ends: cell index per entry, sorted by cell (CSR) */
    uint32_t *start;   /* cells + 1 */
    size_t start_cap;
    uint32_t *gid;     /* node id per grid entry */
    float *gp;         /* 3 per grid entry: the node's end */
    size_t grid_cap;
    /* the positions of the live markers near the tree, the killed ones first */
    float *pts;
    size_t pts_cap;
};

/* associate.c: steps 1 and 2 of the header for the live markers of `mk`: fills
 * m->sum and m->count for the nodes m->ok marks, and copies the markers within
 * d_i of a live node's end (and some farther, which no node takes) into m->pts,
 * in index order, those within d_k of any live node moved to the front:
 * `*killed` of them (the step removes those; the rest only steer). Needs m's
 * per-node arrays sized for the skeleton. MER_ERR_NOMEM. */
mer_result merp_runions_associate(merp_model *m, const merp_skeleton *sk, mer_markers *mk,
                                  float d_i, float d_k, size_t *killed, mer_error *err);

#endif
