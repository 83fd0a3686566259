/* meristem — libFuzzer harness: an edit request body through the daemon's
 * decoder and, when accepted, applied to a small scene; what it journals is
 * then replayed onto a fresh scene, which must come out identical (a journal
 * that does not rebuild what was acknowledged loses edits). */
#include "config.h"

#include <stdlib.h>

#include <jansson.h>

#include "server/edits.h"
#include "tests/fuzz/fuzz_common.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    json_t *body = json_loadb((const char *)data, size, JSON_REJECT_DUPLICATES, NULL);
    if (body == NULL)
        return 0;
    merd_batch *b = NULL;
    merd_refusal why = {0};
    if (merd_batch_decode(body, &fuzz_limits, &b, &why) != 0) {
        fuzz_check_refusal(&why);
        json_decref(body);
        return 0;
    }
    mer_scene *scene = fuzz_scene();
    merd_batch_outcome outcome;
    json_t *applied = NULL;
    if (merd_batch_apply(b, &scene, NULL, NULL, NULL, &outcome, &applied, &why) == 0) {
        mer_scene *again = fuzz_scene();
        merd_refusal why2 = {0};
        if (merd_batch_replay(applied, &again, NULL, &why2) != 0 ||
            mer_scene_hash(again) != mer_scene_hash(scene))
            abort();
        mer_scene_free(again);
    } else {
        fuzz_check_refusal(&why);
    }
    json_decref(applied);
    mer_scene_free(scene);
    merd_batch_free(b);
    json_decref(body);
    return 0;
}
