/* meristemd — sessions whose journals cannot be served: damaged in the middle,
 * not regular files, or not replayable. Such a journal is not ours to cut:
 * it is moved byte for byte into <data-dir>/quarantine/ (with a .reason file
 * beside it) and its session answers 503 until an operator decides. The set is
 * filled at start-up and as sessions are loaded, lazily (under its own lock). */
#ifndef MERISTEMD_QUARANTINE_H
#define MERISTEMD_QUARANTINE_H

#include <stdbool.h>
#include <stdio.h>

#include <jansson.h>

typedef struct merd_quarantine merd_quarantine;

#define MERD_QUARANTINE_REASON_MAX 256

/* An empty set for the data folder `data_dir` (borrowed). NULL when out of memory. */
merd_quarantine *merd_quarantine_new(const char *data_dir);
void merd_quarantine_free(merd_quarantine *q);

/* Lists the journals already in <data-dir>/quarantine/ (one log line for all).
 * Returns how many. */
long merd_quarantine_load(merd_quarantine *q, FILE *log);

/* Quarantines session `id` whose journal is <data-dir>/`name` for `reason`:
 * with `move`, renames the file (a link or FIFO too, never what it points to)
 * and the session's checkpoint, if any, into the quarantine folder without
 * replacing anything there, writes the
 * reason beside it and syncs both folders; without, leaves it in place (a
 * fault that may pass, such as a read error). Logs it loudly to `log`. 0, or
 * -1 if the file could not be moved (it is then left in place and still
 * quarantined). */
int merd_quarantine_add(merd_quarantine *q, const char *name, const char *id, const char *reason,
                        bool move, FILE *log);

/* Whether `id` is quarantined; if so its reason goes to `reason` (`n` bytes). */
bool merd_quarantine_find(merd_quarantine *q, const char *id, char *reason, size_t n);

/* Appends {"id", "state": "quarantined", "reason"} for each to `list`. */
void merd_quarantine_list(merd_quarantine *q, json_t *list);

#endif
