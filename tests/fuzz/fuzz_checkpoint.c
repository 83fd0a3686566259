/* meristem — libFuzzer harness: a checkpoint file loaded as meristemd restores
 * a session from it (server/checkpoint.c hands the bytes to mer_scene_load,
 * which must check everything and trust nothing).
 *
 * Input: a first byte choosing the mode, then the rest. Even: the rest is the
 * file, byte for byte (the header checks). Odd: the rest is the payload after
 * the header, which the harness heads with a correct length and digest, so
 * that inputs reach the decoding of parameters, skeleton, markers, shadow grid,
 * obstacles and the model's state.
 *
 * What must hold for a scene that loads: it saves again, and what it saves
 * loads to a scene with the same hash that saves to the same bytes; it clones
 * to a scene with that hash too. */
#include "config.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <meristem.h>

#include "lib/core/hash.h"
#include "tests/fuzz/fuzz_common.h"

#define HEADER 32 /* magic, version, byte order (16 bytes), payload length, digest */

/* The first 16 bytes of a checkpoint of this build, from a real one. */
static uint8_t head16[16];

static void learn_header(void)
{
    static int done;
    if (done)
        return;
    mer_scene *s = fuzz_scene();
    uint8_t *bytes = NULL;
    size_t size = 0;
    if (mer_scene_save(s, &bytes, &size, NULL) != MER_OK || size < HEADER)
        abort();
    memcpy(head16, bytes, sizeof head16);
    free(bytes);
    mer_scene_free(s);
    done = 1;
}

static void round_trip(const mer_scene *s)
{
    uint8_t *a = NULL, *b = NULL;
    size_t na = 0, nb = 0;
    mer_error err = {0};
    mer_result rc = mer_scene_save(s, &a, &na, &err);
    if (rc != MER_OK) {
        if (rc != MER_ERR_NOMEM)
            abort(); /* a loaded scene is one its model can save */
        return;
    }
    mer_scene *again = NULL;
    if (mer_scene_load(a, na, &again, &err) != MER_OK)
        abort(); /* what we saved we load */
    if (mer_scene_hash(again) != mer_scene_hash(s))
        abort();
    if (mer_scene_save(again, &b, &nb, &err) != MER_OK || nb != na || memcmp(a, b, na) != 0)
        abort();
    mer_scene *copy = NULL;
    if (mer_scene_clone(again, &copy, &err) == MER_OK && mer_scene_hash(copy) != mer_scene_hash(s))
        abort();
    mer_scene_free(copy);
    mer_scene_free(again);
    free(a);
    free(b);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size == 0)
        return 0;
    learn_header();
    const uint8_t *bytes = data + 1;
    size_t n = size - 1;
    uint8_t *framed = NULL;
    if (data[0] & 1) {
        framed = malloc(HEADER + n);
        if (framed == NULL)
            abort();
        uint64_t payload = n, digest = merp_fnv(MERP_FNV_OFFSET, data + 1, n);
        memcpy(framed, head16, sizeof head16);
        memcpy(framed + 16, &payload, 8);
        memcpy(framed + 24, &digest, 8);
        memcpy(framed + HEADER, data + 1, n);
        bytes = framed;
        n += HEADER;
    }
    mer_scene *s = NULL;
    mer_error err = {0};
    mer_result rc = mer_scene_load(bytes, n, &s, &err);
    if (rc != MER_OK) {
        if (s != NULL || (rc != MER_ERR_FORMAT && rc != MER_ERR_NOMEM))
            abort();
    } else {
        round_trip(s);
        mer_scene_free(s);
    }
    free(framed);
    return 0;
}
