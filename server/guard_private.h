/* meristemd — the connection guard's insides, for its unit test. */
#ifndef MERISTEMD_GUARD_PRIVATE_H
#define MERISTEMD_GUARD_PRIVATE_H

#include <stddef.h>

#include "server/guard.h"

/* Cuts every connection not in a request whose deadline (on merd_now's clock)
 * is past at `now`, as the sweeping thread does twice a second. Returns how
 * many it cut. O(listed connections). */
size_t merd_guard_sweep(merd_guard *g, double now);

#endif
