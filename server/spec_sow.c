/* meristemd — a create request's "scene": {"sow": {...}}: a forest (spec.h). */
#include "config.h"

#include <inttypes.h>
#include <stdio.h>
#include <string.h>

#include <meristem.h>

#include "server/decode.h"
#include "server/spec.h"

#define SOW_PRESETS_MAX 16

/* area: [[x0, z0], [x1, z1]], into lo and hi. */
static int area_of(const json_t *a, float lo[2], float hi[2], merd_refusal *why)
{
    const char *f = "scene.sow.area";
    const json_t *p = json_array_get(a, 0), *q = json_array_get(a, 1);
    double v[4];
    for (int i = 0; i < 4; i++) {
        const json_t *c = json_array_get(i < 2 ? p : q, (size_t)(i % 2));
        v[i] = json_is_number(c) ? json_number_value(c) : 0.0;
        if (!json_is_array(a) || json_array_size(a) != 2 || !json_is_array(p) ||
            !json_is_array(q) || json_array_size(p) != 2 || json_array_size(q) != 2 ||
            !json_is_number(c))
            return merd_refuse(why, 422, "invalid-field", f, "%s must be [[x0, z0], [x1, z1]]", f);
        if (!(v[i] >= -MERD_COORD_MAX && v[i] <= MERD_COORD_MAX))
            return merd_refuse(why, 422, "out-of-range", f, "%s: coordinates within ±1e6", f);
    }
    for (int a2 = 0; a2 < 2; a2++) {
        lo[a2] = (float)(v[a2] < v[a2 + 2] ? v[a2] : v[a2 + 2]);
        hi[a2] = (float)(v[a2] < v[a2 + 2] ? v[a2 + 2] : v[a2]);
    }
    return 0;
}

/* The presets' names, each known, and the markers they start with: into *markers. */
static int presets_of(const json_t *list, uint32_t count, const char **names, size_t *n,
                      uint64_t *markers, merd_refusal *why)
{
    const char *f = "scene.sow.presets";
    if (!json_is_array(list) || json_array_size(list) < 1 || json_array_size(list) > SOW_PRESETS_MAX)
        return merd_refuse(why, 422, "invalid-field", f,
                           "%s must be an array of 1 to %d preset names (GET /v1/presets)", f,
                           SOW_PRESETS_MAX);
    *n = json_array_size(list);
    *markers = 0;
    for (size_t i = 0; i < *n; i++) {
        char g[48];
        snprintf(g, sizeof g, "%s[%zu]", f, i);
        const json_t *v = json_array_get(list, i);
        mer_params p;
        mer_error err = {0};
        if (!json_is_string(v) || strlen(json_string_value(v)) > 63 ||
            strspn(json_string_value(v), "abcdefghijklmnopqrstuvwxyz0123456789-._") !=
                strlen(json_string_value(v)) ||
            mer_preset_params(json_string_value(v), &p, &err) != MER_OK)
            return merd_refuse(why, 422, "invalid-field", g,
                               "%s must name a preset; GET /v1/presets lists them", g);
        names[i] = json_string_value(v);
        uint64_t plants = (count + *n - 1 - i) / *n; /* round-robin: plant k gets k mod n */
        if (p.environment == MER_ENV_MARKERS && p.marker_volume != MER_VOLUME_NONE)
            *markers += plants * p.marker_count;
    }
    return 0;
}

int merd_sow_text(const json_t *sow, uint64_t seed, const merd_edit_limits *limits, char *text,
                  size_t cap, merd_refusal *why)
{
    static const char *const fields[] = {"area", "count", "min_distance", "presets", "seed", NULL};
    if (!json_is_object(sow))
        return merd_refuse(why, 422, "invalid-field", "scene.sow",
                           "scene.sow must be {\"area\", \"count\", \"min_distance\", \"presets\", \"seed\"}");
    if (merd_only_fields(sow, fields, "scene.sow", "scene.sow", false, why))
        return -1;
    for (int i = 0; i < 4; i++)
        if (json_object_get(sow, fields[i]) == NULL)
            return merd_refuse(why, 422, "missing-field", "scene.sow", "scene.sow needs %s",
                               fields[i]);
    float lo[2] = {0, 0}, hi[2] = {0, 0};
    if (area_of(json_object_get(sow, "area"), lo, hi, why))
        return -1;
    const json_t *c = json_object_get(sow, "count"), *r = json_object_get(sow, "min_distance");
    if (!json_is_integer(c) || json_integer_value(c) < 1 || json_integer_value(c) > MER_PLANTS_MAX)
        return merd_refuse(why, 422, "out-of-range", "scene.sow.count",
                           "scene.sow.count must be an integer from 1 to %u", MER_PLANTS_MAX);
    if (!json_is_number(r) || !(json_number_value(r) > 0.0 && json_number_value(r) <= MERD_COORD_MAX))
        return merd_refuse(why, 422, "out-of-range", "scene.sow.min_distance",
                           "scene.sow.min_distance must be a number in (0, 1e6]");
    const json_t *s = json_object_get(sow, "seed");
    if (s != NULL && (!json_is_integer(s) || json_integer_value(s) < 0 ||
                      json_integer_value(s) > (json_int_t)((1ULL << 53) - 1)))
        return merd_refuse(why, 422, "out-of-range", "scene.sow.seed",
                           "scene.sow.seed must be an integer from 0 to 2^53 - 1");
    uint32_t count = (uint32_t)json_integer_value(c);
    const char *names[SOW_PRESETS_MAX];
    size_t n = 0;
    uint64_t markers = 0;
    if (presets_of(json_object_get(sow, "presets"), count, names, &n, &markers, why))
        return -1;
    if (markers > limits->max_markers)
        return merd_refuse(why, 422, "out-of-range", "scene.sow.count",
                           "a session may start with at most %u markers (meristemd --max-markers); "
                           "these plants' presets ask for %llu", limits->max_markers,
                           (unsigned long long)markers);
    int at = snprintf(text, cap, "area %.9g %.9g %.9g %.9g\ncount %" PRIu32 "\nmin_distance %.9g\n"
                      "seed %" PRIu64 "\npresets", (double)lo[0], (double)lo[1], (double)hi[0],
                      (double)hi[1], count, (double)(float)json_number_value(r),
                      s != NULL ? (uint64_t)json_integer_value(s) : seed);
    for (size_t i = 0; i < n && at > 0 && (size_t)at < cap; i++)
        at += snprintf(text + at, cap - (size_t)at, " %s", names[i]);
    if (at <= 0 || (size_t)at + 2 > cap)
        return merd_refuse(why, 422, "invalid-field", "scene.sow", "scene.sow is too long");
    memcpy(text + at, "\n", 2);
    return 0;
}

int merd_sow_define(mer_scene *scene, const char *text, merd_refusal *why)
{
    mer_error err = {0};
    mer_result rc = mer_scene_set_definition(scene, text, strlen(text), &err);
    if (rc == MER_OK)
        return 0;
    char f[MERD_FIELD_MAX];
    merd_path(f, sizeof f, "scene.sow", err.field[0] && strcmp(err.field, "definition") != 0
                                            ? err.field : "");
    if (rc == MER_ERR_LIMIT) // the area holds fewer plants at this spacing
        return merd_refuse(why, 422, "out-of-range", f, "%s: %s", f, err.message);
    err.field[0] = '\0';
    return merd_refuse_lib(why, rc, &err, f);
}
