/* meristem — JSON views of library values. */
#include "config.h"

#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "server/codec.h"

json_t *mer_json_float(float x)
{
    char text[32];
    for (int digits = 6; digits <= 9; digits++) {
        snprintf(text, sizeof text, "%.*g", digits, (double)x);
        if (strtof(text, NULL) == x)
            break;
    }
    return json_real(strtod(text, NULL));
}

json_t *mer_json_param(double v)
{
    if (v == (double)(json_int_t)v && v > -9007199254740992.0 && v < 9007199254740992.0)
        return json_integer((json_int_t)v);
    return mer_json_float((float)v);
}

static json_t *vec3(const float v[3])
{
    return json_pack("[o, o, o]", mer_json_float(v[0]), mer_json_float(v[1]), mer_json_float(v[2]));
}

json_t *mer_json_summary(const mer_scene *scene)
{
    mer_summary s;
    mer_scene_summary(scene, &s);
    char hash[17];
    snprintf(hash, sizeof hash, "%016" PRIx64, mer_scene_hash(scene));
    return json_pack("{s:i, s:i, s:i, s:i, s:i, s:i, s:o, s:o, s:o, s:o, s:{s:o, s:o}, s:s}",
                     "step", (json_int_t)s.step, "plants", (json_int_t)s.plants,
                     "internodes", (json_int_t)s.internodes, "buds", (json_int_t)s.buds,
                     "flowers", (json_int_t)s.flowers, "markers", (json_int_t)s.markers,
                     "height", mer_json_float(s.height), "crown_width", mer_json_float(s.crown_width),
                     "crown_base", mer_json_float(s.crown_base), "crown_depth", mer_json_float(s.crown_depth),
                     "bounds", "min", vec3(s.bbox_min), "max", vec3(s.bbox_max), "hash", hash);
}

int mer_color_mode_parse(const char *name)
{
    static const char *const names[] = {"none", "order", "light", "age"};
    for (int i = 0; i < 4; i++)
        if (strcmp(name, names[i]) == 0)
            return i;
    return -1;
}
