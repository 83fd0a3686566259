/* meristem — every parameter of the model, with its paper symbol, default and range.
 *
 * Symbols follow Palubicki et al. 2009 (cited as "P09 §x"). One table in params.c
 * holds, for each scalar field, its name, paper symbol, default, and allowed range;
 * mer_params_default(), mer_params_validate() and mer_params_set() all read it, so
 * the command line and the HTTP API see the same names and ranges.
 *
 * Defaults: mer_params_default() fills every field. A struct that is entirely zero
 * (memset or `= {0}` in static storage) is also taken to mean "all defaults" by
 * every function that takes a `const mer_params *`, as is a NULL pointer. The struct
 * holds only 4-byte fields (float, uint32_t), so it has no padding and can be
 * compared and hashed byte for byte.
 *
 * Units: lengths are in world units; the default internode length l0 is 1, so the
 * paper's "2 internode lengths" is 2. Angles are in degrees. y is up (glTF).
 *
 * Choices where the paper is open (each is tested):
 *  - θ is the full apex angle of the perception cone: a marker is seen when the
 *    angle between the bud direction and the marker direction is at most θ/2.
 *  - The shadow pyramid covers the full square layer |di| <= q, |dk| <= q below the
 *    bud, for q = 0..q_max ("pyramidal penumbra", P09 Fig. 5).
 *  - l = l0 · v/n: the paper's internode length v/n is in units of l0.
 *  - The priority weight function (P09 Fig. 8c) is piecewise linear in the list
 *    position i = 0..N-1: w = w_max at i = 0, falling linearly to w_min at
 *    i = κ·N, and w_min beyond. Smaller κ favours fewer branches (more excurrent,
 *    P09 Fig. 9). N = 1 gives w_max.
 *  - Tropism T is the unit vector up (0, 1, 0); η > 0 bends shoots up
 *    (negative gravitropism), η < 0 down (P09 Fig. 12).
 *  - Apical control (priority model) holds on axes of order k until step
 *    apical_off[k] (MER_NEVER: never removed); orders past the table use the
 *    last entry. λ of the BH model and η follow piecewise-linear keyframes over
 *    steps when keyframes are given (P09 Fig. 11, 13).
 */
#ifndef MERISTEM_PARAMS_H
#define MERISTEM_PARAMS_H

#include <stddef.h>
#include <stdint.h>

#include <meristem/result.h>

#ifdef __cplusplus
extern "C" {
#endif

#define MER_NEVER UINT32_MAX   /* "never" for step-valued parameters */
#define MER_KEYS_MAX 8         /* keyframes per scheduled quantity */
#define MER_ORDERS_MAX 8       /* branch orders with their own schedule entry */

/* The growth model a scene runs. 0 is P09, so all-zero parameters, and every
 * request or journal written before models could be chosen, mean P09. */
typedef enum mer_model_kind {
    MER_MODEL_P09 = 0,    /* self-organizing trees, Palubicki et al. 2009 (default) */
    MER_MODEL_RUNIONS = 1, /* space colonization, Runions, Lane & Prusinkiewicz 2007 */
    MER_MODEL_LSYSTEM = 2, /* L-systems after ABOP, in cpfg's syntax (a definition text) */
    MER_MODEL_INVERSE = 3, /* Galbraith et al. 2004's inverse model: functions of time (a definition text) */
    MER_MODEL_GUIDING = 4, /* least-cost paths along guiding vectors, Xu & Mould 2015 */
    MER_MODEL_FOREST = 5   /* plants of several presets sown over an area (a definition text) */
} mer_model_kind;

/* What Perlin noise perturbs: the bits of mer_params.noise_targets. */
enum {
    MER_NOISE_DIRECTIONS = 1u << 0, /* a new internode's direction */
    MER_NOISE_LENGTHS = 1u << 1,    /* a new internode's length */
    MER_NOISE_RADII = 1u << 2       /* every internode's diameter (pipe model × noise) */
};

typedef enum mer_env_kind {
    MER_ENV_SHADOW = 0,   /* shadow propagation, P09 §4.1 (default) */
    MER_ENV_MARKERS = 1   /* space colonization with markers, P09 §4.1 */
} mer_env_kind;

typedef enum mer_fate_kind {
    MER_FATE_BH = 0,       /* extended Borchert-Honda, P09 §4.2 (default) */
    MER_FATE_PRIORITY = 1  /* priority model, P09 §4.2, Fig. 8b */
} mer_fate_kind;

typedef enum mer_shadow_dir {
    MER_SHADOW_DIR_NEIGHBOUR = 0, /* least-shadowed neighbour voxel in the cone (default) */
    MER_SHADOW_DIR_GRADIENT = 1   /* negative central-difference gradient of s */
} mer_shadow_dir;

typedef enum mer_volume_kind {
    MER_VOLUME_NONE = 0,
    MER_VOLUME_BOX = 1,       /* half extents size[3] */
    MER_VOLUME_SPHERE = 2,    /* radius size[0] */
    MER_VOLUME_ELLIPSOID = 3, /* radii size[3] */
    MER_VOLUME_CYLINDER = 4,  /* radius size[0], half height size[1], axis y */
    MER_VOLUME_CONE = 5       /* base radius size[0] at center.y - size[1], apex at center.y + size[1] */
} mer_volume_kind;

/* A keyframe of a piecewise-linear schedule: `value` at simulation step `step`. */
typedef struct mer_keyframe {
    float step;
    float value;
} mer_keyframe;

/* The developmental schedule (P09 Fig. 10, 11, 13, 20): data an edit may replace
 * between steps. */
typedef struct mer_schedule {
    uint32_t apical_off[MER_ORDERS_MAX]; /* step at which apical control ends on axes of order k; MER_NEVER */
    float eta_order_scale[MER_ORDERS_MAX]; /* η multiplier for order k (P09 Fig. 20 centre); default 1 */
    uint32_t lambda_key_count;           /* 0: λ is constant (`lambda`) */
    mer_keyframe lambda_keys[MER_KEYS_MAX];
    uint32_t eta_key_count;              /* 0: η is constant (`eta`) */
    mer_keyframe eta_keys[MER_KEYS_MAX];
} mer_schedule;

typedef struct mer_params {
    /* models */
    uint32_t model;           /* mer_model_kind; default MER_MODEL_P09; set by name with mer_model_parse */
    uint32_t environment;     /* mer_env_kind; default MER_ENV_SHADOW */
    uint32_t fate;            /* mer_fate_kind; default MER_FATE_BH */

    /* geometry of growth */
    float internode_length;   /* l0, world units per unit of resource v/n; 1; (0, 100] */
    uint32_t max_shoot;       /* cap on n = ⌊v⌋ metamers per shoot per step; 16; 1..1000 */

    /* space colonization, P09 §4.1 */
    float rho;                /* ρ, occupancy radius; 2 (internode lengths); (0, 100] */
    float theta;              /* θ, perception cone full angle, degrees; 90; (0, 360] */
    float r;                  /* r, perception distance; 4 (4 to 6); (0, 100] */
    float marker_cell;        /* edge of the marker grid cells; 4; [0.05, 1000] */

    /* shadow propagation, P09 §4.1 */
    float shadow_a;           /* a, shadow of one bud in its own voxel; 0.1; (0, 1000]. Q of a lone
                               * bud is C; a = 0.1 lets the 4 buds of a young seedling share a
                               * voxel (Q = 0.7) without starving it (0.2 stalls ~1 seed in 8) */
    float shadow_b;           /* b, attenuation per layer, Δs = a·b^(-q); 2; (1, 1000] */
    float shadow_c;           /* C, full exposure; 1; [0, 1e6] */
    uint32_t q_max;           /* q_max, shadow depth in layers; 6 (4 to 8); 0..32 */
    float voxel;              /* voxel edge; 1 (about one internode); [0.01, 1000] */
    uint32_t shadow_dir;      /* mer_shadow_dir; default MER_SHADOW_DIR_NEIGHBOUR */

    /* scene bounds: the marker and shadow grids cover this box */
    float bounds_min[3];      /* (-50, 0, -50) */
    float bounds_max[3];      /* (50, 100, 50) */
    float ground;             /* height of the ground plane; 0 */
    uint32_t ground_enabled;  /* shoots and markers stay above the ground; 1 */

    /* bud fate, P09 §4.2 */
    float alpha;              /* α, v_base = α·Q_base; 2 (Fig. 7); (0, 1e6] */
    float lambda;             /* λ, apical bias of BH; 0.5 (Fig. 7: 0.46..0.54); [0, 1] */
    float w_max;              /* w_max of the Fig. 8c weights; 1; (0, 1e6] */
    float w_min;              /* w_min; 0.006 (Fig. 9); (0, 1e6] */
    float kappa;              /* κ, fraction of the list over which w falls; 0.5 (Fig. 9); (0, 1] */
    uint32_t sylleptic;       /* 1: new lateral buds may grow in the step that made them; 0 */
    uint32_t sympodial;       /* 1: a terminal bud ends its shoot with a flower or abortion; 0 */
    uint32_t sympodial_abort; /* 1: that terminal bud aborts instead of flowering; 0 */

    /* new shoots, P09 §4.3 */
    float divergence;         /* phyllotactic divergence angle, degrees; 137.5; [0, 360] */
    uint32_t buds_per_node;   /* 1 (alternate/spiral) or 2 (opposite; decussate with divergence 90); 1 */
    float branch_angle;       /* branching angle between bud and parent internode, degrees; 45; [0, 180] */
    float xi;                 /* ξ, weight of the optimal growth direction V; 0.3; [0, 100] */
    float eta;                /* η, tropism weight, > 0 up, < 0 down; 0.05; [-100, 100] */

    /* shedding, P09 §4.4 */
    float shed_threshold;     /* shed a branch when its light per internode is below this; 0 = off; [0, 1e6] */

    /* pipe model, P09 §4.5 */
    float pipe_n;             /* n in d^n = d1^n + d2^n; 2.5 (2 to 3); [1, 10] */
    float leaf_diameter;      /* diameter of a leaf-bearing tip internode; 0.05; (0, 100] */

    /* space colonization of Runions, Lane & Prusinkiewicz 2007 (model "runions"):
     * attraction points are the markers; see lib/models/runions/runions.h */
    float d_i;                /* d_i, radius of influence; 6; (0, 1000] */
    float d_k;                /* d_k, kill distance; 2; (0, 1000], below d_i */
    float D;                  /* D, node length (distance between nodes); 1; (0, 100] */

    /* Perlin noise perturbing growth, for every model (the survey's §VII-A; see
     * lib/env/noise.h): improved noise, 3-D, its permutation shuffled from the seed */
    float noise_amplitude;    /* A; 0 = off: no scene changes at all; [0, 2] */
    float noise_scale;        /* frequency: noise cells per world unit; 0.2; (0, 100] */
    uint32_t noise_octaves;   /* fBm octaves; 3; 1..8 */
    uint32_t noise_targets;   /* MER_NOISE_* bits; 7 (directions, lengths, radii); 0..7 */

    /* L-systems, ABOP §1.5, §2.2: the turtle's defaults */
    float ls_delta;           /* δ, the angle of + - & ^ \ / without a parameter, degrees; 90; [0, 360] */
    float ls_step;            /* the step of F, f, G without a parameter; 1; (0, 1e4] */
    float ls_width;           /* the width before any !(w); 0: the pipe model's diameters where ! sets none; [0, 1e4] */
    float ls_width_scale;     /* diameter per unit of !(w) (cpfg widths are pixels); 1; (0, 1e4] */
    float ls_elasticity;      /* e, tropism susceptibility towards T = -y (ABOP §2.2); 0; [-10, 10] */
    uint32_t ls_blocking;     /* 1: the ground and obstacles stop a segment whose end they hold, and
                               * the rest of its branch, as they stop P09's shoots; 0 */

    /* guiding-vector trees of Xu & Mould 2015 (model "guiding"; the crown volume is
     * the marker volume below): see lib/models/guiding/guiding.h. One step is one
     * iteration. */
    float gv_density;         /* graph nodes per unit volume; 1; (0, 1000] */
    uint32_t gv_cones;        /* k cones of the Yao graph; 14; 4..64 */
    float gv_rotation;        /* δ, guiding-vector rotation at the first hop, degrees; 4; [0, 180] */
    float gv_rotation_falloff; /* δ(h) = δ·falloff^(h − 1); 1; [0, 2] */
    uint32_t gv_early_endpoints; /* endpoints of the first iteration (1: a trunk); 1; 1..100000 */
    uint32_t gv_endpoints;    /* endpoints of each later iteration; 200; 1..100000 */
    uint32_t gv_endpoints_total; /* endpoints over all iterations, each later one asking
                                    for its share of what is left (0: gv_endpoints each); 0; 0..1000000 */
    uint32_t gv_k_hops;       /* k, hops from the tree of the later endpoints' surface; 3; 1..1000 */
    float gv_t;               /* t, outermost fraction of those nodes; 0.5; (0, 1] */
    uint32_t gv_bound;        /* 1: later endpoints inside the crown volume only; 0 */
    uint32_t gv_iterations;   /* iterations (steps) that grow; 4; 1..1000 */
    float gv_epsilon;         /* ε of the edge cost |e|·(ε + (1 − g·ê)/2)^p; 0.05; (0, 10] */
    float gv_p;               /* p of that cost; 2; [0.1, 16] */

    /* initial scene: read by mer_scene_new only (set_params leaves the scene as it is) */
    uint32_t seedlings;       /* plants placed along x at creation; 1; 0..1000 */
    float seedling_spacing;   /* distance between them; 10; [0, 1e4] */
    uint32_t marker_volume;   /* mer_volume_kind of the initial markers; MER_VOLUME_ELLIPSOID */
    uint32_t marker_count;    /* initial markers (space colonization only); 20000; 0..20000000 */
    float marker_center[3];   /* (0, 12, 0) */
    float marker_size[3];     /* (10, 10, 10) */

    mer_schedule schedule;
} mer_params;

/* The defaults listed above. O(number of fields). */
mer_params mer_params_default(void);

/* Copies `in` to `out` (not NULL), turning NULL or an all-zero struct into the
 * defaults. Does not validate. */
void mer_params_resolve(const mer_params *in, mer_params *out);

/* Checks every field against its range and the cross-field rules (bounds_min <
 * bounds_max, grids not larger than MER_GRID_CELLS_MAX, `model` naming a model,
 * then the model's own: for P09 w_min <= w_max and keyframes in step order). `p` NULL or all-zero is valid. On failure fills `err` (may
 * be NULL) naming the field and the range. */
mer_result mer_params_validate(const mer_params *p, mer_error *err);

#define MER_GRID_CELLS_MAX (UINT32_C(64) * 1024 * 1024) /* voxels or marker cells */

/* Sets the scalar field `name` (as listed by mer_params_field_name, e.g. "lambda",
 * "bounds_min.y", "apical_off.1") to `value`, after checking its range; integer
 * fields need an integral value. `p` not NULL. Fills `err` on an unknown name or a
 * value out of range, and then leaves `p` unchanged. O(fields). */
mer_result mer_params_set(mer_params *p, const char *name, double value, mer_error *err);

/* Reads the scalar field `name` into `*value`. MER_ERR_INVALID if unknown. */
mer_result mer_params_get(const mer_params *p, const char *name, double *value, mer_error *err);

/* The number of named scalar fields, and the i-th one's name, paper symbol ("" if
 * none), and range. Names are static strings. i out of range gives NULL / 0. */
size_t mer_params_field_count(void);
const char *mer_params_field_name(size_t i);
const char *mer_params_field_symbol(size_t i);
void mer_params_field_range(size_t i, double *min, double *max);
/* The name of the growth model that reads the i-th field ("p09"), or "" when every
 * model does (bounds, grids, ground, pipe model, initial scene). NULL out of range. */
const char *mer_params_field_model(size_t i);
/* 1 if the i-th field bears on a scene of parameters `p` (resolved): the model
 * of `p` reads it (its own rows and every model's), and, for an optional effect
 * (Perlin noise), the effect is on (noise_amplitude > 0). Summaries list these. */
int mer_params_field_used(const mer_params *p, size_t i);

/* The model called `name` ("p09") into `*model` (mer_model_kind). MER_ERR_INVALID
 * naming the models there are when `name` is NULL or unknown. O(models). */
mer_result mer_model_parse(const char *name, uint32_t *model, mer_error *err);
/* The name of model `model`, a static string; NULL when there is no such model. */
const char *mer_model_name(uint32_t model);

/* Schedule evaluation at a (possibly fractional) step. `p` resolved (not NULL). */
float mer_params_lambda_at(const mer_params *p, uint32_t step);
float mer_params_eta_at(const mer_params *p, uint32_t step, uint32_t order);
/* 1 if axes of `order` are under apical control at `step`. */
int mer_params_apical_at(const mer_params *p, uint32_t step, uint32_t order);

/* Piecewise-linear interpolation through `n` keyframes sorted by step (clamped
 * outside them); returns `fallback` when n == 0. */
float mer_keyframes_eval(const mer_keyframe *keys, uint32_t n, float step, float fallback);

#ifdef __cplusplus
}
#endif

#endif
