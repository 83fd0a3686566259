/* meristemd — the system calls through which journals and checkpoints reach the
 * disk, as replaceable pointers: a unit test puts short writes, ENOSPC or EIO in
 * their way to check that no failure loses an acknowledged record. Nothing but
 * tests changes them. */
#ifndef MERISTEMD_IO_HOOKS_H
#define MERISTEMD_IO_HOOKS_H

#include <sys/types.h>

typedef struct merd_io_calls {
    ssize_t (*write)(int fd, const void *bytes, size_t n);
    int (*fsync)(int fd);
    int (*fdatasync)(int fd);
} merd_io_calls;

/* write(2), fsync(2), fdatasync(2) unless a test put others (journal.c). */
extern merd_io_calls merd_io;

/* For the API tests only, undocumented: with MERISTEMD_TEST_FAIL_WRITE=N in
 * the environment, the N-th write through merd_io fails with ENOSPC (a full
 * disk) and writes nothing; the others go through. Call before any journal
 * is written (io_faults.c). */
void merd_io_faults_from_env(void);

#endif
