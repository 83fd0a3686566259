/* meristem — trees grown along least-cost paths in a graph whose edge costs follow
 * guiding vectors, after Xu & Mould 2015 ("XM15", "Procedural tree modeling with
 * guiding vectors"; the survey's §II). Not installed.
 *
 * The method, and where each part lives:
 *  1. graph.c: the volume the tree may occupy is populated with nodes on a
 *     jittered grid (one node per cell of edge h = gv_density^(-1/3), jittered
 *     within its cell), and each node is linked by a directed edge to its
 *     nearest neighbour in each of k cones (a Yao graph; gv_cones). The cones'
 *     axes are k directions spread over the sphere (a Fibonacci lattice); a
 *     neighbour belongs to the cone whose axis is closest to its direction.
 *  2. dijkstra.c: Dijkstra from the source (the tree so far) with edge costs
 *     computed lazily as nodes are opened: a newly opened node's guiding
 *     vector is its parent's rotated by δ(h) about the axis perpendicular to
 *     both the up direction and the edge it was reached by (guide.c), and an
 *     edge e out of it costs |e|·(ε + (1 − g·ê)/2)^p, never zero for ε > 0.
 *  3. endpoints.c: the endpoints of an iteration. The first iteration's
 *     (gv_early_endpoints) are drawn among the nodes of the crown's core (the
 *     crown volume scaled by one half about its centre): one gives a trunk,
 *     several a shrub. A later iteration's lie on a surface extrapolated from
 *     the tree: the nodes exactly gv_k_hops hops from the tree, ordered by
 *     distance from the root, the outermost fraction gv_t of them, and with
 *     gv_bound only those inside the crown volume; gv_endpoints are drawn
 *     among them (all of them when there are fewer). With gv_endpoints_total
 *     T > 0, the iterations share T instead: the first asks for
 *     min(gv_early_endpoints, T), each later one for its share of what is
 *     left, ⌈(T − chosen) / iterations left⌉, so a surface that holds fewer
 *     passes its shortfall on and the tree gets exactly T endpoints unless the
 *     last iteration's surface is short too (the `endpoints` statistic says).
 *  4. tree.c: the union of the least-cost paths to the endpoints joins the
 *     tree, which is the next iteration's source.
 *
 * One step is one iteration; steps after gv_iterations (or after T endpoints)
 * grow nothing, and the step report says the model is done.
 *
 * The crown volume is the scene's marker volume (marker_volume, marker_center,
 * marker_size); no markers are needed (any environment will do). The graph
 * covers that volume's bounding box grown by a quarter on every side and
 * stretched down to the plants' first internodes; nodes below the ground or
 * inside obstacles are left out. The graph is built in the first step (its
 * jitter drawn from the scene's stream) and kept, in clones and checkpoints,
 * for the scene's life: parameters changed later (gv_density, gv_cones, the
 * volume) do not rebuild it.
 *
 * Onto the shared skeleton: each tree edge of the graph is an internode from its
 * parent's end to the node, translated with the parent when a bend moved it. A
 * node's first child continues its axis (slot 0, same order); the others are
 * laterals (order + 1) in slot 1 of the node or of a chain of joints (nodes of
 * length 0 in slot 2), since a graph node may have up to k children. So the
 * orders are the path hierarchy: a path keeps its order until it leaves one it
 * branched from. Diameters are the shared pipe model's. A tip keeps a dormant
 * terminal bud for the pipe model's leaves and the step report. A pruned node
 * leaves the tree (a later iteration may reach it again).
 *
 * Choices where XM15 (as the survey gives it) is open:
 *  - The rotation increment δ(h) = gv_rotation · gv_rotation_falloff^(h − 1) at
 *    the h-th hop from the root; hops and guiding vectors of tree nodes are
 *    kept from the iteration that added them, so later branches go on rotating.
 *    The first guiding vector is up; an edge parallel to up does not rotate it.
 *  - Ties (equal costs, equal distances) go to the lower node index.
 *  - Endpoint draws come from the scene's stream, so a seed replays exactly; all
 *    of it runs on the calling thread. */
#ifndef MERISTEM_GUIDING_H
#define MERISTEM_GUIDING_H

#include <stddef.h>
#include <stdint.h>

#include "models/model.h"

/* graph.c: the directed Yao graph, its edges in CSR order. */
typedef struct merp_gv_graph {
    uint32_t n;      /* nodes */
    float *pos;      /* 3 per node */
    uint32_t *start; /* n + 1: node i's edges are to[start[i] .. start[i + 1]) */
    uint32_t *to;
} merp_gv_graph;

void merp_gv_graph_free(merp_gv_graph *g);
/* The k cone axes (3·k floats): unit vectors spread over the sphere. O(k). */
void merp_gv_cone_axes(uint32_t k, float *axes);
/* The cone of direction d (need not be unit): the axis with the largest dot. */
uint32_t merp_gv_cone_of(const float *axes, uint32_t k, const float d[3]);
/* Links the `n` points at `pos` (copied into g) as a Yao graph: from every point,
 * an edge to the nearest other point within `radius` in each of the `k` cones.
 * MER_ERR_NOMEM. O(n · points within radius · k). */
mer_result merp_gv_graph_link(merp_gv_graph *g, const float *pos, uint32_t n, uint32_t k,
                              float radius, mer_error *err);
/* The jittered grid of `density` per unit volume in the box [lo, hi]: one point
 * per cell drawn from `rng`, leaving out those `keep` says no to (when not
 * NULL). Appends to *pts (3 floats each; *n of them, *cap allocated).
 * MER_ERR_NOMEM. O(cells). */
mer_result merp_gv_jitter(const float lo[3], const float hi[3], float density, mer_rng *rng,
                          int (*keep)(const void *ctx, const float p[3]), const void *ctx,
                          float **pts, uint32_t *n, uint32_t *cap, mer_error *err);

/* guide.c: the guiding vectors and edge costs. */
typedef struct merp_gv_guide {
    int on;         /* 0: plain Euclidean lengths, no guiding vectors (Fig. 5 left) */
    float rotation; /* δ at the first hop, radians */
    float falloff;  /* δ(h) = rotation · falloff^(h − 1) */
    float eps, p;   /* ε > 0 and p of the edge cost */
} merp_gv_guide;

/* The guiding vector of a node opened at hop `hop` (>= 1) over edge `e` from a
 * parent with guiding vector `parent` (unit); `out` is unit. */
void merp_gv_turn(const merp_gv_guide *gd, const float parent[3], const float e[3], uint32_t hop,
                  float out[3]);
/* The cost of edge `e` (not zero) leaving a node with guiding vector `g`. */
double merp_gv_cost(const merp_gv_guide *gd, const float g[3], const float e[3]);

/* dijkstra.c: least-cost paths from a set of sources. */
typedef struct merp_gv_search {
    double *dist;   /* per node; INFINITY when not reached */
    uint32_t *pred; /* per node: the node it was reached from; MER_NO_NODE for sources */
    uint32_t *hop;  /* per node: hops from the root (the rotation's h) */
    uint32_t *hsrc; /* per node: hops from the nearest source on its path */
    float *g;       /* 3 per node: its guiding vector once opened */
    uint8_t *done;
    uint32_t cap;
    struct merp_gv_heap_entry *heap;
    size_t heap_n, heap_cap;
} merp_gv_search;

void merp_gv_search_free(merp_gv_search *s);
/* Runs Dijkstra over `gr` from the `ns` sources `src` (each with its guiding
 * vector src_g[3·i] and hop src_hop[i]), with costs from `gd`. MER_ERR_NOMEM.
 * O((n + edges) log edges). */
mer_result merp_gv_dijkstra(merp_gv_search *s, const merp_gv_graph *gr, const merp_gv_guide *gd,
                            const uint32_t *src, const float *src_g, const uint32_t *src_hop,
                            uint32_t ns, mer_error *err);

/* endpoints.c */
/* 1 when p lies in the volume of `kind` (mer_volume_kind) at `center`, `size`. */
int merp_gv_inside(uint32_t kind, const float center[3], const float size[3], const float p[3]);
/* The axis-aligned box around that volume. */
void merp_gv_volume_box(uint32_t kind, const float center[3], const float size[3], float lo[3],
                        float hi[3]);
/* Up to `want` endpoints of iteration `it` (0: the early ones) into *out (n of
 * them, *cap allocated), from the search `s` over `gr` in which `in_tree` marks
 * the tree's nodes; `root` is where "outward" is measured from. MER_ERR_NOMEM. */
mer_result merp_gv_endpoints(const mer_params *p, uint32_t it, const merp_gv_graph *gr,
                             const merp_gv_search *s, const uint32_t *in_tree,
                             const float root[3], uint32_t want, mer_rng *rng, uint32_t **out,
                             uint32_t *n, uint32_t *cap, mer_error *err);

/* The model's state (guiding.c). */
struct merp_model {
    int built;           /* the graph exists (after the first step) */
    uint32_t iteration;  /* iterations done */
    uint32_t endpoints;  /* endpoints chosen over all iterations */
    merp_gv_graph graph;
    /* per graph node */
    uint32_t *skid;      /* the skeleton node ending at it, MER_NO_NODE when not in the tree */
    float *g;            /* 3 per node: its guiding vector when it joined the tree */
    uint32_t *hop;       /* its hops from the root then */
    /* scratch */
    merp_gv_search search;
    uint32_t *ends, ends_cap;
    uint32_t *path, path_cap;
    uint32_t *src, src_cap;
    float *src_g;
    uint32_t *src_hop;
};

/* tree.c: the union of the paths from s to the `n` endpoints `ends` joins the
 * tree and the skeleton. Returns the internodes made in *grown. MER_ERR_NOMEM,
 * MER_ERR_LIMIT. */
mer_result merp_gv_grow_paths(merp_model *m, const merp_world *w, const uint32_t *ends, uint32_t n,
                              uint32_t *grown, mer_error *err);
/* The guide of the parameters `p`. */
merp_gv_guide merp_gv_guide_of(const mer_params *p);

#endif
