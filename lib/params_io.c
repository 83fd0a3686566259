/* meristem — parameters in a checkpoint by name. The section (host byte order,
 * as the rest of a checkpoint):
 *   u32 count, then count entries, each
 *     u8 name length (1..MAX_NAME), the name (not NUL-terminated), u8 kind,
 *     kind NUMBER:    f64, a field of the parameter table (mer_params_field_name)
 *     kind KEYFRAMES: u32 n (<= MER_KEYS_MAX), n pairs of f32 (step, value), the
 *                     schedule named "lambda_keys" or "eta_keys"
 * Every field is written as a double: floats and 32-bit integers both convert
 * to it and back exactly, so a load restores the very bits that were saved.
 * A reader that does not know a name refuses the whole section: a parameter a
 * newer build added changes growth unless it holds its default, and the reader
 * cannot tell which value that is, so ignoring it could grow another tree than
 * the one the journal acknowledged. A name the section lacks takes its default:
 * new parameters are added with defaults that keep the behaviour before them
 * (noise_amplitude 0 turns Perlin noise off; the rows of a model are read by
 * that model alone). */
#include "config.h"

#include <assert.h>
#include <string.h>

#include "params_io.h"

#define MAX_NAME 64u
#define KIND_NUMBER 1u
#define KIND_KEYFRAMES 2u
#define ENTRIES_MAX 4096u

static void put_name(merp_bytes_out *out, const char *name, uint8_t kind)
{
    uint8_t len = (uint8_t)strlen(name);
    assert(len > 0 && len <= MAX_NAME);
    merp_put(out, &len, 1);
    merp_put(out, name, len);
    merp_put(out, &kind, 1);
}

static void put_keys(merp_bytes_out *out, const char *name, const mer_keyframe *keys, uint32_t n)
{
    put_name(out, name, KIND_KEYFRAMES);
    merp_put_u32(out, n);
    for (uint32_t i = 0; i < n; i++) {
        merp_put(out, &keys[i].step, sizeof keys[i].step);
        merp_put(out, &keys[i].value, sizeof keys[i].value);
    }
}

void merp_params_save(const mer_params *p, merp_bytes_out *out)
{
    assert(p != NULL && out != NULL);
    size_t n = mer_params_field_count();
    merp_put_u32(out, (uint32_t)n + 2);
    for (size_t i = 0; i < n; i++) {
        const char *name = mer_params_field_name(i);
        double v = 0.0;
        mer_result rc = mer_params_get(p, name, &v, NULL);
        assert(rc == MER_OK);
        (void)rc;
        put_name(out, name, KIND_NUMBER);
        merp_put(out, &v, sizeof v);
    }
    const mer_schedule *s = &p->schedule;
    put_keys(out, "lambda_keys", s->lambda_keys, s->lambda_key_count);
    put_keys(out, "eta_keys", s->eta_keys, s->eta_key_count);
}

/* The index of `name` among the table's fields, then the two schedules;
 * -1 when this build has no such parameter. */
static long index_of(const char *name)
{
    size_t n = mer_params_field_count();
    for (size_t i = 0; i < n; i++)
        if (strcmp(mer_params_field_name(i), name) == 0)
            return (long)i;
    if (strcmp(name, "lambda_keys") == 0)
        return (long)n;
    if (strcmp(name, "eta_keys") == 0)
        return (long)n + 1;
    return -1;
}

static mer_result load_keys(merp_bytes_in *in, const char *name, mer_params *p, mer_error *err)
{
    int lambda = strcmp(name, "lambda_keys") == 0;
    mer_keyframe *keys = lambda ? p->schedule.lambda_keys : p->schedule.eta_keys;
    uint32_t n = merp_get_u32(in);
    if (n > MER_KEYS_MAX)
        return mer_error_set(err, MER_ERR_FORMAT, name, "%u keyframes in a checkpoint",
                             (unsigned)n);
    for (uint32_t i = 0; i < n; i++) {
        merp_get(in, &keys[i].step, sizeof keys[i].step);
        merp_get(in, &keys[i].value, sizeof keys[i].value);
    }
    *(lambda ? &p->schedule.lambda_key_count : &p->schedule.eta_key_count) = n;
    return MER_OK;
}

/* One entry into `p`; `seen` marks the names already read. */
static mer_result load_entry(merp_bytes_in *in, mer_params *p, unsigned char *seen, mer_error *err)
{
    uint8_t len = 0, kind = 0;
    char name[MAX_NAME + 1];
    merp_get(in, &len, 1);
    if (len == 0 || len > MAX_NAME)
        in->bad = 1;
    merp_get(in, name, in->bad ? 0 : len);
    merp_get(in, &kind, 1);
    if (in->bad)
        return mer_error_set(err, MER_ERR_FORMAT, "params", "damaged parameters");
    name[len] = '\0';
    long i = index_of(name);
    if (i < 0 || memchr(name, '\0', len) != NULL)
        return mer_error_set(err, MER_ERR_FORMAT, "params",
                             "a parameter this build does not know: '%.64s' (a newer writer)", name);
    if (seen[i])
        return mer_error_set(err, MER_ERR_FORMAT, name, "the parameter '%s' given twice", name);
    seen[i] = 1;
    int number = (size_t)i < mer_params_field_count();
    if (kind != (number ? KIND_NUMBER : KIND_KEYFRAMES))
        return mer_error_set(err, MER_ERR_FORMAT, name, "the parameter '%s' of another kind", name);
    if (!number)
        return load_keys(in, name, p, err);
    double v = 0.0;
    merp_get(in, &v, sizeof v);
    if (!in->bad && mer_params_set(p, name, v, NULL) != MER_OK)
        return mer_error_set(err, MER_ERR_FORMAT, name, "the parameter '%s' out of its range", name);
    return MER_OK;
}

mer_result merp_params_load(merp_bytes_in *in, mer_params *p, mer_error *err)
{
    assert(in != NULL && p != NULL);
    *p = mer_params_default();
    unsigned char seen[ENTRIES_MAX] = {0};
    assert(mer_params_field_count() + 2 <= ENTRIES_MAX);
    // Names are known and each comes once, so more entries than names are
    // refused on reading the first one too many.
    uint32_t count = merp_get_u32(in);
    mer_result rc = MER_OK;
    for (uint32_t k = 0; k < count && rc == MER_OK && !in->bad; k++)
        rc = load_entry(in, p, seen, err);
    if (rc == MER_OK && in->bad)
        rc = mer_error_set(err, MER_ERR_FORMAT, "params", "damaged parameters");
    return rc;
}
