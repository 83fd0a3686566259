/* meristemd — the clocks: monotonic seconds for durations, Unix time for
 * deadlines that outlive the process (a session's time to live). */
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

/* Seconds since the Unix epoch (CLOCK_REALTIME). */
static inline double merd_wall_clock(void)
{
    struct timespec t;
    clock_gettime(CLOCK_REALTIME, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

#endif
