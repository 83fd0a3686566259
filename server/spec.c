/* meristemd — decoding a create request into a scene (see spec.h). */
#include "config.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <meristem.h>

#include "server/codec.h"
#include "server/decode.h"
#include "server/spec.h"

/* The largest seed: every integer a JSON number holds exactly. */
#define SEED_MAX ((json_int_t)((1ULL << 53) - 1))

static const struct {
    const char *name;
    uint32_t kind;
} volumes[] = {{"box", MER_VOLUME_BOX},           {"sphere", MER_VOLUME_SPHERE},
               {"ellipsoid", MER_VOLUME_ELLIPSOID}, {"cylinder", MER_VOLUME_CYLINDER},
               {"cone", MER_VOLUME_CONE}};

/* Every key of `obj` allowed; a creation refusal names the object, not the list. */
static int only(const json_t *obj, const char *const *allowed, const char *where, merd_refusal *why)
{
    return merd_only_fields(obj, allowed, where[0] ? where : "the session request", where, false,
                            why);
}

/* The triangles of a base64 glTF/GLB in a request (caller frees *xyz with
 * mer_gltf_free). A file the request carries is refused as content: 413 when
 * it holds too many triangles, invalid-gltf when it cannot be read. */
static int gltf_triangles(const json_t *v, const char *f, float **xyz, size_t *triangles,
                          merd_refusal *why)
{
    uint8_t *bytes = NULL;
    size_t size = 0;
    if (!json_is_string(v) || merd_base64_decode(json_string_value(v), &bytes, &size) != 0)
        return merd_refuse(why, 422, "invalid-field", f,
                           "%s must be a base64 string of a .glb, or of a .gltf with embedded buffers", f);
    mer_error err = {0};
    mer_result rc = mer_gltf_read_triangles(bytes, size, MER_MESH_TRIANGLES_MAX, xyz, triangles, &err);
    free(bytes);
    if (rc == MER_ERR_NOMEM)
        return merd_refuse_lib(why, rc, &err, f);
    if (rc != MER_OK)
        return merd_refuse(why, rc == MER_ERR_LIMIT ? 413 : 422, "invalid-gltf", f, "%s: %s", f,
                           err.message);
    return 0;
}

/* The glTF at `f` into the scene: an obstacle (`markers` 0), or that many
 * markers filling its inside. */
static int add_gltf(mer_scene *scene, const json_t *v, const char *f, uint32_t markers,
                    merd_refusal *why)
{
    float *xyz = NULL;
    size_t triangles = 0;
    if (gltf_triangles(v, f, &xyz, &triangles, why) != 0)
        return -1;
    mer_error err = {0};
    mer_result rc = markers == 0 ? mer_scene_add_mesh(scene, xyz, triangles, &err)
                                 : mer_scene_fill_mesh_markers(scene, xyz, triangles, markers, &err);
    mer_gltf_free(xyz);
    return rc == MER_OK ? 0 : merd_refuse_lib(why, rc, &err, f);
}

static int radius_of(const json_t *r, const char *g, float *out, merd_refusal *why)
{
    if (!json_is_number(r))
        return merd_refuse(why, 422, "invalid-field", g, "%s must be a number", g);
    // As a vector's bound: a double past float's range has no float to become.
    if (!(json_number_value(r) > 0.0 && json_number_value(r) <= MERD_COORD_MAX))
        return merd_refuse(why, 422, "out-of-range", g, "%s must be a number in (0, 1e6]", g);
    *out = (float)json_number_value(r);
    return 0;
}

/* {"min", "max"} of a box or {"center", "radius"} of a sphere at path `f`:
 * the same shape, a vector then a second value. */
static int add_solid(mer_scene *scene, const json_t *b, const char *f, bool sphere,
                     merd_refusal *why)
{
    static const char *const box_fields[] = {"min", "max", NULL};
    static const char *const sphere_fields[] = {"center", "radius", NULL};
    const char *const *fields = sphere ? sphere_fields : box_fields;
    if (!json_is_object(b))
        return merd_refuse(why, 422, "invalid-field", f, "%s must be {\"%s\", \"%s\"}", f,
                           fields[0], fields[1]);
    if (only(b, fields, f, why))
        return -1;
    char g[MERD_FIELD_MAX];
    float a[3], hi[3], radius = 0;
    merd_path(g, sizeof g, f, fields[0]);
    if (merd_vec3(json_object_get(b, fields[0]), g, &merd_words_spec, a, why))
        return -1;
    merd_path(g, sizeof g, f, fields[1]);
    const json_t *second = json_object_get(b, fields[1]);
    if (sphere ? radius_of(second, g, &radius, why)
               : merd_vec3(second, g, &merd_words_spec, hi, why))
        return -1;
    mer_error err = {0};
    mer_result rc = sphere ? mer_scene_add_sphere(scene, a, radius, &err)
                           : mer_scene_add_box(scene, a, hi, &err);
    return rc == MER_OK ? 0 : merd_refuse_lib(why, rc, &err, f);
}

static int add_obstacle(mer_scene *scene, const json_t *o, const char *w, merd_refusal *why)
{
    static const char *const kinds[] = {"box", "sphere", "gltf", NULL};
    if (!json_is_object(o) || json_object_size(o) != 1)
        return merd_refuse(why, 422, "invalid-field", w,
                           "%s must be {\"box\": {...}} or {\"sphere\": {...}}", w);
    if (only(o, kinds, w, why))
        return -1;
    char f[MERD_FIELD_MAX];
    const json_t *mesh = json_object_get(o, "gltf");
    if (mesh != NULL) {
        merd_path(f, sizeof f, w, "gltf");
        return add_gltf(scene, mesh, f, 0, why);
    }
    const json_t *box = json_object_get(o, "box");
    merd_path(f, sizeof f, w, box != NULL ? "box" : "sphere");
    return add_solid(scene, box != NULL ? box : json_object_get(o, "sphere"), f, box == NULL, why);
}

/* A marker volume: a shape ({"volume", "center", "size", "count"}) or the
 * inside of a triangle mesh ({"gltf", "count"}). */
static int fill_volume(mer_scene *scene, const json_t *m, const char *w, merd_refusal *why)
{
    static const char *const shape_fields[] = {"volume", "center", "size", "count", NULL};
    static const char *const mesh_fields[] = {"gltf", "count", NULL};
    if (!json_is_object(m))
        return merd_refuse(why, 422, "invalid-field", w, "%s must be an object", w);
    const json_t *mesh = json_object_get(m, "gltf");
    if (only(m, mesh != NULL ? mesh_fields : shape_fields, w, why))
        return -1;
    const json_t *count = json_object_get(m, "count");
    char f[MERD_FIELD_MAX];
    merd_path(f, sizeof f, w, "count");
    if (!json_is_integer(count) || json_integer_value(count) < 1 ||
        json_integer_value(count) > MERD_VOLUME_MARKERS_MAX)
        return merd_refuse(why, 422, "out-of-range", f, "%s must be an integer from 1 to %d", f,
                           MERD_VOLUME_MARKERS_MAX);
    uint32_t n = (uint32_t)json_integer_value(count);
    if (mesh != NULL) {
        merd_path(f, sizeof f, w, "gltf");
        return add_gltf(scene, mesh, f, n, why);
    }
    const json_t *v = json_object_get(m, "volume");
    uint32_t kind = 0;
    for (size_t i = 0; json_is_string(v) && i < sizeof volumes / sizeof volumes[0]; i++)
        if (strcmp(volumes[i].name, json_string_value(v)) == 0)
            kind = volumes[i].kind;
    merd_path(f, sizeof f, w, "volume");
    if (kind == 0)
        return merd_refuse(why, 422, "invalid-field", f,
                           "%s must be box, sphere, ellipsoid, cylinder or cone", f);
    float center[3], size[3];
    merd_path(f, sizeof f, w, "center");
    if (merd_vec3(json_object_get(m, "center"), f, &merd_words_spec, center, why))
        return -1;
    merd_path(f, sizeof f, w, "size");
    if (merd_vec3(json_object_get(m, "size"), f, &merd_words_spec, size, why))
        return -1;
    mer_error err = {0};
    mer_result rc = mer_scene_fill_markers(scene, kind, center, size, n, &err);
    return rc == MER_OK ? 0 : merd_refuse_lib(why, rc, &err, w);
}

static int add_plant(mer_scene *scene, const json_t *item, const char *w, merd_refusal *why)
{
    float base[3];
    if (merd_vec3(item, w, &merd_words_spec, base, why) != 0)
        return -1;
    mer_error err = {0};
    mer_result rc = mer_scene_add_plant(scene, base, NULL, &err);
    if (rc == MER_OK)
        return 0;
    // The plant is the field at fault; the detail names it too.
    mer_error plant = {.code = rc};
    merd_refuse_lib(why, rc, &plant, w);
    snprintf(why->detail, sizeof why->detail, "%s: %s", w, err.message);
    return -1;
}

/* The growth model, preset, seed and parameters of a request, checked: into *p
 * and *seed. The model defaults to P09, the preset's parameters' model. */
static int decode_params(const json_t *spec, mer_params *p, uint64_t *seed, merd_refusal *why)
{
    static const char *const fields[] = {"model", "preset", "seed", "params", "scene", "lsystem",
                                         "inverse", NULL};
    if (!json_is_object(spec))
        return merd_refuse(why, 422, "invalid-field", "body",
                           "the body must be a JSON object ({} for defaults)");
    if (only(spec, fields, "", why))
        return -1;
    const json_t *preset = json_object_get(spec, "preset");
    if (preset != NULL && !json_is_string(preset))
        return merd_refuse(why, 422, "invalid-field", "preset",
                           "preset must be a string (GET /v1/presets)");
    mer_error err = {0};
    if (mer_preset_params(preset ? json_string_value(preset) : "default", p, &err) != MER_OK)
        return merd_refuse(why, 422, "invalid-field", "preset",
                           "%s; GET /v1/presets lists them", err.message);
    const json_t *s = json_object_get(spec, "seed");
    if (s != NULL && (!json_is_integer(s) || json_integer_value(s) < 0 ||
                      json_integer_value(s) > SEED_MAX))
        return merd_refuse(why, 422, "out-of-range", "seed",
                           "seed must be an integer from 0 to 2^53 - 1");
    *seed = s != NULL ? (uint64_t)json_integer_value(s) : 0;
    const json_t *model = json_object_get(spec, "model");
    if (model != NULL && !json_is_string(model))
        return merd_refuse(why, 422, "invalid-field", "model", "model must be a string, e.g. \"p09\"");
    if (model != NULL && mer_model_parse(json_string_value(model), &p->model, &err) != MER_OK)
        return merd_refuse(why, 422, "invalid-field", "model", "%s", err.message);
    const json_t *params = json_object_get(spec, "params");
    return params != NULL ? merd_params_from_json(params, p, "params", why) : 0;
}

/* The "scene" object's parts, checked for shape: *plants, *obstacles, *markers
 * (each NULL when absent). */
static int decode_scene(const json_t *spec, const json_t **plants, const json_t **obstacles,
                        const json_t **markers, merd_refusal *why)
{
    static const char *const fields[] = {"plants", "markers", "obstacles", "sow", NULL};
    const json_t *sc = json_object_get(spec, "scene");
    if (sc != NULL && (!json_is_object(sc) || only(sc, fields, "scene", why)))
        return why->status ? -1
                           : merd_refuse(why, 422, "invalid-field", "scene", "scene must be an object");
    *plants = sc ? json_object_get(sc, "plants") : NULL;
    *obstacles = sc ? json_object_get(sc, "obstacles") : NULL;
    *markers = sc ? json_object_get(sc, "markers") : NULL;
    if (*plants != NULL && (!json_is_array(*plants) || json_array_size(*plants) > MER_PLANTS_MAX))
        return merd_refuse(why, 422, "invalid-field", "scene.plants",
                           "scene.plants must be an array of at most %u [x, y, z] bases",
                           MER_PLANTS_MAX);
    return 0;
}

/* A sown forest (scene.sow): its definition into text, and the parameters of
 * the forest scene (the world's rows; each plant grows by its own preset's). */
static int decode_sow(const json_t *spec, mer_params *p, uint64_t seed,
                      const merd_edit_limits *limits, char *text, size_t cap, merd_refusal *why)
{
    const json_t *sc = json_object_get(spec, "scene");
    const json_t *model = json_object_get(spec, "model");
    static const char *const alone[] = {"plants", "markers", "obstacles"};
    for (size_t i = 0; i < 3; i++)
        if (json_object_get(sc, alone[i]) != NULL)
            return merd_refuse(why, 422, "invalid-field", "scene.sow",
                               "scene.sow sows the plants and their markers; give it no scene.%s",
                               alone[i]);
    if (json_object_get(spec, "lsystem") != NULL || json_object_get(spec, "inverse") != NULL ||
        (model != NULL && p->model != MER_MODEL_FOREST))
        return merd_refuse(why, 422, "invalid-field", "scene.sow",
                           "a sown forest's plants take their models from scene.sow.presets: "
                           "give no model (or \"forest\"), lsystem or inverse");
    if (merd_sow_text(json_object_get(sc, "sow"), seed, limits, text, cap, why))
        return -1;
    p->model = MER_MODEL_FOREST;
    p->seedlings = 0;
    p->environment = MER_ENV_MARKERS; // markers live in the members: no shadow grid here
    p->marker_count = 0;
    return 0;
}

/* The markers a request starts with: the preset's and its volumes'. */
static int check_markers(const mer_params *p, const json_t *vols, const merd_edit_limits *limits,
                         merd_refusal *why)
{
    uint64_t total = p->environment == MER_ENV_MARKERS ? p->marker_count : 0;
    size_t i;
    const json_t *vol;
    json_array_foreach(vols, i, vol) {
        const json_t *c = json_object_get(vol, "count");
        if (json_is_integer(c) && json_integer_value(c) > 0)
            total += (uint64_t)json_integer_value(c);
    }
    if (total <= limits->max_markers)
        return 0;
    return merd_refuse(why, 422, "out-of-range", vols ? "scene.markers" : "params.marker_count",
                       "a session may start with at most %u markers (meristemd --max-markers); "
                       "this one asks for %llu", limits->max_markers, (unsigned long long)total);
}

/* Obstacles and marker volumes, when given, are arrays (checked before either is used). */
static int arrays(const json_t *obstacles, const json_t *markers, merd_refusal *why)
{
    const char *f = obstacles != NULL && !json_is_array(obstacles) ? "scene.obstacles"
                    : markers != NULL && !json_is_array(markers)   ? "scene.markers"
                                                                     : NULL;
    return f != NULL ? merd_refuse(why, 422, "invalid-field", f, "%s must be an array", f) : 0;
}

/* Adds each item of `list` (an array, or NULL) with `add`, naming it PREFIX[i]. */
static int add_each(mer_scene *scene, const json_t *list, const char *prefix,
                    int (*add)(mer_scene *, const json_t *, const char *, merd_refusal *),
                    merd_refusal *why)
{
    size_t i;
    const json_t *item;
    json_array_foreach(list, i, item) {
        char w[48];
        snprintf(w, sizeof w, "%s[%zu]", prefix, i);
        if (add(scene, item, w, why) != 0)
            return -1;
    }
    return 0;
}

/* The definition text of a request, into *text, *len and *key (the member that
 * gave it, "lsystem" or "inverse"): an L-system's source ("lsystem":
 * {"source"}), an inverse model's functions ("inverse": {"fset"}), else its
 * preset's (key NULL); *text NULL when it has none. */
static int decode_source(const json_t *spec, const char **text, size_t *len, const char **key,
                         merd_refusal *why)
{
    static const char *const ls_fields[] = {"source", NULL};
    static const char *const inv_fields[] = {"fset", NULL};
    const json_t *inv = json_object_get(spec, "inverse");
    const json_t *ls = inv != NULL ? inv : json_object_get(spec, "lsystem");
    const char *const *fields = inv != NULL ? inv_fields : ls_fields;
    const char *k = inv != NULL ? "inverse" : "lsystem";
    const char *member = inv != NULL ? "inverse.fset" : "lsystem.source";
    const char *shape = inv != NULL ? "{\"fset\": \"<.fset text>\"}" : "{\"source\": \"<cpfg text>\"}";
    *text = NULL;
    *len = 0;
    *key = NULL;
    if (inv != NULL && json_object_get(spec, "lsystem") != NULL)
        return merd_refuse(why, 422, "invalid-field", "lsystem",
                           "give lsystem or inverse, not both");
    if (ls == NULL) {
        const json_t *preset = json_object_get(spec, "preset");
        *text = preset != NULL ? mer_preset_definition(json_string_value(preset)) : NULL;
        *len = *text != NULL ? strlen(*text) : 0;
        return 0;
    }
    if (!json_is_object(ls))
        return merd_refuse(why, 422, "invalid-field", k, "%s must be %s", k, shape);
    if (only(ls, fields, k, why))
        return -1;
    const json_t *src = json_object_get(ls, fields[0]);
    if (!json_is_string(src))
        return merd_refuse(why, 422, src ? "invalid-field" : "missing-field", member,
                           "%s must be a string", member);
    if (json_string_length(src) > MERD_SOURCE_MAX)
        return merd_refuse(why, 422, "out-of-range", member, "%s may hold at most %d bytes",
                           member, MERD_SOURCE_MAX);
    *text = json_string_value(src);
    *len = json_string_length(src);
    *key = k;
    return 0;
}

/* Gives a scene its definition text: required for an L-system, optional for
 * the inverse model (the Populus by default), refused for the others and for
 * the other model's member. */
static int define(mer_scene *scene, const char *text, size_t len, const char *key,
                  merd_refusal *why)
{
    uint32_t model = mer_scene_params(scene)->model;
    if (model == MER_MODEL_INVERSE) {
        if (key != NULL && strcmp(key, "inverse") != 0)
            return merd_refuse(why, 422, "invalid-field", key,
                               "%s is for sessions of the model \"%s\"", key, key);
        mer_error err = {0};
        mer_result rc = text != NULL ? mer_scene_set_definition(scene, text, len, &err) : MER_OK;
        if (rc == MER_OK)
            return 0;
        if (strcmp(err.field, "definition") == 0)
            snprintf(err.field, sizeof err.field, "fset");
        return merd_refuse_lib(why, rc, &err, "inverse");
    }
    if (key != NULL && strcmp(key, "inverse") == 0)
        return merd_refuse(why, 422, "invalid-field", "inverse",
                           "inverse is for sessions of the model \"inverse\"");
    bool wants = model == MER_MODEL_LSYSTEM;
    if (text == NULL && !wants)
        return 0;
    if (text == NULL)
        return merd_refuse(why, 422, "missing-field", "lsystem.source",
                           "an lsystem session needs \"lsystem\": {\"source\": \"<cpfg text>\"} "
                           "or an L-system preset");
    if (!wants)
        return merd_refuse(why, 422, "invalid-field", "lsystem",
                           "lsystem is for sessions of the model \"lsystem\"");
    mer_error err = {0};
    mer_result rc = mer_scene_set_definition(scene, text, len, &err);
    if (rc == MER_OK)
        return 0;
    if (strcmp(err.field, "definition") == 0)
        snprintf(err.field, sizeof err.field, "source");
    return merd_refuse_lib(why, rc, &err, "lsystem");
}

mer_scene *merd_scene_from_spec(const json_t *spec, const merd_edit_limits *limits,
                                merd_refusal *why)
{
    mer_params p;
    uint64_t seed = 0;
    const json_t *plants = NULL, *obstacles = NULL, *markers = NULL;
    const char *source = NULL, *key = NULL;
    size_t source_len = 0;
    if (decode_params(spec, &p, &seed, why) || decode_scene(spec, &plants, &obstacles, &markers, why) ||
        decode_source(spec, &source, &source_len, &key, why))
        return NULL;
    if (plants != NULL)
        p.seedlings = 0;  // the given plants replace the preset's seedlings
    const json_t *sc = json_object_get(spec, "scene");
    const json_t *sow = sc != NULL ? json_object_get(sc, "sow") : NULL;
    char sown[512];
    if (sow != NULL && decode_sow(spec, &p, seed, limits, sown, sizeof sown, why))
        return NULL;
    if (sow == NULL && p.model == MER_MODEL_FOREST) {
        merd_refuse(why, 422, "missing-field", "scene.sow",
                    "a forest session needs \"scene\": {\"sow\": {...}}");
        return NULL;
    }
    mer_error err = {0};
    mer_result rc = mer_params_validate(&p, &err);
    if (rc != MER_OK) {
        merd_refuse_lib(why, rc, &err, "params");
        return NULL;
    }
    if (check_markers(&p, markers, limits, why))
        return NULL;
    mer_scene *scene = NULL;
    rc = mer_scene_new(&p, seed, &scene, &err);
    if (rc != MER_OK) {
        merd_refuse_lib(why, rc, &err, "params");
        return NULL;
    }
    if (sow != NULL) {
        if (merd_sow_define(scene, sown, why)) {
            mer_scene_free(scene);
            return NULL;
        }
        return scene;
    }
    // Obstacles first: plants are checked against them, and they clear the
    // markers filled after them.
    if (arrays(obstacles, markers, why) ||
        add_each(scene, obstacles, "scene.obstacles", add_obstacle, why) ||
        add_each(scene, plants, "scene.plants", add_plant, why) ||
        add_each(scene, markers, "scene.markers", fill_volume, why) ||
        define(scene, source, source_len, key, why)) {
        mer_scene_free(scene);
        return NULL;
    }
    return scene;
}
