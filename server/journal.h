/* meristemd — the per-session edit journal: an append-only file of records,
 * each a little-endian u32 payload length, a u32 CRC-32 (zlib) of the payload,
 * then the payload (one JSON document). The first record describes how the
 * session was created; each later one is one accepted batch of edits.
 *
 * Durability: mer_journal_append returns only after the record is written and,
 * in MER_FSYNC_ALWAYS mode, fsync'ed (the file, and the folder when the file was
 * created), so an acknowledged edit survives a crash or power cut. In
 * MER_FSYNC_INTERVAL mode a record is written at once and flushed to disk by
 * mer_journal_sync, which meristemd calls every `interval` ms: a power cut (not
 * a crash of the daemon: written data is in the kernel) may lose the records
 * of the last interval.
 *
 * Torn tails: a record whose length runs past the end of the file or whose
 * checksum does not match (a write cut short) ends the journal; replay drops it
 * and everything after it, and truncates the file there so appends go on from
 * the last whole record. A torn record is never replayed in part.
 */
#ifndef MERISTEMD_JOURNAL_H
#define MERISTEMD_JOURNAL_H

#include <stdbool.h>
#include <stddef.h>

typedef struct mer_journal mer_journal;

typedef enum mer_fsync_mode {
    MER_FSYNC_ALWAYS = 0,   /* fsync before every append returns */
    MER_FSYNC_INTERVAL = 1  /* fsync from mer_journal_sync */
} mer_fsync_mode;

#define MER_JOURNAL_RECORD_MAX (64u << 20) /* bytes of one record's payload */
#define MER_JOURNAL_ERROR_MAX 256

/* Creates `path` (which must not exist) with `first` as its first record.
 * NULL on failure, with the reason in `error` (MER_JOURNAL_ERROR_MAX bytes). */
mer_journal *mer_journal_create(const char *path, const char *first, size_t size,
                                mer_fsync_mode mode, char *error);

/* Called once per whole record, in order; returns 0 to go on, non-zero to stop
 * (then mer_journal_open fails with that record's number in `error`). */
typedef int (*mer_journal_record_fn)(void *ctx, size_t index, const char *payload, size_t size);

/* Opens an existing journal, hands every whole record to `fn`, drops a torn
 * tail (reporting the bytes dropped in *dropped, may be NULL) and returns the
 * journal ready for appends. NULL on failure with the reason in `error`. */
mer_journal *mer_journal_open(const char *path, mer_fsync_mode mode, mer_journal_record_fn fn,
                              void *ctx, size_t *dropped, char *error);

/* Appends one record. 0 on success; -1 with `error` filled, and then the file
 * is cut back to where it was, so a failed append leaves no partial record. */
int mer_journal_append(mer_journal *j, const char *payload, size_t size, char *error);

/* Flushes appended records to disk (MER_FSYNC_INTERVAL mode). 0 or -1. */
int mer_journal_sync(mer_journal *j);

/* The number of records in the journal, the creation record included. */
size_t mer_journal_records(const mer_journal *j);

/* Closes the file. With `remove` true, also deletes it. NULL is fine. */
void mer_journal_close(mer_journal *j, bool remove);

#endif
