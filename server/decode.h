/* meristemd — decoding JSON requests: the field helpers that session creation
 * and edits share. Each checks one thing, and on failure fills a refusal that
 * names the field by its JSON path ("edits[2].center") and returns -1:
 * 400 unknown-field for a name not allowed, 422 missing-field, 422
 * invalid-field for a wrong type or shape, 422 out-of-range for a bad value.
 * `where` is the path of the object being read ("" at the top).
 */
#ifndef MERISTEMD_DECODE_H
#define MERISTEMD_DECODE_H

#include <stdbool.h>
#include <stdint.h>

#include <jansson.h>

#include <meristem/params.h>

#include "server/refusal.h"

/* The largest |x| of any coordinate or size a request may give. */
#define MERD_COORD_MAX 1e6

/* How a vector's refusals read. Creation and edits have always worded them
 * differently; both wordings are kept so replies stay as they were. */
typedef struct merd_vec3_words {
    const char *shape; /* "%s must be SHAPE" */
    const char *range; /* "%s must hold 3 numbers from RANGE" */
} merd_vec3_words;

extern const merd_vec3_words merd_words_spec, merd_words_edit;

/* Every key of `obj` must be one of `allowed` (NULL-terminated). The detail
 * says "unknown field 'k' in WHAT", with "; allowed: a, b" when `list`. */
int merd_only_fields(const json_t *obj, const char *const *allowed, const char *what,
                     const char *where, bool list, merd_refusal *why);

/* `v` as [x, y, z], each a number within ±MERD_COORD_MAX. `field` is its path. */
int merd_vec3(const json_t *v, const char *field, const merd_vec3_words *words, float out[3],
              merd_refusal *why);

/* The vector `key` of `obj` (edit wording); absent leaves `out` as it is,
 * which is a refusal only when `required`. */
int merd_get_vec3(const json_t *obj, const char *key, const char *where, bool required,
                  float out[3], merd_refusal *why);

/* The number `key` of `obj` within [lo, hi]; `fallback` when absent and not
 * `required`. */
int merd_get_number(const json_t *obj, const char *key, const char *where, double lo, double hi,
                    bool required, double fallback, double *out, merd_refusal *why);

/* The integer `key` of `obj` within [lo, hi]; `fallback` when absent and not
 * `required`. */
int merd_get_uint(const json_t *obj, const char *key, const char *where, uint64_t lo,
                  uint64_t hi, bool required, uint64_t fallback, uint64_t *out,
                  merd_refusal *why);

/* Sets named parameters from a JSON object onto `p` (which holds the base
 * values), checking names (400) and ranges (422); `where` prefixes field paths. */
int merd_params_from_json(const json_t *obj, mer_params *p, const char *where, merd_refusal *why);

#endif
