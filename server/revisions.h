/* meristemd — a session's revisions: what each accepted batch was (its edits,
 * the step and the internodes after it) and a few recent states of the tree,
 * so that a revert or a past snapshot costs a copy or a short replay instead of
 * the whole journal.
 *
 * Any revision can be had again because the engine is deterministic: the state
 * at N is the creation request's scene with the batches 1..N replayed on it
 * (a batch that reverts replays by deriving its own target, which is earlier).
 * A derivation starts from the latest kept state at or before N: a recent state
 * in memory, else the session's checkpoint, else the creation. Not locked: the
 * session's `work` lock guards it.
 */
#ifndef MERISTEMD_REVISIONS_H
#define MERISTEMD_REVISIONS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <jansson.h>

#include <meristem.h>

#include "server/refusal.h"

/* States of the tree kept in memory per session (each costs a mer_scene_clone). */
#define MERD_REVISION_STATES 8

/* Bytes of past snapshots (GLB) kept per session, for scrubbing and animation. */
#define MERD_REVISION_GLB_BYTES ((size_t)48 << 20)

typedef struct merd_revisions merd_revisions;

/* What a derivation starts from when no recent state fits: the session's
 * creation request and its checkpoint file. Borrowed. */
typedef struct merd_revision_origin {
    const char *id;
    const json_t *spec;
    const char *checkpoint;
} merd_revision_origin;

/* NULL when out of memory. */
merd_revisions *merd_revisions_new(void);

void merd_revisions_free(merd_revisions *h);

/* Records revision `revision`: its edits (borrowed, a reference is kept; an
 * empty array for the creation), the step and the living internodes after it
 * (negative when unknown: a record restored from an older journal). Revisions
 * come in order; recording one already known replaces it (a journal replayed
 * again). 0, or -1 when out of memory. O(1) amortized. */
int merd_revisions_add(merd_revisions *h, uint64_t revision, const json_t *edits, int64_t step,
                       int64_t internodes);

/* One past the newest revision recorded. */
uint64_t merd_revisions_count(const merd_revisions *h);

/* The revision that first made the tree of `revision`: itself, or for a
 * batch that is one revert, its target's. A snapshot names it, so a revert
 * gives the GLB of its target byte for byte. */
uint64_t merd_revisions_tree(const merd_revisions *h, uint64_t revision);

/* {"revisions": [{revision, edits, step, internodes}...], "next_after": N|null}:
 * the revisions after `after` (all from 0 when `from_start`), oldest first, at
 * most `limit`; next_after is the `after` of the next page. New reference. */
json_t *merd_revisions_page(const merd_revisions *h, uint64_t after, bool from_start, size_t limit);

/* A new scene as it was at `revision` (the caller owns it). 0, or -1 with
 * `why`: 422 naming `field` when the revision is not one of the session's,
 * 503 when out of memory. Keeps the states it passes by for the next call.
 * Cost: a copy when a kept state is that revision; otherwise a replay of the
 * batches after the nearest kept state. */
int merd_revisions_scene(merd_revisions *h, const merd_revision_origin *origin, uint64_t revision,
                         const char *field, mer_scene **out, merd_refusal *why);

/* Takes over `scene`, the tree at `revision`, as a kept state (the least
 * recently used one goes). */
void merd_revisions_keep(merd_revisions *h, uint64_t revision, mer_scene *scene);

/* A past snapshot (GLB bytes) kept under `key` ("\"r{revision}-{options}\""):
 * a new reference, or NULL. */
struct merd_snapshot *merd_revisions_glb(merd_revisions *h, const char *key);

/* Keeps a reference to `snap` under `key`, dropping the oldest past snapshots
 * past MERD_REVISION_GLB_BYTES. */
void merd_revisions_glb_put(merd_revisions *h, const char *key, struct merd_snapshot *snap);

#endif
