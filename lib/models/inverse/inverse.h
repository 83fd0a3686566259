/* meristem — the inverse (global-to-local) model of G04 §4: a tree whose local
 * properties are graphically defined functions (gfunc.h) of global position and
 * time. Private to lib; `merp_inv_` names.
 *
 * Each equation of G04 §4.1–4.3 is a pure function in a file named after what
 * it computes:
 *   silhouette.c  eqs (5)–(7): branch length by year, young and mature silhouette
 *   order.c       eq (12): the length scaling of higher orders
 *   heading.c     eqs (8)–(9): the heading of each growth increment; the
 *                 branching angle (G04 §2.2: 80° short to 35° long)
 *   scale.c       eqs (10), (13), (15): the branch scale factor s_b
 *   lifespan.c    eq (11): when a branch is shed
 *   shoot.c       eq (14): metamers of a shoot; leaf size G_l
 *   phyllotaxis.c 137.5° divergence and the 40° rule (G04 §4.3)
 *   development.c continuous development within a year (G04 §4.3, Figs. 12–13)
 *   radius.c      the radius as a function of position along the branch (§4.1)
 * and build.c puts them together into a tree at any (fractional) time on the
 * shared skeleton; regrow.c and memory.c carry ids, prunes and bends from one
 * tree to the next; inverse.c is the growth model (model.h) around them,
 * populus.c the Populus deltoides definition of G04 §5, species.c two more of
 * our own.
 *
 * Units: lengths in metres, angles in degrees, time in years. A function's
 * value is in [0, 1] (or [-1, 1] for headings) and a scalar of the definition
 * gives it its unit: l = h_max · G_h(t), θ = θ_max · G_o(x), a = a_max · G_a(s_b),
 * m = m_max · G_m(q), leaf = leaf_size · G_l(x_s), r = r_max · (L / h_max) · G_r(x). G04 draws its functions in
 * the unit the model reads; a unit scale per quantity lets one drawn shape serve
 * trees of any size. */
#ifndef MERISTEM_INVERSE_H
#define MERISTEM_INVERSE_H

#include <stdint.h>

#include <meristem/result.h>

#include <meristem/scene.h>

#include "models/inverse/gfunc.h"
#include "models/model.h"
#include "skeleton/skeleton.h"

/* The functions of the model, by their symbol in G04. */
typedef enum merp_inv_fn {
    MERP_G_H,   /* G_h(t_y): trunk length by time (§4) */
    MERP_G_S1,  /* G_s1(x_y): the young silhouette, eq (6) */
    MERP_G_S2,  /* G_s2(x_y): the mature silhouette, eq (6) */
    MERP_G_O1,  /* G_o1(x_y): heading along a branch of length 0, eq (9) */
    MERP_G_O2,  /* G_o2(x_y): heading along a branch of length l_max, eq (9) */
    MERP_G_BS,  /* G_bs(x_max): branch scale by position on the parent, eqs (10), (13) */
    MERP_G_SS,  /* G_ss(x_s): branch scale by position on the shoot, eq (15) */
    MERP_G_A,   /* G_a(s_b): age at which a branch is shed, eq (11) */
    MERP_G_M,   /* G_m(q): metamers of a shoot, eq (14) */
    MERP_G_L,   /* G_l(x_s): leaf size by position on the shoot (§4.3) */
    MERP_G_E,   /* internode elongation over a metamer's growth (§4.3, Fig. 12) */
    MERP_G_LG,  /* leaf growth over a metamer's growth (§4.3, Fig. 13) */
    MERP_G_BG,  /* bud growth over a metamer's growth (§4.3) */
    MERP_G_R,   /* G_r(x_y): radius by position along the branch (§4.1); optional in a
                 * .fset (merp_inv_radius_default) */
    MERP_G_COUNT
} merp_inv_fn;

/* The function names a definition's .fset uses, by merp_inv_fn: "G_h", ... */
extern const char *const merp_inv_fn_names[MERP_G_COUNT];

#define MERP_INV_YEARS_MAX 200u /* y_max's range: 1..200 */
#define MERP_INV_ORDER_MAX 8u

/* A tree: its functions and scalars. */
typedef struct merp_inv_def {
    merp_gfunc g[MERP_G_COUNT];
    uint32_t y_max;     /* the tree's age at t_y = 1, years (§4) */
    float h_max;        /* trunk length at y_max: the unit of G_h, m */
    float l_min;        /* the least length of a shoot, eq (5), m */
    float l_max;        /* the branch length G_o2 is drawn for, eq (8), m */
    float ls_max;       /* l_smax, the longest shoot, eq (14), m */
    uint32_t m_max;     /* metamers of a shoot of length l_smax: the unit of G_m */
    float a_max;        /* the unit of G_a, years */
    float s_min;        /* no lateral branch below this scale factor (§4.2) */
    float theta_max;    /* the unit of G_o1, G_o2, degrees */
    float beta_short;   /* branching angle of a branch of length 0, degrees (§2.2: 80) */
    float beta_long;    /* branching angle of a branch of length l_max (§2.2: 35) */
    float leaf_size;    /* the unit of G_l, m */
    float span;         /* fraction of a year over which a shoot's metamers start (§4.3) */
    uint32_t order_max; /* the highest branch order built, 1..MERP_INV_ORDER_MAX */
    float jitter;       /* stochastic variation of orientation (§4.1), degrees */
    float r_max;        /* the trunk's base radius at length h_max: the unit of G_r, m */
} merp_inv_def;

/* Checks a definition: every function prepared and named after its role, the
 * scalars in range. MER_ERR_INVALID naming the field. O(functions). */
mer_result merp_inv_def_check(const merp_inv_def *d, mer_error *err);
/* Fills d's functions from a .fset text, matched by name (merp_inv_fn_names;
 * order free, every one required, no others). MER_ERR_FORMAT/INVALID as
 * merp_fset_read, MER_ERR_INVALID for a missing or unknown name. */
mer_result merp_inv_def_functions(merp_inv_def *d, const char *fset, size_t len,
                                  mer_error *err);
/* Replaces the functions a .fset text names (any subset, each at most once);
 * the others stay. Errors as merp_inv_def_functions; d is unchanged then. */
mer_result merp_inv_def_replace(merp_inv_def *d, const char *fset, size_t len, mer_error *err);
/* text.c: a definition as one text: `name: value` lines (`species:` one of
 * populus-deltoides, conifer, weeping, which resets the whole definition to that
 * tree; or a scalar of merp_inv_def by its field name), then .fset text naming
 * any of the functions. What the text names replaces d's; the rest stays.
 * MER_ERR_INVALID/FORMAT/LIMIT with err->line and err->column for a text that
 * does not read or gives an invalid definition; d is unchanged then. O(len). */
mer_result merp_inv_def_read(merp_inv_def *d, const char *text, size_t len, mer_error *err);
/* d whole as such a text (every scalar, every function), merp_malloc'd and
 * 0-terminated, its length in *len (may be NULL); NULL when out of memory.
 * Reading it back gives d. */
char *merp_inv_def_write(const merp_inv_def *d, size_t *len);
/* The Populus deltoides of G04 §5 (populus.c): 27 years. Its functions as .fset
 * text, and the whole definition. */
extern const char merp_inv_populus_fset[];
mer_result merp_inv_populus(merp_inv_def *d, mer_error *err);
/* species.c: two more trees that show the model's range, each the Populus with
 * some functions and scalars changed: an excurrent conifer (a spire of short,
 * level branches in whorl-like tiers) and a weeping form (long branches that arch
 * over and hang). */
mer_result merp_inv_conifer(merp_inv_def *d, mer_error *err);
mer_result merp_inv_weeping(merp_inv_def *d, mer_error *err);

/* silhouette.c — eqs (5)–(7). */
/* t_y = y / y_max (§4). */
float merp_inv_time(uint32_t y, uint32_t y_max);
/* Eq (6): l_dy = l_py · ((1 − t_y) · G_s1(x_y) + t_y · G_s2(x_y)). */
float merp_inv_silhouette(const merp_gfunc *gs1, const merp_gfunc *gs2, float t_y, float x_y,
                          float l_py);
/* Eq (7): l_y = max(l_dy, l_{y−1} + l_min), which enforces eq (5). */
float merp_inv_enforce_min(float l_dy, float l_prev, float l_min);
/* The trunk's lengths l_y = h_max · G_h(t_y) (§4), with eq (7) applied from
 * l_{-1} = 0, for y = 0..y_max into l[0..y_max]. O(y_max). */
void merp_inv_trunk_lengths(const merp_inv_def *d, float *l);
/* A lateral branch's lengths for y = 0..y_max into l[0..y_max] (0 before y_c):
 * eqs (6), (7) on the parent's lengths lp[] at the global position x (m) along
 * it, from l_{y_c − 1} = 0; then scaled by s_b (§4.1, "once a branch's length is
 * determined ... it is scaled by s_b") and by eq (12) for its order. O(y_max). */
void merp_inv_branch_lengths(const merp_inv_def *d, const float *lp, float x, uint32_t y_c,
                             uint32_t order, float s_b, float *l);

/* order.c — eq (12): the divisor's inverse 1 / (0.5 · order + 1) for order >= 2,
 * 1 for the trunk and order 1 (eq (7) as §4.1 gives it). */
float merp_inv_order_scale(uint32_t order);

/* heading.c — eqs (8)–(9). */
/* Eq (8): s_θ = l_y / l_max, clamped to [0, 1]. */
float merp_inv_s_theta(float l_y, float l_max);
/* Eq (9): θ = (1 − s_θ) · G_o1(x_y) + s_θ · G_o2(x_y), times θ_max (degrees). */
float merp_inv_heading(const merp_gfunc *go1, const merp_gfunc *go2, float s_theta, float x_y,
                       float theta_max);
/* The branching angle: from beta_short (s_θ = 0) to beta_long (s_θ = 1). */
float merp_inv_branch_angle(const merp_inv_def *d, float s_theta);
/* The direction at angle θ (degrees) from the branch's original heading h0
 * towards the parent's direction dp (θ < 0: away from it), θ clamped so it
 * neither passes dp nor −dp. h0, dp unit; out unit. */
void merp_inv_orient(const float h0[3], const float dp[3], float theta, float out[3]);

/* scale.c — eqs (10), (13), (15). */
/* s_b = G_ss(x_s) · s_bp · G_bs(x_max): eq (15); eq (13) with gss NULL; eq (10)
 * with gss NULL and s_bp = 1. Never negative. */
float merp_inv_scale(const merp_gfunc *gbs, float x_max, float s_bp, const merp_gfunc *gss,
                     float x_s);

/* lifespan.c — eq (11). */
/* a = a_max · G_a(s_b), in years. */
float merp_inv_lifespan(const merp_gfunc *ga, float s_b, float a_max);
/* Whether a branch born (its first shoot growing) in year `born`, with lifespan
 * a, still stands at time t: it is shed once t − born reaches a. */
int merp_inv_alive_at(float a, uint32_t born, double t);

/* shoot.c — eq (14) and leaves. */
/* m = G_m(q), q = l_s / l_smax, in metamers: at least 1, at most m_max. */
uint32_t merp_inv_metamers(const merp_gfunc *gm, float l_s, float ls_max, uint32_t m_max);
/* The leaf size of the metamer at x_s along its shoot: leaf_size · G_l(x_s). */
float merp_inv_leaf_size(const merp_gfunc *gl, float x_s, float leaf_size);
/* Where the j-th of m metamers sits along its shoot, x_s ∈ (0, 1]: its tip's. */
float merp_inv_x_s(uint32_t j, uint32_t m);

/* radius.c — the radius along a branch (§4.1). */
/* A branch's base radius: r_max · length / h_max, at most `cap` (the parent's
 * radius where it leaves it; cap < 0: none), m. */
float merp_inv_base_radius(const merp_inv_def *d, float length, float cap);
/* r = r_base · G_r(x), x the position along the branch over its current length
 * (x_y, as for the headings of eq (9)); never negative. */
float merp_inv_radius(const merp_gfunc *gr, float x, float r_base);
/* The G_r a .fset without one gets: a taper from 1 to 0.1. MER_ERR_INVALID
 * never (the points are fixed). */
mer_result merp_inv_radius_default(merp_gfunc *gr, mer_error *err);

/* phyllotaxis.c — G04 §4.3. */
#define MERP_INV_DIVERGENCE 137.5f /* degrees between successive laterals */
#define MERP_INV_APART 40.0f       /* the 40° rule */
/* The angle between two azimuths, in [0, 180]. */
float merp_inv_angle_apart(float a, float b);
/* Whether a shoot of m metamers following a shoot whose longest lateral is on its
 * last metamer keeps its two longest laterals (its last two) at least 40° from
 * that one. */
int merp_inv_count_ok(uint32_t m);
/* The count nearest m in 1..m_max that merp_inv_count_ok accepts (the smaller at
 * a tie); m itself when none does. */
uint32_t merp_inv_phyllo_count(uint32_t m, uint32_t m_max);

/* development.c — continuous development (G04 §4.3, Figs. 12–13). */
/* The fraction of the year when the j-th of m metamers of a shoot starts to
 * grow: span · j / m; each grows for 1 − span, so all are done by the year's end. */
float merp_inv_metamer_start(uint32_t j, uint32_t m, float span);
/* How far (0..1) the j-th of m metamers has grown at fraction f of its year,
 * by the growth curve g (G_e, G_lg or G_bg) over its own growing time. */
float merp_inv_growth(const merp_gfunc *g, float f, uint32_t j, uint32_t m, float span);

/* build.c — every metamer has a key, a function of the seed and its place in
 * the tree (its branch's key, the year of its shoot and its index in that
 * shoot), the same in every year, at every t and under every definition that
 * makes it: what lets a node keep its id, and a prune or bend outlive the
 * rebuilds. */
typedef struct merp_inv_map {
    uint64_t *key;  /* open addressing, linear probing; id MER_NO_NODE: empty */
    uint32_t *id;
    uint32_t mask;  /* slots − 1 (a power of two), 0 when there are none */
} merp_inv_map;
typedef struct merp_inv_keys {
    uint64_t *of;        /* of[id]: the key of node id, for the nodes builds made */
    float *leaf;         /* leaf[id]: its leaf's size, m (G_l, G_lg; 0: none) */
    float *radius;       /* radius[id]: its radius at its base, m (G_r, radius.c) */
    uint32_t cap;        /* entries of the arrays (merp_malloc'd; builds grow them) */
    uint32_t used;       /* one past the highest id a build recorded */
    const uint64_t *cut; /* the keys of cut metamers, sorted: a build stops there */
    uint8_t *hit;        /* hit[k]: a build reached cut k (may be NULL) */
    uint32_t ncut;
    const merp_inv_map *ids; /* the ids of the tree before: a key found there
                              * gets its id again (may be NULL) */
} merp_inv_keys;

/* memory.c — what the model keeps across rebuilds (see inverse.c). */
/* The map of every live node of sk with a key in `keys` to its id. MER_ERR_NOMEM.
 * O(nodes). */
mer_result merp_inv_map_build(merp_inv_map *map, const merp_inv_keys *keys,
                              const merp_skeleton *sk, mer_error *err);
void merp_inv_map_free(merp_inv_map *map);
/* The id of `key` in the map, MER_NO_NODE when it is not there. O(1) expected. */
uint32_t merp_inv_map_find(const merp_inv_map *map, uint64_t key);
/* A bend as the model records it: the node by its key, the axis in the node's
 * frame (along its direction, its side, and direction × side), so that it turns
 * the same way relative to the branch however the functions place it. */
typedef struct merp_inv_bend {
    uint64_t key;
    float axis[3];
    float angle;     /* degrees */
    uint32_t spread; /* mer_scene_bend_spread's */
} merp_inv_bend;
/* The bend of node `id` about the world axis `ax` (unit), as a record. */
merp_inv_bend merp_inv_bend_record(const merp_skeleton *sk, uint32_t id, uint64_t key,
                                   const float ax[3], float angle, uint32_t spread);
/* The world axis of a record at node id. */
void merp_inv_bend_axis(const merp_skeleton *sk, uint32_t id, const merp_inv_bend *b,
                        float out[3]);
/* Whether the tree needs its ids renumbered: more dead ids than live ones (and
 * 1024 more), or a node whose id is below its parent's (the mesher and the
 * pipe model take parents first). O(nodes). */
int merp_inv_needs_renumbering(const merp_skeleton *sk);
/* The tree at time t (years, 0..y_max, fractional allowed) onto plant `root`
 * of sk: root's subtree is replaced (the old nodes die, unremembered by the pipe
 * model) by the tree of `d` at t, its nodes born at the year of their shoot.
 * Deterministic in (d, t, seed): the same branch gets the same variation in
 * every year. With `keys` (may be NULL), each node's key is recorded and a
 * branch ends below a cut metamer. MER_ERR_LIMIT past MER_NODES_MAX,
 * MER_ERR_NOMEM. O(nodes). */
mer_result merp_inv_build(const merp_inv_def *d, double t, uint64_t seed, merp_skeleton *sk,
                          uint32_t root, merp_inv_keys *keys, mer_error *err);

/* The model's state (inverse.c, regrow.c). */
struct merp_model {
    merp_inv_def def;
    uint64_t seed;
    int seeded;
    double t;              /* the time the tree shows */
    merp_inv_keys keys;
    uint64_t *cuts;        /* keys.cut's storage, sorted */
    uint8_t *hit;          /* keys.hit's storage */
    uint32_t cap_cuts;     /* of cuts and hit */
    merp_inv_bend *bends;  /* in the order they were made */
    uint32_t nbends, cap_bends;
    uint32_t dropped;      /* prunes and bends the last rebuild dropped */
    merp_inv_map ids;      /* scratch: key → id */
    char *text;            /* the definition as text (merp_inv_def_write), NULL out of memory */
    size_t tlen;
    uint32_t branches[MERP_INV_ORDER_MAX + 1]; /* live branches by order, last build */
};

/* regrow.c — the tree at time t on every plant of w->sk, the recorded edits
 * made again: the seed is drawn from w->rng at the first; a node keeps its id
 * where its key had one (renumbered when merp_inv_needs_renumbering says so);
 * a cut key stops its branch; each bend is made again at its node. A prune or
 * bend whose node this tree lacks is dropped (m->dropped counts them).
 * MER_ERR_NOMEM, MER_ERR_LIMIT as merp_inv_build. O(nodes). */
mer_result merp_inv_show(merp_model *m, const merp_world *w, double t, mer_error *err);
/* Records a bend of node id (model.h's `bending`). MER_ERR_NOMEM. */
mer_result merp_inv_record_bend(merp_model *m, const merp_skeleton *sk, uint32_t id,
                                const float ax[3], float angle, uint32_t spread,
                                mer_error *err);

/* inverse.c — the growth model (model.h): a step is a year; the scene's tree is
 * its definition at year = steps done (the Populus of G04 §5 until
 * a definition text (mer_scene_set_definition, text.c) or merp_inverse_set_def
 * gives another). Registered as MER_MODEL_INVERSE, "inverse". Past y_max a step
 * is MER_ERR_LIMIT. */
extern const merp_model_ops merp_inverse_ops;
/* Shows the scene's tree at time t (years, fractional allowed, 0..y_max): every
 * plant rebuilt, then the pipe model's diameters. The step count stays; the next
 * step shows its whole year. `s` must run merp_inverse_ops. MER_ERR_RANGE for t
 * outside 0..y_max; as merp_inv_build. O(nodes). */
mer_result merp_inverse_show(mer_scene *s, double t, mer_error *err);
/* Replaces the scene's definition (checked: merp_inv_def_check) and shows the
 * tree of the time shown last under it (nothing to show before the first
 * step or show). MER_ERR_RANGE when its y_max is below that time. As
 * merp_inverse_show otherwise. */
mer_result merp_inverse_set_def(mer_scene *s, const merp_inv_def *d, mer_error *err);
/* The scene's definition, borrowed. */
const merp_inv_def *merp_inverse_def(const mer_scene *s);
/* The time its tree shows. */
double merp_inverse_time(const mer_scene *s);
/* The key of node id (build.c): the same metamer has the same key in every
 * year's tree, though its id changes with every rebuild. 0 for an id no build
 * made (the plants' roots before the first step). */
uint64_t merp_inverse_node_key(const mer_scene *s, uint32_t id);
/* The size (m) of node id's leaf in the tree shown: G_l(x_s) as grown by G_lg
 * so far this year (§4.3); 0 for last year's metamers and ids no build made.
 * For a mesher that sizes leaves per node (lib/mesh/ sizes them all alike). */
float merp_inverse_leaf_size(const mer_scene *s, uint32_t id);

#endif
