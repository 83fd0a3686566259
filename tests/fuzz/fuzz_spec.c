/* meristem — libFuzzer harness: a session-create request body
 * ({"preset", "seed", "params", "scene"}) through merd_scene_from_spec. */
#include "config.h"

#include <stdlib.h>

#include <jansson.h>

#include "server/spec.h"
#include "tests/fuzz/fuzz_common.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    json_t *spec = json_loadb((const char *)data, size, JSON_REJECT_DUPLICATES, NULL);
    if (spec == NULL)
        return 0;
    merd_refusal why = {0};
    mer_scene *s = merd_scene_from_spec(spec, &fuzz_limits, &why);
    if (s == NULL)
        fuzz_check_refusal(&why);
    mer_scene_free(s);
    json_decref(spec);
    return 0;
}
