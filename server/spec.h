/* meristemd — the create request: {"preset", "seed", "params", "scene"} in, a
 * scene out. Deterministic, so a journal's first record (the request as
 * given) rebuilds the same scene. */
#ifndef MERISTEMD_SPEC_H
#define MERISTEMD_SPEC_H

#include <jansson.h>

#include <meristem/scene.h>

#include "server/edits.h"
#include "server/refusal.h"

/* The most markers one marker volume of a request may hold. */
#define MERD_VOLUME_MARKERS_MAX 2000000

/* Builds the scene `spec` (borrowed) describes: preset, seed and parameters,
 * then obstacles, plants and marker volumes, in that order (plants are checked
 * against obstacles, and obstacles clear the markers filled after them).
 * `limits->max_markers` bounds the markers it starts with. NULL with `why`
 * filled on a refusal (400 unknown field, 413 a glTF too large, 422 a wrong
 * value, 409 a limit of the scene, 503 out of memory). */
/* spec_sow.c: "scene": {"sow": {...}} (borrowed) checked and written as the
 * forest model's definition into text (cap bytes; 512 hold any), the sow's
 * seed defaulting to `seed`: 0, or -1 with `why` (422). */
int merd_sow_text(const json_t *sow, uint64_t seed, const merd_edit_limits *limits, char *text,
                  size_t cap, merd_refusal *why);
/* Sows the forest of `text` in `scene` (a forest scene): 0, or -1 with `why`:
 * 422 naming how many plants fit when fewer than the count do. */
int merd_sow_define(mer_scene *scene, const char *text, merd_refusal *why);

mer_scene *merd_scene_from_spec(const json_t *spec, const merd_edit_limits *limits,
                                merd_refusal *why);

#endif
