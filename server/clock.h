/* meristemd — the one clock for durations: monotonic seconds. */
#ifndef MERISTEMD_CLOCK_H
#define MERISTEMD_CLOCK_H

#include <time.h>

/* Seconds on the monotonic clock (from an arbitrary origin): subtract two. */
static inline double merd_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

#endif
