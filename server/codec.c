/* meristem — JSON views of library values. */
#include "config.h"

#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "server/codec.h"

json_t *merd_json_float(float x)
{
    char text[32];
    for (int digits = 6; digits <= 9; digits++) {
        snprintf(text, sizeof text, "%.*g", digits, (double)x);
        if (strtof(text, NULL) == x)
            break;
    }
    return json_real(strtod(text, NULL));
}

json_t *merd_json_param(double v)
{
    if (v == (double)(json_int_t)v && v > -9007199254740992.0 && v < 9007199254740992.0)
        return json_integer((json_int_t)v);
    return merd_json_float((float)v);
}

static json_t *vec3(const float v[3])
{
    return json_pack("[o, o, o]", merd_json_float(v[0]), merd_json_float(v[1]), merd_json_float(v[2]));
}

#define MERD_MODEL_STATS_MAX 600 /* an L-system: 4 numbers and up to 512 module counts */

static json_t *summary_of(const mer_scene *scene);

/* The model's own numbers (mer_scene_model_stats) as an object; a name
 * "group.key" goes into a nested object "group". */
static json_t *model_stats(const mer_scene *scene)
{
    mer_model_stat *st = malloc(MERD_MODEL_STATS_MAX * sizeof *st);
    size_t n = st != NULL ? mer_scene_model_stats(scene, st, MERD_MODEL_STATS_MAX) : 0;
    json_t *o = json_object();
    for (size_t i = 0; i < n && i < MERD_MODEL_STATS_MAX; i++) {
        json_t *v = json_real(st[i].value);
        if (st[i].value == (double)(json_int_t)st[i].value)
            json_decref(v), v = json_integer((json_int_t)st[i].value);
        const char *dot = strchr(st[i].name, '.');
        if (dot == NULL) {
            json_object_set_new(o, st[i].name, v);
            continue;
        }
        char group[sizeof st[i].name];
        snprintf(group, sizeof group, "%.*s", (int)(dot - st[i].name), st[i].name);
        json_t *g = json_object_get(o, group);
        if (g == NULL)
            json_object_set_new(o, group, g = json_object());
        json_object_set_new(g, dot + 1, v);
    }
    free(st);
    return o;
}

json_t *merd_json_summary(const mer_scene *scene)
{
    json_t *j = summary_of(scene);
    // P09's summary is as it always was; another model names itself and adds
    // its own numbers under its name.
    uint32_t model = mer_scene_params(scene)->model;
    if (model != MER_MODEL_P09 && j != NULL) {
        json_object_set_new(j, "model", json_string(mer_model_name(model)));
        json_object_set_new(j, mer_model_name(model), model_stats(scene));
    }
    return j;
}

static json_t *summary_of(const mer_scene *scene)
{
    mer_summary s;
    mer_scene_summary(scene, &s);
    char hash[17];
    snprintf(hash, sizeof hash, "%016" PRIx64, mer_scene_hash(scene));
    return json_pack("{s:i, s:i, s:i, s:i, s:i, s:i, s:o, s:o, s:o, s:o, s:{s:o, s:o}, s:s}",
                     "step", (json_int_t)s.step, "plants", (json_int_t)s.plants,
                     "internodes", (json_int_t)s.internodes, "buds", (json_int_t)s.buds,
                     "flowers", (json_int_t)s.flowers, "markers", (json_int_t)s.markers,
                     "height", merd_json_float(s.height), "crown_width", merd_json_float(s.crown_width),
                     "crown_base", merd_json_float(s.crown_base), "crown_depth", merd_json_float(s.crown_depth),
                     "bounds", "min", vec3(s.bbox_min), "max", vec3(s.bbox_max), "hash", hash);
}

int merd_color_mode_parse(const char *name)
{
    static const char *const names[] = {"none", "order", "light", "age"};
    for (int i = 0; i < 4; i++)
        if (strcmp(name, names[i]) == 0)
            return i;
    return -1;
}

int merd_junctions_parse(const char *name)
{
    if (strcmp(name, "tubes") == 0)
        return MER_JUNCTIONS_TUBES;
    return strcmp(name, "implicit") == 0 ? MER_JUNCTIONS_IMPLICIT : -1;
}

int merd_compression_parse(const char *name)
{
    if (strcmp(name, "none") == 0)
        return MER_GLTF_UNCOMPRESSED;
    if (strcmp(name, "meshopt") == 0)
        return MER_GLTF_MESHOPT;
    return -1;
}

bool merd_param_in_schedule(const char *name)
{
    return strncmp(name, "apical_off.", 11) == 0 || strncmp(name, "eta_order_scale.", 16) == 0;
}

json_t *merd_json_params(const mer_params *p)
{
    json_t *o = json_object();
    for (size_t i = 0; i < mer_params_field_count(); i++) {
        const char *name = mer_params_field_name(i);
        double v;
        if (!mer_params_field_used(p, i))
            continue; /* another model's row, or noise while it is off */
        if (!merd_param_in_schedule(name) && mer_params_get(p, name, &v, NULL) == MER_OK)
            json_object_set_new(o, name, merd_json_param(v));
    }
    return o;
}

json_t *merd_json_schedule(const mer_schedule *s)
{
    json_t *apical = json_array(), *scale = json_array(), *lk = json_array(), *ek = json_array();
    for (int k = 0; k < MER_ORDERS_MAX; k++) {
        json_array_append_new(apical, s->apical_off[k] == MER_NEVER
                                          ? json_null()
                                          : json_integer((json_int_t)s->apical_off[k]));
        json_array_append_new(scale, merd_json_float(s->eta_order_scale[k]));
    }
    for (uint32_t k = 0; k < s->lambda_key_count; k++)
        json_array_append_new(lk, json_pack("[o, o]", merd_json_float(s->lambda_keys[k].step),
                                            merd_json_float(s->lambda_keys[k].value)));
    for (uint32_t k = 0; k < s->eta_key_count; k++)
        json_array_append_new(ek, json_pack("[o, o]", merd_json_float(s->eta_keys[k].step),
                                            merd_json_float(s->eta_keys[k].value)));
    return json_pack("{s:o, s:o, s:o, s:o}", "apical_off", apical, "eta_order_scale", scale,
                     "lambda_keys", lk, "eta_keys", ek);
}

int merd_base64_decode(const char *in, uint8_t **out, size_t *size)
{
    size_t n = strlen(in);
    while (n > 0 && in[n - 1] == '=')
        n--;
    if (n % 4 == 1)
        return -1;
    uint8_t *buf = malloc(n / 4 * 3 + 3);
    if (buf == NULL)
        return -1;
    size_t o = 0;
    uint32_t acc = 0;
    for (size_t i = 0; i < n; i++) {
        char c = in[i];
        int v = c >= 'A' && c <= 'Z' ? c - 'A'
              : c >= 'a' && c <= 'z' ? c - 'a' + 26
              : c >= '0' && c <= '9' ? c - '0' + 52
              : c == '+' ? 62 : c == '/' ? 63 : -1;
        if (v < 0) {
            free(buf);
            return -1;
        }
        acc = acc << 6 | (uint32_t)v;
        if (i % 4 == 3) {
            buf[o++] = (uint8_t)(acc >> 16);
            buf[o++] = (uint8_t)(acc >> 8);
            buf[o++] = (uint8_t)acc;
        }
    }
    if (n % 4 == 2) {
        buf[o++] = (uint8_t)(acc >> 4);
    } else if (n % 4 == 3) {
        buf[o++] = (uint8_t)(acc >> 10);
        buf[o++] = (uint8_t)(acc >> 2);
    }
    *out = buf;
    *size = o;
    return 0;
}

char *merd_json_body(const json_t *j)
{
    char *text = json_dumps(j, MERD_JSON_DUMP_FLAGS);
    size_t n = text ? strlen(text) : 0;
    char *body = text ? realloc(text, n + 2) : NULL;
    if (body == NULL) {
        free(text);
        return NULL;
    }
    body[n] = '\n';
    body[n + 1] = '\0';
    return body;
}
