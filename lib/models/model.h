/* meristem — the growth-model interface (private to lib). A growth model (a
 * paradigm: P09's self-organizing trees, L-systems, later the inverse model) grows
 * the shared skeleton in the shared environment, one step (a season) at a time.
 * The scene owns the world and calls the model through its ops table; after the
 * model's step the scene updates the pipe model's diameters and counts the step.
 * An op a model has no use for is left NULL where its comment says it may be,
 * and its callers (scene.c, edit.c, ...) skip it; the others are required.
 *
 * Adding a model: a folder under lib/models/ with an ops table, a row in the
 * registry (models/registry.c), an entry in mer_model_kind (params.h), and its
 * parameters as rows of params.c's table tagged with a new MERP_ROWS_ group. A
 * test can run a model of its own without registering it: merp_scene_new_with
 * (scene_private.h). */
#ifndef MERISTEM_MODEL_H
#define MERISTEM_MODEL_H

#include <stddef.h>
#include <stdint.h>

#include <meristem/params.h>
#include <meristem/result.h>
#include <meristem/rng.h>
#include <meristem/scene.h>

#include "core/perlin.h"
#include "env/env.h"
#include "skeleton/skeleton.h"

/* What every model shares, lent to it for the length of one call. */
typedef struct merp_world {
    merp_skeleton *sk;   /* metamers, buds, diameters: what gets meshed */
    merp_env *env;       /* markers, shadow, obstacles, ground */
    mer_rng *rng;        /* the scene's one deterministic stream */
    const mer_params *p; /* the scene's parameters, resolved and valid */
    uint32_t step;       /* the step being grown (new nodes are born at it) */
    /* the scene's Perlin noise: a model passes each new internode's direction and
     * length through merp_noise_internode (env/noise.h) */
    const merp_perlin *noise;
} merp_world;

/* Each model's own state, defined in its folder. */
typedef struct merp_model merp_model;

typedef struct merp_model_ops {
    const char *name; /* "p09": what mer_model_parse reads and mer_model_name gives */
    /* The groups of rows of the parameter table (params.c) it reads besides the
     * world's: MERP_ROWS_* below; mer_params_field_model reports them. */
    uint32_t param_rows;
    /* The version of what `save` writes: a checkpoint names its model and this
     * number, and a load refuses any other (MER_ERR_FORMAT). Raise it whenever
     * save's bytes change, the layout of a struct it writes whole included. */
    uint32_t state_version;
    /* The checks across its fields that the table's ranges cannot express; `p` is
     * resolved and in range. May be NULL (nothing more to check). */
    mer_result (*validate)(const mer_params *p, mer_error *err);
    /* Its state for a new scene; the skeleton is still empty. */
    mer_result (*create)(const mer_params *p, merp_model **out, mer_error *err);
    /* New parameters, already valid; cannot fail once validated. May be NULL:
     * the model keeps nothing derived from them (it reads w->p in each call). */
    void (*set_params)(merp_model *m, const mer_params *p);
    /* One step (a season), whole: the model adds nodes and sets buds through the
     * skeleton, and asks the environment what the buds perceive. */
    mer_result (*step)(merp_model *m, const merp_world *w, mer_error *err);
    /* Nodes were removed or moved outside the model's step (prune, bend). May
     * be NULL: the model keeps nothing about the skeleton's nodes between steps
     * (or reads the edits from the skeleton at its next step). */
    void (*nodes_changed)(merp_model *m, const merp_world *w);
    /* Folds the model's own state into the scene hash `h`. */
    uint64_t (*hash)(const merp_model *m, uint64_t h);
    /* A deep copy of its state that grows on exactly as `m` would. MER_ERR_NOMEM.
     * May be NULL: scenes of the model cannot be cloned (MER_ERR_INVALID). */
    mer_result (*clone)(const merp_model *m, merp_model **out, mer_error *err);
    /* Its state into a checkpoint (scene_io.c), and a new state read back from
     * one, for a skeleton of `nodes` nodes: MER_ERR_FORMAT for damaged input,
     * MER_ERR_NOMEM. Both may be NULL: the model's scenes cannot be saved. */
    void (*save)(const merp_model *m, merp_bytes_out *out);
    mer_result (*load)(merp_bytes_in *in, uint32_t nodes, merp_model **out, mer_error *err);
    void (*free)(merp_model *m);
    /* A model defined by a text (an L-system's productions, an inverse model's
     * functions) takes it here, between steps: `len` bytes, not NUL-terminated.
     * The first definition sets the model up (and may grow the skeleton's first
     * nodes); a later one replaces the rules and keeps what has grown. A text
     * that does not parse is MER_ERR_INVALID with err->line and err->column set,
     * and changes nothing. It and the three ops below may be NULL: a model
     * without a definition (or without widths of its own). */
    mer_result (*set_definition)(merp_model *m, const merp_world *w, const char *text,
                                 size_t len, mer_error *err);
    /* The definition text it holds (NUL-terminated, owned by m), NULL when none. */
    const char *(*definition)(const merp_model *m, size_t *len);
    /* Up to `cap` warnings about that text into `out`; returns how many there
     * are (mer_scene_definition_warnings). May be NULL: never any. */
    size_t (*warnings)(const merp_model *m, mer_warning *out, size_t cap);
    /* After the pipe model's diameters (merp_pipe_update): sets the d^n of the
     * nodes whose width the model gives explicitly. */
    void (*diameters)(const merp_model *m, const merp_world *w);
    /* The length of node id's leaf when the model sizes leaves per node
     * (mer_node.leaf): > 0 a leaf, < 0 none. May be NULL: the mesher sizes them. */
    float (*leaf)(const merp_model *m, const merp_skeleton *sk, uint32_t id);
    /* A bend (mer_scene_bend_spread's node, axis, angle and spread, checked) is
     * about to be made: a model that rebuilds its tree records it to make it
     * again. MER_ERR_NOMEM refuses the bend. May be NULL. */
    mer_result (*bending)(merp_model *m, const merp_world *w, uint32_t node,
                          const float axis[3], float angle, uint32_t spread, mer_error *err);
    /* Up to `cap` named numbers about its state (mer_scene_model_stats). */
    size_t (*stats)(const merp_model *m, mer_model_stat *out, size_t cap);
    /* 1 when no further step will grow with the parameters `p` (its iterations
     * or derivation length are used up): a step that grew nothing then reports
     * MER_STALL_DONE. May be NULL: the model never stops by itself. */
    int (*finished)(const merp_model *m, const mer_params *p);
} merp_model_ops;

/* The row groups of the parameter table: a row read by every model, or only by
 * the models whose param_rows include its group. */
enum {
    MERP_ROWS_WORLD = 1u << 0,
    MERP_ROWS_P09 = 1u << 1,
    MERP_ROWS_RUNIONS = 1u << 2,
    MERP_ROWS_NOISE = 1u << 3, /* every model's, and only while noise_amplitude > 0 */
    MERP_ROWS_LSYSTEM = 1u << 4,
    MERP_ROWS_GUIDING = 1u << 5
};

/* The ops of model `kind` (mer_model_kind), or NULL when there is none. */
const merp_model_ops *merp_model_ops_of(uint32_t kind);

/* models/p09/p09.c */
extern const merp_model_ops merp_p09_ops;
/* models/runions/runions.c */
extern const merp_model_ops merp_runions_ops;
/* models/lsystem/model.c */
extern const merp_model_ops merp_lsystem_ops;
/* models/guiding/guiding.c */
extern const merp_model_ops merp_guiding_ops;
/* models/forest/forest.c */
extern const merp_model_ops merp_forest_ops;
/* models/inverse/inverse.c */
extern const merp_model_ops merp_inverse_ops;

#endif
