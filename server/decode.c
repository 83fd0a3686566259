/* meristemd — JSON field decoding shared by creation and edits (see decode.h). */
#include "config.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "server/decode.h"

const merd_vec3_words merd_words_spec = {"[x, y, z]", "-1e6 to 1e6"};
const merd_vec3_words merd_words_edit = {"an array of 3 numbers", "-1e+06 to 1e+06"};

int merd_only_fields(const json_t *obj, const char *const *allowed, const char *what,
                     const char *where, bool list, merd_refusal *why)
{
    const char *key;
    const json_t *value;
    json_object_foreach((json_t *)obj, key, value) {
        (void)value;
        bool ok = false;
        for (const char *const *a = allowed; *a != NULL && !ok; a++)
            ok = strcmp(*a, key) == 0;
        if (ok)
            continue;
        char f[MERD_FIELD_MAX];
        merd_path(f, sizeof f, where, key);
        char names[256] = "";
        for (const char *const *a = allowed; list && *a != NULL; a++)
            snprintf(names + strlen(names), sizeof names - strlen(names), "%s%s",
                     a == allowed ? "; allowed: " : ", ", *a);
        return merd_refuse(why, 400, "unknown-field", f, "unknown field '%s' in %s%s", key, what,
                           names);
    }
    return 0;
}

int merd_vec3(const json_t *v, const char *field, const merd_vec3_words *words, float out[3],
              merd_refusal *why)
{
    if (!json_is_array(v) || json_array_size(v) != 3)
        return merd_refuse(why, 422, "invalid-field", field, "%s must be %s", field, words->shape);
    for (size_t k = 0; k < 3; k++) {
        const json_t *x = json_array_get(v, k);
        // The bound also keeps a double past float's range from being cast.
        if (!json_is_number(x) || !isfinite(json_number_value(x)) ||
            fabs(json_number_value(x)) > MERD_COORD_MAX)
            return merd_refuse(why, 422, "out-of-range", field, "%s must hold 3 numbers from %s",
                               field, words->range);
        out[k] = (float)json_number_value(x);
    }
    return 0;
}

/* The field `key` of `obj`; NULL when absent, which is a refusal (returned
 * through *failed) only when it is required. */
static const json_t *field(const json_t *obj, const char *key, const char *where, bool required,
                           int *failed, merd_refusal *why)
{
    const json_t *v = json_object_get(obj, key);
    *failed = 0;
    if (v == NULL && required) {
        char f[MERD_FIELD_MAX];
        merd_path(f, sizeof f, where, key);
        *failed = merd_refuse(why, 422, "missing-field", f, "%s is required", f);
    }
    return v;
}

static int bad_type(merd_refusal *why, const char *where, const char *key, const char *want)
{
    char f[MERD_FIELD_MAX];
    merd_path(f, sizeof f, where, key);
    return merd_refuse(why, 422, "invalid-field", f, "%s must be %s", f, want);
}

int merd_get_vec3(const json_t *obj, const char *key, const char *where, bool required,
                  float out[3], merd_refusal *why)
{
    int failed;
    const json_t *v = field(obj, key, where, required, &failed, why);
    if (v == NULL)
        return failed;
    char f[MERD_FIELD_MAX];
    merd_path(f, sizeof f, where, key);
    return merd_vec3(v, f, &merd_words_edit, out, why);
}

int merd_get_number(const json_t *obj, const char *key, const char *where, double lo, double hi,
                    bool required, double fallback, double *out, merd_refusal *why)
{
    int failed;
    const json_t *v = field(obj, key, where, required, &failed, why);
    if (v == NULL) {
        *out = fallback;
        return failed;
    }
    if (!json_is_number(v))
        return bad_type(why, where, key, "a number");
    double x = json_number_value(v);
    if (!isfinite(x) || x < lo || x > hi) {
        char f[MERD_FIELD_MAX];
        merd_path(f, sizeof f, where, key);
        return merd_refuse(why, 422, "out-of-range", f, "%s must be from %g to %g, got %g", f, lo,
                           hi, x);
    }
    *out = x;
    return 0;
}

int merd_get_uint(const json_t *obj, const char *key, const char *where, uint64_t lo,
                  uint64_t hi, bool required, uint64_t fallback, uint64_t *out,
                  merd_refusal *why)
{
    int failed;
    const json_t *v = field(obj, key, where, required, &failed, why);
    if (v == NULL) {
        *out = fallback;
        return failed;
    }
    if (!json_is_integer(v))
        return bad_type(why, where, key, "an integer");
    json_int_t x = json_integer_value(v);
    if (x < 0 || (uint64_t)x < lo || (uint64_t)x > hi) {
        char f[MERD_FIELD_MAX];
        merd_path(f, sizeof f, where, key);
        return merd_refuse(why, 422, "out-of-range", f,
                           "%s must be an integer from %llu to %llu, got %lld", f,
                           (unsigned long long)lo, (unsigned long long)hi, (long long)x);
    }
    *out = (uint64_t)x;
    return 0;
}

int merd_params_from_json(const json_t *obj, mer_params *p, const char *where, merd_refusal *why)
{
    if (!json_is_object(obj))
        return merd_refuse(why, 422, "invalid-field", where,
                           "%s must be an object of name: number", where);
    const char *key;
    const json_t *value;
    json_object_foreach((json_t *)obj, key, value) {
        char f[MERD_FIELD_MAX];
        merd_path(f, sizeof f, where, key);
        double x;
        mer_error err;
        if (mer_params_get(p, key, &x, &err) != MER_OK)
            return merd_refuse(why, 400, "unknown-field", f,
                               "unknown parameter '%s'; GET /v1/presets lists them", key);
        if (!json_is_number(value))
            return merd_refuse(why, 422, "invalid-field", f, "%s must be a number", f);
        mer_result rc = mer_params_set(p, key, json_number_value(value), &err);
        if (rc != MER_OK) {
            snprintf(err.field, sizeof err.field, "%s", key); // the request's name for it
            return merd_refuse_lib(why, rc, &err, where);
        }
    }
    return 0;
}
