/* meristemd — the per-session edit journal: an append-only file of records,
 * each a little-endian u32 payload length, a u32 CRC-32 (zlib) of the payload,
 * then the payload (one JSON document). The first record describes how the
 * session was created; each later one is one accepted batch of edits.
 *
 * Durability: merd_journal_append returns only after the record is written and,
 * in MERD_FSYNC_ALWAYS mode, fsync'ed (the file, and the folder when the file was
 * created), so an acknowledged edit survives a crash or power cut. In
 * MERD_FSYNC_INTERVAL mode a record is written at once and flushed to disk by
 * merd_journal_sync, which meristemd calls every `interval` ms: a power cut (not
 * a crash of the daemon: written data is in the kernel) may lose the records
 * of the last interval.
 *
 * Torn tails and damage: a record that does not read whole (its header or
 * payload runs past the end of the file, or its checksum does not match) is a
 * torn tail only when nothing after it could have been written by us (no
 * whole record starts at any later byte) and it looks cut short: it runs past
 * the end of the file, or it holds NUL bytes (blocks a power cut left
 * unwritten; our payloads are JSON and never hold one). Replay drops a torn
 * tail and truncates the file there, so appends go on from the last whole
 * record. Anything else is damage: the file is left byte for byte as it is
 * and the open fails with MERD_JOURNAL_DAMAGED, so that no acknowledged record
 * after the damage is ever cut away. A torn record is never replayed in part.
 *
 * Only regular files are journals: a symbolic link (O_NOFOLLOW), a FIFO, a
 * device or a folder at the path is refused as MERD_JOURNAL_DAMAGED without
 * blocking and without touching what a link points to.
 */
#ifndef MERISTEMD_JOURNAL_H
#define MERISTEMD_JOURNAL_H

#include <stdbool.h>
#include <stddef.h>

typedef struct merd_journal merd_journal;

typedef enum merd_fsync_mode {
    MERD_FSYNC_ALWAYS = 0,   /* fsync before every append returns */
    MERD_FSYNC_INTERVAL = 1  /* fsync from merd_journal_sync */
} merd_fsync_mode;

#define MERD_JOURNAL_RECORD_MAX (64u << 20) /* bytes of one record's payload */
#define MERD_JOURNAL_ERROR_MAX 256

/* Creates `path` (which must not exist) with `first` as its first record.
 * NULL on failure, with the reason in `error` (MERD_JOURNAL_ERROR_MAX bytes). */
merd_journal *merd_journal_create(const char *path, const char *first, size_t size,
                                  merd_fsync_mode mode, char *error);

/* Called once per whole record, in order; returns 0 to go on, non-zero to stop
 * (then merd_journal_open fails with that record's number in `error`). */
typedef int (*merd_journal_record_fn)(void *ctx, size_t index, const char *payload, size_t size);

/* Why merd_journal_open failed, or that it did not. */
typedef enum merd_journal_fault {
    MERD_JOURNAL_SOUND = 0,        /* opened */
    MERD_JOURNAL_IO,               /* cannot read or write it now (errno, memory) */
    MERD_JOURNAL_DAMAGED,          /* not ours to cut: damage before a whole record,
                                      not a regular file, or a record `fn` refused */
    MERD_JOURNAL_TORN_CREATION     /* the whole file is a torn first record: a creation
                                      that was never acknowledged */
} merd_journal_fault;

typedef struct merd_journal_report {
    merd_journal_fault fault;
    size_t dropped;                /* bytes of a torn tail dropped */
} merd_journal_report;

/* Opens an existing journal, hands every whole record to `fn`, drops a torn
 * tail and returns the journal ready for appends. NULL on failure with the
 * reason in `error`. `report` (may be NULL) says what was dropped, or why the
 * open failed; a damaged file is left unchanged. Cost: reads the file once;
 * after damage, one look (and at most one CRC) per later byte. */
merd_journal *merd_journal_open(const char *path, merd_fsync_mode mode, merd_journal_record_fn fn,
                                void *ctx, merd_journal_report *report, char *error);

/* Removes the journal file at `path` durably: unlinks it and syncs its folder.
 * 0 (also when there was no file), or -1 with `error` filled. */
int merd_journal_unlink(const char *path, char *error);

/* Appends one record. 0 on success; -1 with `error` filled, and then the file
 * is cut back to where it was, so a failed append leaves no partial record. */
int merd_journal_append(merd_journal *j, const char *payload, size_t size, char *error);

/* Replaces the journal by one whose only record is `first`: written to
 * "<path>.tmp", flushed, renamed over the journal, the folder flushed, so a
 * crash leaves the old file or the new one, whole; appends go on in the new
 * one. Only for a caller who has every other record durably elsewhere (a
 * checkpoint). 0, or -1 with `error` filled (the old file then stays the
 * journal unless the rename was done). O(size). */
int merd_journal_compact(merd_journal *j, const char *first, size_t size, char *error);

/* Flushes appended records to disk (MERD_FSYNC_INTERVAL mode). 0 or -1. */
int merd_journal_sync(merd_journal *j);

/* The number of records in the journal, the creation record included. */
size_t merd_journal_records(const merd_journal *j);

/* Closes the file. With `remove` true, also deletes it. NULL is fine. */
void merd_journal_close(merd_journal *j, bool remove);

/* Writes all `n` bytes to `fd`, retrying short writes and EINTR: 0, or -1 with
 * errno set. Shared with the checkpoints. */
int merd_write_all(int fd, const void *bytes, size_t n);

/* fsyncs the folder that holds `path`: a new, renamed or removed name is durable
 * only once its folder is. 0, or -1 with errno set. */
int merd_sync_folder(const char *path);

#endif
