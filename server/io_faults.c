/* meristemd — a disk that fills up, on request of the API tests (see io_hooks.h). */
#include "config.h"

#include <errno.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <unistd.h>

#include "server/io_hooks.h"

static atomic_long writes_left = -1;

/* write(2), except that the armed one fails as a full disk does, writing nothing. */
static ssize_t write_or_full(int fd, const void *bytes, size_t n)
{
    if (atomic_fetch_sub(&writes_left, 1) == 1) {
        errno = ENOSPC;
        return -1;
    }
    return write(fd, bytes, n);
}

void merd_io_faults_from_env(void)
{
    const char *n = getenv("MERISTEMD_TEST_FAIL_WRITE");
    long k = n != NULL ? strtol(n, NULL, 10) : 0;
    if (k <= 0)
        return;
    atomic_store(&writes_left, k);
    merd_io.write = write_or_full;
}
