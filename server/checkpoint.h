/* meristemd — checkpoints: a session's whole scene at a revision, in a file
 * beside its journal (<id>.checkpoint), so that restore replays only the
 * journal's records after it. The file is the session id and the revision
 * (with their own digest) before mer_scene_save's bytes (with theirs). */
#ifndef MERISTEMD_CHECKPOINT_H
#define MERISTEMD_CHECKPOINT_H

#include <stdbool.h>
#include <stdint.h>

#include <meristem.h>

/* Writes the checkpoint of session `id` at `revision` to `path`: to a temporary
 * name, flushed (when `sync`), renamed over `path`, the folder flushed, so a
 * crash leaves the old checkpoint or the new one, whole. 0, or -1 with a reason
 * in `error` (MERD_JOURNAL_ERROR_MAX bytes). O(scene). */
int merd_checkpoint_write(const char *path, const char *id, uint64_t revision,
                          const mer_scene *scene, bool sync, char *error);

/* The scene of the checkpoint at `path` if it is session `id`'s and whole, and
 * its revision in `*revision`; NULL with a reason in `error` otherwise (no file
 * is a reason too). Never trusts the file: mer_scene_load checks it all. */
mer_scene *merd_checkpoint_read(const char *path, const char *id, uint64_t *revision, char *error);

#endif
