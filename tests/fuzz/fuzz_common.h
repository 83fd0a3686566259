/* meristem — what the libFuzzer harnesses share: the limits a fuzzed request
 * runs under (small, so that one input costs milliseconds) and a fresh small
 * scene to apply edits to. */
#ifndef MERISTEM_FUZZ_COMMON_H
#define MERISTEM_FUZZ_COMMON_H

#include <stdint.h>
#include <stdlib.h>

#include <meristem.h>

#include "server/edits.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* A request's limits, kept small: steps and markers are what cost time. */
static const merd_edit_limits fuzz_limits = {.max_steps = 3, .max_markers = 300};

/* A seedling grown two steps (a few nodes, some buds, markers left): every op
 * has something to act on. Aborts on failure, which is a bug. */
static inline mer_scene *fuzz_scene(void)
{
    mer_scene *s = NULL;
    if (mer_scene_new(NULL, 7, &s, NULL) != MER_OK ||
        mer_scene_step(s, 2, NULL, NULL, NULL, NULL, NULL) != MER_OK)
        abort();
    return s;
}

/* A refusal is the caller's fault (4xx) or a passing condition (503); a 500 is
 * a bug of ours. */
static inline void fuzz_check_refusal(const merd_refusal *why)
{
    if (why->status < 400 || why->status == 500 || why->status > 599)
        abort();
}

#endif
