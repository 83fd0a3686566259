/* meristemd — edits: JSON in, checked, applied to a scene.
 *
 * Decoding checks everything that does not depend on the tree (ops, fields,
 * types, ranges, request limits) before anything is applied, so most refusals
 * cost nothing. What depends on the tree (is this node alive?) is found while
 * applying; the caller then restores the session from its journal, which makes
 * a batch all or none.
 */
#ifndef MERISTEMD_EDITS_H
#define MERISTEMD_EDITS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <jansson.h>

#include <meristem.h>

/* Why a request was refused: everything a problem+json body needs. */
typedef struct merd_refusal {
    unsigned status;  /* 400, 404, 409, 413, 415, 422, 429, 500, 503 */
    char slug[40];    /* urn:meristem:problem:SLUG */
    char field[96];   /* JSON path of the input at fault, or "" */
    char detail[400];
} merd_refusal;

/* Fills `why` and returns -1, for `return merd_refuse(...)`. */
int merd_refuse(merd_refusal *why, unsigned status, const char *slug, const char *field,
               const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 5, 6)))
#endif
    ;

/* Request limits, from meristemd's settings. */
typedef struct merd_edit_limits {
    uint32_t max_steps;      /* steps in one request */
    uint32_t max_markers;    /* markers one request may add (points, or a dab with its copies) */
} merd_edit_limits;

typedef struct merd_batch merd_batch;

/* Decodes a request body: one edit object or {"edits": [...]}. On success
 * *out (caller frees with merd_batch_free) holds the checked edits; on failure
 * `why` says what and where (400 for an unknown op or field, 422 for a wrong
 * type or value). `body` is borrowed. */
int merd_batch_decode(const json_t *body, const merd_edit_limits *limits, merd_batch **out,
                     merd_refusal *why);

void merd_batch_free(merd_batch *b);

/* How a batch went: steps done of those asked, and whether it stopped early. */
typedef struct merd_batch_outcome {
    uint32_t steps_done;
    uint32_t steps_asked;
    const char *interrupted;   /* NULL, "cancelled" or "time limit" */
} merd_batch_outcome;

/* Called between steps; returns non-zero to stop at this whole step. */
typedef int (*merd_batch_stop_fn)(void *ctx, uint32_t done, uint32_t total);

/* Applies the edits in order. Stops early, keeping whole steps, when `stop`
 * says so (cancel, time limit, internode limit); later edits are then not
 * applied. Returns 0, or -1 with `why` (the scene may then be partly changed:
 * the caller restores it). `*applied` (new reference) is the JSON of what was
 * applied, for the journal: the edits as given, a stopped step with the count
 * done, the edits after it left out. */
int merd_batch_apply(const merd_batch *b, mer_scene *scene, merd_batch_stop_fn stop, void *ctx,
                    merd_batch_outcome *outcome, json_t **applied, merd_refusal *why);

/* Decodes and applies a journaled `applied` array (replay): the same edits,
 * never stopped. 0, or -1 with `why`. */
int merd_batch_replay(const json_t *applied, mer_scene *scene, merd_refusal *why);

/* Sets named parameters from a JSON object onto `p` (which holds the base
 * values), checking names and ranges; `where` prefixes field paths. */
int merd_params_from_json(const json_t *obj, mer_params *p, const char *where, merd_refusal *why);

#endif
