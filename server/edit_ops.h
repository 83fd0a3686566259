/* meristemd — the table of edit ops (private to edits.c and edit_ops.c).
 *
 * One row per op, as redis keeps its commands: the name a request gives, the
 * fields it allows, how it is decoded, how it is applied and which growth
 * models accept it. Dispatch and the "use one of ..." messages come from the
 * table, so a new op is a new row and its two functions.
 */
#ifndef MERISTEMD_EDIT_OPS_H
#define MERISTEMD_EDIT_OPS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <jansson.h>

#include <meristem.h>

#include "server/edits.h"

typedef struct merd_edit_op merd_edit_op;

/* One decoded edit; what an op reads of it depends on the op. */
typedef struct merd_edit {
    const merd_edit_op *op;
    const json_t *json;    /* the edit as given (borrowed from the body) */
    uint32_t count;        /* step */
    uint32_t node, bud;    /* prune, bend, brush constraint */
    float axis[3], angle;  /* bend */
    uint32_t spread;       /* bend: internodes the turn is spread over */
    float *points;         /* add_markers points: 3 × npoints, owned; NULL for a dab */
    size_t npoints;
    mer_brush brush;
    mer_symmetry symmetry;
    bool has_symmetry, constrain;
    mer_schedule schedule; /* set_apical_schedule: the parts named in sched_mask */
    unsigned sched_mask;
    const json_t *params;  /* set_params: the object */
    uint64_t revision;     /* revert */
    const char *source;    /* set_lsystem, set_functions: the text (borrowed from json,
                            * or `owned`) */
    char *owned;           /* set_functions given JSON functions: their .fset text, owned */
    size_t source_len;
} merd_edit;

/* What decoding one request sums over its edits, against its limits. */
typedef struct merd_decode_ctx {
    const merd_edit_limits *limits;
    uint64_t steps, markers;
} merd_decode_ctx;

/* Applying one edit: the scene, the edit's path, and the batch's stop check. */
typedef struct merd_apply_ctx {
    mer_scene *scene;           /* a revert replaces it */
    const merd_past *past;      /* where a revert finds past revisions; may be NULL */
    bool first;                 /* the batch's first edit: the scene is the last revision's */
    const char *where;          /* "edits[3]", or "" for a single edit */
    merd_batch_stop_fn stop;    /* may be NULL */
    void *stop_ctx;
    volatile int cancel;        /* set when `stop` said to stop */
    const char *stopped;        /* what `stop` said */
    uint32_t done;              /* steps the last step edit did */
    merd_batch_outcome *outcome; /* where an edit's warnings go */
} merd_apply_ctx;

/* Which growth models accept an op: bit k is mer_model_kind k (a session runs
 * one model; an op for another is refused when applied). */
enum {
    MERD_MODEL_P09 = 1u << MER_MODEL_P09,
    MERD_MODEL_RUNIONS = 1u << MER_MODEL_RUNIONS,
    MERD_MODEL_LSYSTEM = 1u << MER_MODEL_LSYSTEM,
    MERD_MODEL_INVERSE = 1u << MER_MODEL_INVERSE,
    MERD_MODEL_GUIDING = 1u << MER_MODEL_GUIDING,
    MERD_MODEL_FOREST = 1u << MER_MODEL_FOREST
};

/* Flags of an op. */
enum { MERD_OP_STEPS = 1u << 0 /* runs steps: counted in the outcome, may stop early */ };

struct merd_edit_op {
    const char *name;
    const char *const *fields; /* allowed fields (NULL-terminated); NULL: decode checks them */
    const char *what;          /* how refusals name an edit of this op: "a bend edit" */
    int (*decode)(const json_t *o, const char *w, merd_decode_ctx *c, merd_edit *e,
                  merd_refusal *why);
    int (*apply)(const merd_edit *e, merd_apply_ctx *c, merd_refusal *why);
    unsigned models;           /* MERD_MODEL_* */
    unsigned flags;            /* MERD_OP_* */
};

/* The op named `name`, or NULL. */
const merd_edit_op *merd_edit_op_find(const char *name);

/* Writes the ops' names as prose ("step, add_markers, ... or release") to
 * `out` (`n` bytes, truncated). */
void merd_edit_op_names(char *out, size_t n);

#endif
