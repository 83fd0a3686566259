/* meristemd — edits: JSON in, checked, applied to a scene.
 *
 * Decoding checks everything that does not depend on the tree (ops, fields,
 * types, ranges, request limits) before anything is applied, so most refusals
 * cost nothing. What depends on the tree (is this node alive?) the library
 * finds while applying; the caller then restores the session from its journal,
 * which makes a batch all or none. The ops themselves are one table
 * (edit_ops.c).
 */
#ifndef MERISTEMD_EDITS_H
#define MERISTEMD_EDITS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <jansson.h>

#include <meristem.h>

#include "server/refusal.h"

/* The most edits one {"edits": [...]} batch may hold. */
#define MERD_BATCH_EDITS_MAX 10000
/* The longest model definition (an L-system's source) a request may give. */
#define MERD_SOURCE_MAX (1 << 20)

/* Request limits, from meristemd's settings. */
typedef struct merd_edit_limits {
    uint32_t max_steps;      /* steps in one request */
    uint32_t max_markers;    /* markers one request may add (points, or a dab with its copies) */
    /* Decoding a journal record rather than a request: a field left out means
     * what it meant when the record was written (a bend's spread: 1), where a
     * request gets today's default, which is then written into its record. */
    bool journal;
} merd_edit_limits;

typedef struct merd_batch merd_batch;

/* Where a revert edit gets a past revision of the session (revisions.h). */
typedef struct merd_past {
    /* A new scene as it was at `revision`: 0, or -1 with `why` (422 naming
     * `field` when the revision is not the session's). */
    int (*scene_at)(void *ctx, uint64_t revision, const char *field, mer_scene **out,
                    merd_refusal *why);
    /* Takes over the scene a revert replaces when it is the session's last
     * accepted revision (the revert is the batch's first edit); NULL: freed. */
    void (*retire)(void *ctx, mer_scene *scene);
    void *ctx;
} merd_past;

/* Decodes a request body: one edit object or {"edits": [...]}. On success
 * *out (caller frees with merd_batch_free) holds the checked edits; on failure
 * `why` says what and where (400 for an unknown op or field, 422 for a wrong
 * type or value). `body` is borrowed. */
int merd_batch_decode(const json_t *body, const merd_edit_limits *limits, merd_batch **out,
                      merd_refusal *why);

void merd_batch_free(merd_batch *b);

/* A warning about an edit that was applied (a definition with unbalanced
 * brackets): the member it is about ("source", "edits[2].source"), and where in
 * that text. */
#define MERD_WARNINGS_MAX 8
typedef struct merd_edit_warning {
    char field[MERD_FIELD_MAX];
    mer_warning w;
} merd_edit_warning;

/* How a batch went: steps done of those asked, and whether it stopped early. */
typedef struct merd_batch_outcome {
    uint32_t steps_done;
    uint32_t steps_asked;
    /* NULL, or why it stopped: what the stop function said ("cancelled",
     * "time limit", "internode limit"). */
    const char *interrupted;
    /* The report of the last step the batch ran (mer_scene_step_report): its
     * `stall` says why that step grew nothing; MER_STALL_NONE when it grew or
     * the batch ran no step. */
    mer_step_report last_step;
    /* The applied edits' warnings, the first MERD_WARNINGS_MAX of them. */
    merd_edit_warning warnings[MERD_WARNINGS_MAX];
    uint32_t nwarnings;
} merd_batch_outcome;

/* Called between steps: NULL to go on, or why to stop at this whole step (a
 * static string, which becomes the outcome's `interrupted`). */
typedef const char *(*merd_batch_stop_fn)(void *ctx, uint32_t done, uint32_t total);

/* Applies the edits to `*scene` in order; a revert replaces `*scene` with the
 * tree of a past revision taken from `past` (NULL: reverts are refused). Stops early, keeping whole steps, when `stop`
 * says so; later edits are then not applied. Returns 0, or -1 with `why` (the
 * scene may then be partly changed: the caller restores it). `*applied` (new
 * reference) is the JSON of what was applied, for the journal: the edits as
 * given, a stopped step with the count done, the edits after it left out. */
int merd_batch_apply(const merd_batch *b, mer_scene **scene, const merd_past *past,
                     merd_batch_stop_fn stop, void *ctx, merd_batch_outcome *outcome,
                     json_t **applied, merd_refusal *why);

/* How a refusal of `b` halfway is undone. */
typedef enum merd_undo {
    /* One edit, one library call: a refused call changes nothing. */
    MERD_UNDO_NOTHING,
    /* One step edit: a copy would cost O(shadow voxels) before every step (a
     * 200³ grid is 32 MB: ~100 ms per edit while the tree is small), and a step
     * is refused only when out of memory or past the node limit; then the
     * session is rebuilt from its checkpoint and the journal records after it
     * (at most --checkpoint-every of them). */
    MERD_UNDO_REPLAY,
    /* Anything else: a copy of the scene (mer_scene_clone) taken before. */
    MERD_UNDO_COPY
} merd_undo;

merd_undo merd_batch_undo(const merd_batch *b);

/* Decodes and applies a journaled `applied` array (replay) to `*scene`: the
 * same edits, never stopped; reverts derive their revision from `past`. 0, or
 * -1 with `why`. */
int merd_batch_replay(const json_t *applied, mer_scene **scene, const merd_past *past,
                      merd_refusal *why);

#endif
