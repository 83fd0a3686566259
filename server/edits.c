/* meristemd — decoding, checking and applying edits. */
#include "config.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "server/edits.h"

typedef enum edit_op {
    OP_STEP,
    OP_POINTS,
    OP_BRUSH,
    OP_PRUNE,
    OP_BEND,
    OP_SCHEDULE,
    OP_PARAMS,
    OP_RELEASE
} edit_op;

typedef struct edit {
    edit_op op;
    const json_t *json;   /* the edit as given (borrowed from the body) */
    uint32_t count;       /* step */
    uint32_t node, bud;   /* prune, bend, brush constraint */
    float axis[3], angle; /* bend */
    float *points;        /* add_markers points: 3 × npoints */
    size_t npoints;
    mer_brush brush;
    mer_symmetry symmetry;
    bool has_symmetry, constrain;
    mer_schedule schedule; /* set_apical_schedule: the parts named in sched_mask */
    unsigned sched_mask;
    const json_t *params;  /* set_params: the object */
} edit;

enum { SCHED_APICAL = 1, SCHED_ETA_SCALE = 2, SCHED_LAMBDA = 4, SCHED_ETA = 8 };

struct merd_batch {
    json_t *body;         /* a reference keeping `json` pointers valid */
    edit *edits;
    size_t count;
};

int merd_refuse(merd_refusal *why, unsigned status, const char *slug, const char *field,
               const char *fmt, ...)
{
    why->status = status;
    snprintf(why->slug, sizeof why->slug, "%s", slug);
    snprintf(why->field, sizeof why->field, "%s", field != NULL ? field : "");
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(why->detail, sizeof why->detail, fmt, ap);
    va_end(ap);
    return -1;
}

/* ------------------------------------------------------------ JSON fields */

/* A field path: "edits[2].count", or "count" for a single edit. */
static void append(char *out, size_t n, size_t *used, const char *text)
{
    while (*text != '\0' && *used + 1 < n)
        out[(*used)++] = *text++;
    out[*used] = '\0';
}

static void path(char *out, size_t n, const char *where, const char *key)
{
    size_t used = 0;
    out[0] = '\0';
    append(out, n, &used, where);
    if (where[0] != '\0' && key[0] != '\0')
        append(out, n, &used, ".");
    append(out, n, &used, key);
}

static int bad_type(merd_refusal *why, const char *where, const char *key, const char *want)
{
    char f[96];
    path(f, sizeof f, where, key);
    return merd_refuse(why, 422, "invalid-field", f, "%s must be %s", f, want);
}

/* The field `key` of `obj`; NULL when absent, which is a refusal (returned
 * through *failed) only when it is required. */
static const json_t *field(const json_t *obj, const char *key, const char *where, bool required,
                           int *failed, merd_refusal *why)
{
    const json_t *v = json_object_get(obj, key);
    *failed = 0;
    if (v == NULL && required) {
        char f[96];
        path(f, sizeof f, where, key);
        *failed = merd_refuse(why, 422, "missing-field", f, "%s is required", f);
    }
    return v;
}

static int get_number(const json_t *obj, const char *key, const char *where, double lo, double hi,
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
        char f[96];
        path(f, sizeof f, where, key);
        return merd_refuse(why, 422, "out-of-range", f, "%s must be from %g to %g, got %g", f, lo,
                          hi, x);
    }
    *out = x;
    return 0;
}

static int get_uint(const json_t *obj, const char *key, const char *where, uint64_t lo, uint64_t hi,
                    bool required, uint64_t fallback, uint64_t *out, merd_refusal *why)
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
        char f[96];
        path(f, sizeof f, where, key);
        return merd_refuse(why, 422, "out-of-range", f,
                          "%s must be an integer from %llu to %llu, got %lld", f,
                          (unsigned long long)lo, (unsigned long long)hi, (long long)x);
    }
    *out = (uint64_t)x;
    return 0;
}

/* A vector of 3 finite numbers within ±limit. */
static int get_vec3(const json_t *v, const char *field, double limit, float out[3], merd_refusal *why)
{
    if (!json_is_array(v) || json_array_size(v) != 3)
        return merd_refuse(why, 422, "invalid-field", field, "%s must be an array of 3 numbers", field);
    for (size_t k = 0; k < 3; k++) {
        const json_t *x = json_array_get(v, k);
        if (!json_is_number(x) || !isfinite(json_number_value(x)) ||
            fabs(json_number_value(x)) > limit)
            return merd_refuse(why, 422, "out-of-range", field,
                              "%s must hold 3 numbers from %g to %g", field, -limit, limit);
        out[k] = (float)json_number_value(x);
    }
    return 0;
}

static int get_vec3_field(const json_t *obj, const char *key, const char *where, bool required,
                          float out[3], merd_refusal *why)
{
    char f[96];
    path(f, sizeof f, where, key);
    const json_t *v = json_object_get(obj, key);
    if (v == NULL)
        return required ? merd_refuse(why, 422, "missing-field", f, "%s is required", f) : 0;
    return get_vec3(v, f, 1e6, out, why);
}

/* Every key of `obj` must be one of `allowed` (NULL-terminated): 400 otherwise. */
static int only_fields(const json_t *obj, const char *const *allowed, const char *what,
                       const char *where, merd_refusal *why)
{
    const char *key;
    const json_t *value;
    json_object_foreach((json_t *)obj, key, value) {
        (void)value;
        bool ok = false;
        for (const char *const *a = allowed; *a != NULL && !ok; a++)
            ok = strcmp(*a, key) == 0;
        if (!ok) {
            char f[96];
            path(f, sizeof f, where, key);
            char list[256] = "";
            for (const char *const *a = allowed; *a != NULL; a++)
                snprintf(list + strlen(list), sizeof list - strlen(list), "%s%s",
                         a == allowed ? "" : ", ", *a);
            return merd_refuse(why, 400, "unknown-field", f,
                              "unknown field '%s' in %s; allowed: %s", key, what, list);
        }
    }
    return 0;
}

/* ---------------------------------------------------------------- decoding */

static int decode_step(const json_t *o, const char *w, const merd_edit_limits *lim, edit *e,
                       uint64_t *steps, merd_refusal *why)
{
    static const char *const allowed[] = {"op", "count", NULL};
    uint64_t n;
    if (only_fields(o, allowed, "a step edit", w, why) ||
        get_uint(o, "count", w, 1, lim->max_steps, false, 1, &n, why))
        return -1;
    *steps += n;
    char f[96];
    path(f, sizeof f, w, "count");
    if (*steps > lim->max_steps)
        return merd_refuse(why, 422, "out-of-range", f,
                          "a request may step at most %u times (meristemd --max-steps), this one "
                          "asks for %llu", lim->max_steps, (unsigned long long)*steps);
    e->count = (uint32_t)n;
    return 0;
}

static int decode_symmetry(const json_t *s, const char *w, mer_symmetry *out, merd_refusal *why)
{
    static const char *const allowed[] = {"rotational", "center", "mirror", "tiles", "tile_step", NULL};
    if (!json_is_object(s))
        return merd_refuse(why, 422, "invalid-field", w, "%s must be an object", w);
    if (only_fields(s, allowed, "a symmetry", w, why))
        return -1;
    uint64_t n;
    if (get_uint(s, "rotational", w, 0, 64, false, 0, &n, why) ||
        get_vec3_field(s, "center", w, false, out->center, why))
        return -1;
    out->rotational = (uint32_t)n;
    const json_t *m = json_object_get(s, "mirror");
    if (m != NULL) {
        static const char *const mirror_fields[] = {"point", "normal", NULL};
        char mw[96];
        path(mw, sizeof mw, w, "mirror");
        if (!json_is_object(m))
            return merd_refuse(why, 422, "invalid-field", mw, "%s must be an object", mw);
        if (only_fields(m, mirror_fields, "a mirror", mw, why) ||
            get_vec3_field(m, "point", mw, false, out->mirror_point, why) ||
            get_vec3_field(m, "normal", mw, true, out->mirror_normal, why))
            return -1;
        out->mirror = 1;
    }
    const json_t *t = json_object_get(s, "tiles");
    if (t != NULL) {
        char tw[96];
        path(tw, sizeof tw, w, "tiles");
        if (!json_is_array(t) || json_array_size(t) != 2 || !json_is_integer(json_array_get(t, 0)) ||
            !json_is_integer(json_array_get(t, 1)))
            return merd_refuse(why, 422, "invalid-field", tw, "%s must be [nu, nv], two integers", tw);
        for (size_t k = 0; k < 2; k++) {
            json_int_t x = json_integer_value(json_array_get(t, k));
            if (x < 0 || x > 1024)
                return merd_refuse(why, 422, "out-of-range", tw, "%s holds integers from 0 to 1024", tw);
            out->tiles[k] = (uint32_t)x;
        }
        const json_t *st = json_object_get(s, "tile_step");
        char sw[96];
        path(sw, sizeof sw, w, "tile_step");
        if (!json_is_array(st) || json_array_size(st) != 2)
            return merd_refuse(why, 422, "invalid-field", sw,
                              "%s must be two lattice vectors [[x,y,z],[x,y,z]] when tiles is given", sw);
        for (size_t k = 0; k < 2; k++)
            if (get_vec3(json_array_get(st, k), sw, 1e6, out->tile_step[k], why))
                return -1;
    }
    return 0;
}

static int decode_markers(const json_t *o, const char *w, const merd_edit_limits *lim, edit *e,
                          uint64_t *markers, merd_refusal *why)
{
    const json_t *pts = json_object_get(o, "points");
    if (pts != NULL) {
        static const char *const allowed[] = {"op", "points", NULL};
        char f[96];
        path(f, sizeof f, w, "points");
        if (only_fields(o, allowed, "an add_markers edit with points", w, why))
            return -1;
        if (!json_is_array(pts))
            return merd_refuse(why, 422, "invalid-field", f, "%s must be an array of [x, y, z]", f);
        e->npoints = json_array_size(pts);
        *markers += e->npoints;
        if (*markers > lim->max_markers)
            return merd_refuse(why, 422, "out-of-range", f,
                              "a request may add at most %u markers (meristemd --max-markers), "
                              "this one adds %llu", lim->max_markers, (unsigned long long)*markers);
        e->points = malloc((e->npoints ? e->npoints : 1) * 3 * sizeof(float));
        if (e->points == NULL)
            return merd_refuse(why, 500, "internal", f, "out of memory for markers");
        for (size_t i = 0; i < e->npoints; i++) {
            char pf[128];
            snprintf(pf, sizeof pf, "%s[%zu]", f, i);
            if (get_vec3(json_array_get(pts, i), pf, 1e6, e->points + 3 * i, why))
                return -1;
        }
        e->op = OP_POINTS;
        return 0;
    }
    static const char *const allowed[] = {"op", "center", "radius", "pressure", "count",
                                          "symmetry", "constrain", NULL};
    if (only_fields(o, allowed, "an add_markers edit (give points, or a brush dab)", w, why))
        return -1;
    double radius, pressure;
    uint64_t count;
    if (get_vec3_field(o, "center", w, true, e->brush.center, why) ||
        get_number(o, "radius", w, 1e-3, 1000, true, 0, &radius, why) ||
        get_number(o, "pressure", w, 1e-3, 1, false, 0.5, &pressure, why) ||
        get_uint(o, "count", w, 1, 100000, false, 50, &count, why))
        return -1;
    e->brush.radius = (float)radius;
    e->brush.pressure = (float)pressure;
    e->brush.max_count = (uint32_t)count;
    const json_t *s = json_object_get(o, "symmetry");
    uint64_t copies = 1;
    if (s != NULL) {
        char sw[96];
        path(sw, sizeof sw, w, "symmetry");
        if (decode_symmetry(s, sw, &e->symmetry, why))
            return -1;
        e->has_symmetry = true;
        const mer_symmetry *y = &e->symmetry;
        copies = (y->rotational > 1 ? y->rotational : 1) * (y->mirror ? 2 : 1) *
                 (uint64_t)(y->tiles[0] > 1 ? y->tiles[0] : 1) * (y->tiles[1] > 1 ? y->tiles[1] : 1);
    }
    *markers += count * copies;
    char count_field[96];
    path(count_field, sizeof count_field, w, "count");
    if (*markers > lim->max_markers)
        return merd_refuse(why, 422, "out-of-range", count_field,
                          "a request may add at most %u markers (meristemd --max-markers); this "
                          "dab may add up to %llu with its symmetric copies",
                          lim->max_markers, (unsigned long long)*markers);
    const json_t *c = json_object_get(o, "constrain");
    if (c != NULL) {
        static const char *const cf[] = {"node", "bud", NULL};
        char cw[96];
        path(cw, sizeof cw, w, "constrain");
        uint64_t node, bud;
        if (!json_is_object(c))
            return merd_refuse(why, 422, "invalid-field", cw, "%s must be {\"node\", \"bud\"}", cw);
        if (only_fields(c, cf, "a constraint", cw, why) ||
            get_uint(c, "node", cw, 0, UINT32_MAX - 1, true, 0, &node, why) ||
            get_uint(c, "bud", cw, 0, 2, false, 0, &bud, why))
            return -1;
        e->node = (uint32_t)node;
        e->bud = (uint32_t)bud;
        e->constrain = true;
    }
    e->op = OP_BRUSH;
    return 0;
}

static int decode_node_edit(const json_t *o, const char *w, edit *e, merd_refusal *why)
{
    uint64_t node;
    if (get_uint(o, "node", w, 0, UINT32_MAX - 1, true, 0, &node, why))
        return -1;
    e->node = (uint32_t)node;
    return 0;
}

/* A keyframe list [[step, value], ...] in step order, at most MER_KEYS_MAX. */
static int decode_keys_into(const json_t *v, const char *f, double lo, double hi,
                            mer_keyframe *keys, uint32_t *count, merd_refusal *why)
{
    if (!json_is_array(v) || json_array_size(v) > MER_KEYS_MAX)
        return merd_refuse(why, 422, "invalid-field", f,
                          "%s must be an array of at most %d [step, value] pairs", f, MER_KEYS_MAX);
    *count = (uint32_t)json_array_size(v);
    for (size_t i = 0; i < *count; i++) {
        const json_t *k = json_array_get(v, i);
        if (!json_is_array(k) || json_array_size(k) != 2 || !json_is_number(json_array_get(k, 0)) ||
            !json_is_number(json_array_get(k, 1)))
            return merd_refuse(why, 422, "invalid-field", f, "%s[%zu] must be [step, value]", f, i);
        double step = json_number_value(json_array_get(k, 0)), value = json_number_value(json_array_get(k, 1));
        if (!(step >= 0 && step <= 1e6) || !(value >= lo && value <= hi))
            return merd_refuse(why, 422, "out-of-range", f,
                              "%s[%zu]: step must be from 0 to 1e6 and value from %g to %g", f, i, lo, hi);
        if (i > 0 && step <= (double)keys[i - 1].step)
            return merd_refuse(why, 422, "out-of-range", f, "%s must be in increasing step order", f);
        keys[i] = (mer_keyframe){(float)step, (float)value};
    }
    return 0;
}

static int decode_schedule(const json_t *o, const char *w, edit *e, merd_refusal *why)
{
    static const char *const allowed[] = {"op", "apical_off", "eta_order_scale", "lambda_keys",
                                          "eta_keys", NULL};
    if (only_fields(o, allowed, "a set_apical_schedule edit", w, why))
        return -1;
    char f[96];
    const json_t *v;
    if ((v = json_object_get(o, "apical_off")) != NULL) {
        path(f, sizeof f, w, "apical_off");
        if (!json_is_array(v) || json_array_size(v) == 0 || json_array_size(v) > MER_ORDERS_MAX)
            return merd_refuse(why, 422, "invalid-field", f,
                              "%s must be an array of 1 to %d steps (null: never), one per branch "
                              "order from the trunk", f, MER_ORDERS_MAX);
        size_t n = json_array_size(v);
        for (size_t k = 0; k < MER_ORDERS_MAX; k++) {
            // Orders past the list take its last entry, as the engine does.
            const json_t *x = json_array_get(v, k < n ? k : n - 1);
            if (json_is_null(x)) {
                e->schedule.apical_off[k] = MER_NEVER;
            } else if (json_is_integer(x) && json_integer_value(x) >= 0 &&
                       json_integer_value(x) < (json_int_t)MER_NEVER) {
                e->schedule.apical_off[k] = (uint32_t)json_integer_value(x);
            } else {
                return merd_refuse(why, 422, "out-of-range", f,
                                  "%s[%zu] must be a step (an integer from 0) or null for never", f,
                                  k < n ? k : n - 1);
            }
        }
        e->sched_mask |= SCHED_APICAL;
    }
    if ((v = json_object_get(o, "eta_order_scale")) != NULL) {
        path(f, sizeof f, w, "eta_order_scale");
        if (!json_is_array(v) || json_array_size(v) == 0 || json_array_size(v) > MER_ORDERS_MAX)
            return merd_refuse(why, 422, "invalid-field", f,
                              "%s must be an array of 1 to %d numbers, one per branch order", f,
                              MER_ORDERS_MAX);
        size_t n = json_array_size(v);
        for (size_t k = 0; k < MER_ORDERS_MAX; k++) {
            const json_t *x = json_array_get(v, k < n ? k : n - 1);
            if (!json_is_number(x) || !(fabs(json_number_value(x)) <= 100))
                return merd_refuse(why, 422, "out-of-range", f, "%s holds numbers from -100 to 100", f);
            e->schedule.eta_order_scale[k] = (float)json_number_value(x);
        }
        e->sched_mask |= SCHED_ETA_SCALE;
    }
    if ((v = json_object_get(o, "lambda_keys")) != NULL) {
        path(f, sizeof f, w, "lambda_keys");
        if (decode_keys_into(v, f, 0, 1, e->schedule.lambda_keys, &e->schedule.lambda_key_count, why))
            return -1;
        e->sched_mask |= SCHED_LAMBDA;
    }
    if ((v = json_object_get(o, "eta_keys")) != NULL) {
        path(f, sizeof f, w, "eta_keys");
        if (decode_keys_into(v, f, -100, 100, e->schedule.eta_keys, &e->schedule.eta_key_count, why))
            return -1;
        e->sched_mask |= SCHED_ETA;
    }
    if (e->sched_mask == 0)
        return merd_refuse(why, 422, "missing-field", w,
                          "a set_apical_schedule edit needs apical_off, eta_order_scale, "
                          "lambda_keys or eta_keys");
    return 0;
}

int merd_params_from_json(const json_t *obj, mer_params *p, const char *where, merd_refusal *why)
{
    if (!json_is_object(obj))
        return merd_refuse(why, 422, "invalid-field", where, "%s must be an object of name: number",
                          where);
    const char *key;
    const json_t *value;
    json_object_foreach((json_t *)obj, key, value) {
        char f[96];
        path(f, sizeof f, where, key);
        double x;
        mer_error err;
        if (mer_params_get(p, key, &x, &err) != MER_OK)
            return merd_refuse(why, 400, "unknown-field", f,
                              "unknown parameter '%s'; GET /v1/presets lists them", key);
        if (!json_is_number(value))
            return merd_refuse(why, 422, "invalid-field", f, "%s must be a number", f);
        if (mer_params_set(p, key, json_number_value(value), &err) != MER_OK)
            return merd_refuse(why, 422, "out-of-range", f, "%s", err.message);
    }
    return 0;
}

static int decode_params(const json_t *o, const char *w, edit *e, merd_refusal *why)
{
    static const char *const allowed[] = {"op", "params", NULL};
    if (only_fields(o, allowed, "a set_params edit", w, why))
        return -1;
    char f[96];
    path(f, sizeof f, w, "params");
    e->params = json_object_get(o, "params");
    if (e->params == NULL)
        return merd_refuse(why, 422, "missing-field", f, "%s is required", f);
    // Names and ranges now; cross-field rules against the tree's values when applied.
    mer_params scratch = mer_params_default();
    return merd_params_from_json(e->params, &scratch, f, why);
}

static int decode_one(const json_t *o, const char *w, const merd_edit_limits *lim, edit *e,
                      uint64_t *steps, uint64_t *markers, merd_refusal *why)
{
    e->json = o;
    if (!json_is_object(o))
        return merd_refuse(why, 422, "invalid-field", w[0] ? w : "body", "an edit must be an object");
    const json_t *op = json_object_get(o, "op");
    char f[96];
    path(f, sizeof f, w, "op");
    if (!json_is_string(op))
        return merd_refuse(why, 400, "unknown-op", f,
                          "every edit needs \"op\": step, add_markers, prune, bend, "
                          "set_apical_schedule, set_params or release");
    const char *name = json_string_value(op);
    if (strcmp(name, "step") == 0) {
        e->op = OP_STEP;
        return decode_step(o, w, lim, e, steps, why);
    }
    if (strcmp(name, "add_markers") == 0)
        return decode_markers(o, w, lim, e, markers, why);
    if (strcmp(name, "prune") == 0) {
        static const char *const allowed[] = {"op", "node", NULL};
        e->op = OP_PRUNE;
        return only_fields(o, allowed, "a prune edit", w, why) || decode_node_edit(o, w, e, why);
    }
    if (strcmp(name, "bend") == 0) {
        static const char *const allowed[] = {"op", "node", "axis", "angle", NULL};
        double angle;
        e->op = OP_BEND;
        if (only_fields(o, allowed, "a bend edit", w, why) || decode_node_edit(o, w, e, why) ||
            get_vec3_field(o, "axis", w, true, e->axis, why) ||
            get_number(o, "angle", w, -360, 360, true, 0, &angle, why))
            return -1;
        if (e->axis[0] == 0 && e->axis[1] == 0 && e->axis[2] == 0) {
            path(f, sizeof f, w, "axis");
            return merd_refuse(why, 422, "out-of-range", f, "%s must not be the zero vector", f);
        }
        e->angle = (float)angle;
        return 0;
    }
    if (strcmp(name, "set_apical_schedule") == 0) {
        e->op = OP_SCHEDULE;
        return decode_schedule(o, w, e, why);
    }
    if (strcmp(name, "set_params") == 0) {
        e->op = OP_PARAMS;
        return decode_params(o, w, e, why);
    }
    if (strcmp(name, "release") == 0) {
        static const char *const allowed[] = {"op", NULL};
        e->op = OP_RELEASE;
        return only_fields(o, allowed, "a release edit", w, why);
    }
    return merd_refuse(why, 400, "unknown-op", f,
                      "unknown op '%s'; use step, add_markers, prune, bend, set_apical_schedule, "
                      "set_params or release", name);
}

int merd_batch_decode(const json_t *body, const merd_edit_limits *lim, merd_batch **out,
                     merd_refusal *why)
{
    *out = NULL;
    if (!json_is_object(body))
        return merd_refuse(why, 422, "invalid-field", "body",
                          "the body must be an edit object or {\"edits\": [...]}");
    const json_t *list = json_object_get(body, "edits");
    bool batch = list != NULL;
    if (batch) {
        static const char *const allowed[] = {"edits", NULL};
        if (only_fields(body, allowed, "a batch", "", why))
            return -1;
        if (!json_is_array(list) || json_array_size(list) == 0 || json_array_size(list) > 10000)
            return merd_refuse(why, 422, "invalid-field", "edits",
                              "edits must be an array of 1 to 10000 edit objects");
    }
    merd_batch *b = calloc(1, sizeof *b);
    size_t n = batch ? json_array_size(list) : 1;
    if (b == NULL || (b->edits = calloc(n, sizeof *b->edits)) == NULL) {
        free(b);
        return merd_refuse(why, 500, "internal", "", "out of memory for edits");
    }
    b->body = json_incref((json_t *)body);
    b->count = n;
    uint64_t steps = 0, markers = 0;
    for (size_t i = 0; i < n; i++) {
        char w[32] = "";
        if (batch)
            snprintf(w, sizeof w, "edits[%zu]", i);
        if (decode_one(batch ? json_array_get(list, i) : body, w, lim, &b->edits[i], &steps,
                       &markers, why) != 0) {
            merd_batch_free(b);
            return -1;
        }
    }
    *out = b;
    return 0;
}

void merd_batch_free(merd_batch *b)
{
    if (b == NULL)
        return;
    for (size_t i = 0; i < b->count; i++)
        free(b->edits[i].points);
    free(b->edits);
    json_decref(b->body);
    free(b);
}

/* ---------------------------------------------------------------- applying */

/* The library's refusal as an HTTP one: an id that was never issued is 404,
 * a node that is gone or a limit of the tree is 409, a bad value 422. */
static int from_lib(merd_refusal *why, mer_result rc, const mer_error *err, const char *where)
{
    char f[96];
    path(f, sizeof f, where, err->field);
    switch (rc) {
    case MER_ERR_NOMEM: return merd_refuse(why, 503, "out-of-memory", f, "%s", err->message);
    case MER_ERR_LIMIT: return merd_refuse(why, 409, "limit", f, "%s", err->message);
    case MER_ERR_NOT_FOUND: return merd_refuse(why, 404, "unknown-node", f, "%s", err->message);
    case MER_ERR_GONE: return merd_refuse(why, 409, "dead-node", f, "%s", err->message);
    case MER_ERR_RANGE: return merd_refuse(why, 422, "out-of-range", f, "%s", err->message);
    default: return merd_refuse(why, 422, "invalid-field", f, "%s", err->message);
    }
}

typedef struct step_ctx {
    merd_batch_stop_fn stop;
    void *ctx;
    volatile int cancel;
} step_ctx;

static void on_step(void *ctx, uint32_t done, uint32_t total)
{
    step_ctx *c = ctx;
    if (c->stop != NULL && c->stop(c->ctx, done, total))
        c->cancel = 1;
}

/* A node named by an edit must have been issued (404) and be alive (409). */
static int check_node(const mer_scene *s, uint32_t node, const char *w, merd_refusal *why)
{
    char f[96];
    path(f, sizeof f, w, "node");
    mer_node n;
    if (node >= mer_scene_node_bound(s) || mer_scene_node(s, node, &n, NULL) != MER_OK)
        return merd_refuse(why, 404, "unknown-node", f, "node %u was never part of this tree "
                          "(ids run from 0 to %u)", node, mer_scene_node_bound(s) - 1);
    if (!n.alive)
        return merd_refuse(why, 409, "dead-node", f, "node %u was pruned or shed", node);
    return 0;
}

static int apply_one(const edit *e, const char *w, mer_scene *s, step_ctx *sc, uint32_t *done,
                     merd_refusal *why)
{
    mer_error err = {0};
    mer_result rc = MER_OK;
    if ((e->op == OP_PRUNE || e->op == OP_BEND || (e->op == OP_BRUSH && e->constrain)) &&
        check_node(s, e->node, w, why) != 0)
        return -1;
    switch (e->op) {
    case OP_STEP:
        rc = mer_scene_step(s, e->count, on_step, sc, &sc->cancel, done, &err);
        break;
    case OP_POINTS:
        rc = mer_scene_add_markers(s, e->points, e->npoints, &err);
        break;
    case OP_BRUSH:
        if (e->constrain)
            rc = mer_scene_constrain(s, e->node, e->bud, &err);
        if (rc == MER_OK)
            rc = mer_scene_brush(s, &e->brush, e->has_symmetry ? &e->symmetry : NULL, NULL, &err);
        // Name the request's fields, not the library's.
        static const char *const names[][2] = {{"slot", "constrain.bud"},
                                               {"mirror_normal", "symmetry.mirror.normal"},
                                               {"tiles", "symmetry.tiles"},
                                               {"rotational", "symmetry.rotational"},
                                               {"max_count", "count"}};
        for (size_t k = 0; rc != MER_OK && k < sizeof names / sizeof names[0]; k++)
            if (strcmp(err.field, names[k][0]) == 0)
                snprintf(err.field, sizeof err.field, "%s", names[k][1]);
        break;
    case OP_PRUNE:
        rc = mer_scene_prune(s, e->node, &err);
        break;
    case OP_BEND:
        rc = mer_scene_bend(s, e->node, e->axis, e->angle, &err);
        break;
    case OP_SCHEDULE: {
        mer_params p = *mer_scene_params(s);
        if (e->sched_mask & SCHED_APICAL)
            memcpy(p.schedule.apical_off, e->schedule.apical_off, sizeof p.schedule.apical_off);
        if (e->sched_mask & SCHED_ETA_SCALE)
            memcpy(p.schedule.eta_order_scale, e->schedule.eta_order_scale,
                   sizeof p.schedule.eta_order_scale);
        if (e->sched_mask & SCHED_LAMBDA) {
            p.schedule.lambda_key_count = e->schedule.lambda_key_count;
            memcpy(p.schedule.lambda_keys, e->schedule.lambda_keys, sizeof p.schedule.lambda_keys);
        }
        if (e->sched_mask & SCHED_ETA) {
            p.schedule.eta_key_count = e->schedule.eta_key_count;
            memcpy(p.schedule.eta_keys, e->schedule.eta_keys, sizeof p.schedule.eta_keys);
        }
        rc = mer_scene_set_params(s, &p, &err);
        break;
    }
    case OP_PARAMS: {
        mer_params p = *mer_scene_params(s);
        char f[96];
        path(f, sizeof f, w, "params");
        if (merd_params_from_json(e->params, &p, f, why) != 0)
            return -1;
        rc = mer_scene_set_params(s, &p, &err);
        break;
    }
    case OP_RELEASE:
        mer_scene_unconstrain(s);
        break;
    }
    return rc == MER_OK ? 0 : from_lib(why, rc, &err, w);
}

int merd_batch_apply(const merd_batch *b, mer_scene *scene, merd_batch_stop_fn stop, void *ctx,
                    merd_batch_outcome *outcome, json_t **applied, merd_refusal *why)
{
    *applied = json_array();
    memset(outcome, 0, sizeof *outcome);
    step_ctx sc = {stop, ctx, 0};
    for (size_t i = 0; i < b->count; i++) {
        const edit *e = &b->edits[i];
        char w[32] = "";
        if (b->count > 1 || json_object_get(b->body, "edits") != NULL)
            snprintf(w, sizeof w, "edits[%zu]", i);
        uint32_t done = 0;
        if (apply_one(e, w, scene, &sc, &done, why) != 0) {
            json_decref(*applied);
            *applied = NULL;
            return -1;
        }
        if (e->op == OP_STEP) {
            outcome->steps_asked += e->count;
            outcome->steps_done += done;
            if (done < e->count) {
                // Stopped at a whole step: journal what was done, nothing after it.
                if (done > 0)
                    json_array_append_new(*applied, json_pack("{s:s, s:i}", "op", "step", "count", (json_int_t)done));
                outcome->interrupted = "stopped";
                return 0;
            }
        }
        json_array_append(*applied, (json_t *)e->json);
    }
    return 0;
}

int merd_batch_replay(const json_t *applied, mer_scene *scene, merd_refusal *why)
{
    const merd_edit_limits unlimited = {UINT32_MAX, UINT32_MAX};
    json_t *body = json_pack("{s:O}", "edits", (json_t *)applied);
    merd_batch *b = NULL;
    int rc = merd_batch_decode(body, &unlimited, &b, why);
    json_decref(body);
    if (rc != 0)
        return -1;
    merd_batch_outcome outcome;
    json_t *again = NULL;
    rc = merd_batch_apply(b, scene, NULL, NULL, &outcome, &again, why);
    json_decref(again);
    merd_batch_free(b);
    return rc;
}
