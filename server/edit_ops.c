/* meristemd — each edit op: how it is decoded and applied, and the table that
 * names them (see edit_ops.h). */
#include "config.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "server/decode.h"
#include "server/edit_ops.h"
#include "server/functions_json.h"

/* A bend turns by at most a full turn either way, in degrees, spread by default
 * over the first three internodes of the bent axis (a curve, not an elbow). */
#define ANGLE_MAX 360.0
#define MERD_BEND_SPREAD_DEFAULT 3
/* A keyframe's step and a schedule's η values. */
#define KEY_STEP_MAX 1e6
#define ETA_MAX 100.0
/* Symmetry: rotational copies, and tiles along each lattice vector. */
#define ROTATIONAL_MAX 64
#define TILES_MAX 1024
/* Markers one brush dab may scatter. */
#define DAB_COUNT_MAX 100000

enum { SCHED_APICAL = 1, SCHED_ETA_SCALE = 2, SCHED_LAMBDA = 4, SCHED_ETA = 8 };

/* ---------------------------------------------------------------- decoding */

static int decode_step(const json_t *o, const char *w, merd_decode_ctx *c, merd_edit *e,
                       merd_refusal *why)
{
    const merd_edit_limits *lim = c->limits;
    uint64_t n;
    if (merd_get_uint(o, "count", w, 1, lim->max_steps, false, 1, &n, why))
        return -1;
    c->steps += n;
    char f[MERD_FIELD_MAX];
    merd_path(f, sizeof f, w, "count");
    if (c->steps > lim->max_steps)
        return merd_refuse(why, 422, "out-of-range", f,
                           "a request may step at most %u times (meristemd --max-steps), this one "
                           "asks for %llu", lim->max_steps, (unsigned long long)c->steps);
    e->count = (uint32_t)n;
    return 0;
}

static int decode_mirror(const json_t *m, const char *w, mer_symmetry *out, merd_refusal *why)
{
    static const char *const fields[] = {"point", "normal", NULL};
    if (!json_is_object(m))
        return merd_refuse(why, 422, "invalid-field", w, "%s must be an object", w);
    if (merd_only_fields(m, fields, "a mirror", w, true, why) ||
        merd_get_vec3(m, "point", w, false, out->mirror_point, why) ||
        merd_get_vec3(m, "normal", w, true, out->mirror_normal, why))
        return -1;
    out->mirror = 1;
    return 0;
}

static int decode_tiles(const json_t *s, const char *w, mer_symmetry *out, merd_refusal *why)
{
    const json_t *t = json_object_get(s, "tiles");
    char tw[MERD_FIELD_MAX];
    merd_path(tw, sizeof tw, w, "tiles");
    if (!json_is_array(t) || json_array_size(t) != 2 || !json_is_integer(json_array_get(t, 0)) ||
        !json_is_integer(json_array_get(t, 1)))
        return merd_refuse(why, 422, "invalid-field", tw, "%s must be [nu, nv], two integers", tw);
    for (size_t k = 0; k < 2; k++) {
        json_int_t x = json_integer_value(json_array_get(t, k));
        if (x < 0 || x > TILES_MAX)
            return merd_refuse(why, 422, "out-of-range", tw, "%s holds integers from 0 to %d", tw,
                               TILES_MAX);
        out->tiles[k] = (uint32_t)x;
    }
    const json_t *st = json_object_get(s, "tile_step");
    char sw[MERD_FIELD_MAX];
    merd_path(sw, sizeof sw, w, "tile_step");
    if (!json_is_array(st) || json_array_size(st) != 2)
        return merd_refuse(why, 422, "invalid-field", sw,
                           "%s must be two lattice vectors [[x,y,z],[x,y,z]] when tiles is given", sw);
    for (size_t k = 0; k < 2; k++)
        if (merd_vec3(json_array_get(st, k), sw, &merd_words_edit, out->tile_step[k], why))
            return -1;
    return 0;
}

static int decode_symmetry(const json_t *s, const char *w, mer_symmetry *out, merd_refusal *why)
{
    static const char *const fields[] = {"rotational", "center", "mirror", "tiles", "tile_step", NULL};
    if (!json_is_object(s))
        return merd_refuse(why, 422, "invalid-field", w, "%s must be an object", w);
    if (merd_only_fields(s, fields, "a symmetry", w, true, why))
        return -1;
    uint64_t n;
    if (merd_get_uint(s, "rotational", w, 0, ROTATIONAL_MAX, false, 0, &n, why) ||
        merd_get_vec3(s, "center", w, false, out->center, why))
        return -1;
    out->rotational = (uint32_t)n;
    const json_t *m = json_object_get(s, "mirror");
    char mw[MERD_FIELD_MAX];
    merd_path(mw, sizeof mw, w, "mirror");
    if (m != NULL && decode_mirror(m, mw, out, why))
        return -1;
    if (json_object_get(s, "tiles") != NULL && decode_tiles(s, w, out, why))
        return -1;
    return 0;
}

static int decode_points(const json_t *o, const char *w, merd_decode_ctx *c, merd_edit *e,
                         merd_refusal *why)
{
    static const char *const fields[] = {"op", "points", NULL};
    const json_t *pts = json_object_get(o, "points");
    char f[MERD_FIELD_MAX];
    merd_path(f, sizeof f, w, "points");
    if (merd_only_fields(o, fields, "an add_markers edit with points", w, true, why))
        return -1;
    if (!json_is_array(pts))
        return merd_refuse(why, 422, "invalid-field", f, "%s must be an array of [x, y, z]", f);
    e->npoints = json_array_size(pts);
    c->markers += e->npoints;
    if (c->markers > c->limits->max_markers)
        return merd_refuse(why, 422, "out-of-range", f,
                           "a request may add at most %u markers (meristemd --max-markers), "
                           "this one adds %llu", c->limits->max_markers,
                           (unsigned long long)c->markers);
    e->points = malloc((e->npoints ? e->npoints : 1) * 3 * sizeof(float));
    if (e->points == NULL)
        return merd_refuse(why, 500, "internal", f, "out of memory for markers");
    for (size_t i = 0; i < e->npoints; i++) {
        char pf[MERD_FIELD_MAX + 24];
        snprintf(pf, sizeof pf, "%s[%zu]", f, i);
        if (merd_vec3(json_array_get(pts, i), pf, &merd_words_edit, e->points + 3 * i, why))
            return -1;
    }
    return 0;
}

/* A dab's {"node", "bud"}: the growth it steers. */
static int decode_constraint(const json_t *c, const char *w, merd_edit *e, merd_refusal *why)
{
    static const char *const fields[] = {"node", "bud", NULL};
    uint64_t node, bud;
    if (!json_is_object(c))
        return merd_refuse(why, 422, "invalid-field", w, "%s must be {\"node\", \"bud\"}", w);
    if (merd_only_fields(c, fields, "a constraint", w, true, why) ||
        merd_get_uint(c, "node", w, 0, UINT32_MAX - 1, true, 0, &node, why) ||
        merd_get_uint(c, "bud", w, 0, 2, false, 0, &bud, why))
        return -1;
    e->node = (uint32_t)node;
    e->bud = (uint32_t)bud;
    e->constrain = true;
    return 0;
}

static int decode_dab(const json_t *o, const char *w, merd_decode_ctx *c, merd_edit *e,
                      merd_refusal *why)
{
    static const char *const fields[] = {"op", "center", "radius", "pressure", "count",
                                         "symmetry", "constrain", NULL};
    if (merd_only_fields(o, fields, "an add_markers edit (give points, or a brush dab)", w, true, why))
        return -1;
    double radius, pressure;
    uint64_t count;
    if (merd_get_vec3(o, "center", w, true, e->brush.center, why) ||
        merd_get_number(o, "radius", w, 1e-3, 1000, true, 0, &radius, why) ||
        merd_get_number(o, "pressure", w, 1e-3, 1, false, 0.5, &pressure, why) ||
        merd_get_uint(o, "count", w, 1, DAB_COUNT_MAX, false, 50, &count, why))
        return -1;
    e->brush.radius = (float)radius;
    e->brush.pressure = (float)pressure;
    e->brush.max_count = (uint32_t)count;
    const json_t *s = json_object_get(o, "symmetry");
    uint64_t copies = 1;
    if (s != NULL) {
        char sw[MERD_FIELD_MAX];
        merd_path(sw, sizeof sw, w, "symmetry");
        if (decode_symmetry(s, sw, &e->symmetry, why))
            return -1;
        e->has_symmetry = true;
        const mer_symmetry *y = &e->symmetry;
        copies = (y->rotational > 1 ? y->rotational : 1) * (y->mirror ? 2 : 1) *
                 (uint64_t)(y->tiles[0] > 1 ? y->tiles[0] : 1) * (y->tiles[1] > 1 ? y->tiles[1] : 1);
    }
    c->markers += count * copies;
    char f[MERD_FIELD_MAX];
    merd_path(f, sizeof f, w, "count");
    if (c->markers > c->limits->max_markers)
        return merd_refuse(why, 422, "out-of-range", f,
                           "a request may add at most %u markers (meristemd --max-markers); this "
                           "dab may add up to %llu with its symmetric copies",
                           c->limits->max_markers, (unsigned long long)c->markers);
    const json_t *k = json_object_get(o, "constrain");
    merd_path(f, sizeof f, w, "constrain");
    return k != NULL ? decode_constraint(k, f, e, why) : 0;
}

/* add_markers: points, or a brush dab around a center. */
static int decode_markers(const json_t *o, const char *w, merd_decode_ctx *c, merd_edit *e,
                          merd_refusal *why)
{
    if (json_object_get(o, "points") != NULL)
        return decode_points(o, w, c, e, why);
    return decode_dab(o, w, c, e, why);
}

static int decode_node(const json_t *o, const char *w, merd_decode_ctx *c, merd_edit *e,
                       merd_refusal *why)
{
    (void)c;
    uint64_t node;
    if (merd_get_uint(o, "node", w, 0, UINT32_MAX - 1, true, 0, &node, why))
        return -1;
    e->node = (uint32_t)node;
    return 0;
}

static int decode_revert(const json_t *o, const char *w, merd_decode_ctx *c, merd_edit *e,
                         merd_refusal *why)
{
    (void)c;
    // Any revision a journal can hold; whether the session has it is known when applied.
    return merd_get_uint(o, "revision", w, 0, (uint64_t)INT64_MAX, true, 0, &e->revision, why);
}

static int decode_bend(const json_t *o, const char *w, merd_decode_ctx *c, merd_edit *e,
                       merd_refusal *why)
{
    double angle;
    if (decode_node(o, w, c, e, why) || merd_get_vec3(o, "axis", w, true, e->axis, why) ||
        merd_get_number(o, "angle", w, -ANGLE_MAX, ANGLE_MAX, true, 0, &angle, why))
        return -1;
    if (e->axis[0] == 0 && e->axis[1] == 0 && e->axis[2] == 0) {
        char f[MERD_FIELD_MAX];
        merd_path(f, sizeof f, w, "axis");
        return merd_refuse(why, 422, "out-of-range", f, "%s must not be the zero vector", f);
    }
    e->angle = (float)angle;
    // A bend recorded before `spread` existed was an elbow; a new one without it
    // gets the default, written into the edit so that its journal record says so.
    uint64_t spread;
    if (merd_get_uint(o, "spread", w, 1, MER_BEND_SPREAD_MAX, false,
                      c->limits->journal ? 1 : MERD_BEND_SPREAD_DEFAULT, &spread, why))
        return -1;
    if (json_object_get(o, "spread") == NULL)
        json_object_set_new((json_t *)o, "spread", json_integer((json_int_t)spread));
    e->spread = (uint32_t)spread;
    return 0;
}

/* A keyframe list [[step, value], ...] in step order, at most MER_KEYS_MAX. */
static int decode_keys(const json_t *v, const char *f, double lo, double hi, mer_keyframe *keys,
                       uint32_t *count, merd_refusal *why)
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
        double step = json_number_value(json_array_get(k, 0));
        double value = json_number_value(json_array_get(k, 1));
        if (!(step >= 0 && step <= KEY_STEP_MAX) || !(value >= lo && value <= hi))
            return merd_refuse(why, 422, "out-of-range", f,
                               "%s[%zu]: step must be from 0 to 1e6 and value from %g to %g", f, i,
                               lo, hi);
        if (i > 0 && step <= (double)keys[i - 1].step)
            return merd_refuse(why, 422, "out-of-range", f, "%s must be in increasing step order", f);
        keys[i] = (mer_keyframe){(float)step, (float)value};
    }
    return 0;
}

/* apical_off: one step per branch order (null: never); orders past the list
 * take its last entry, as the engine does. */
static int decode_apical_off(const json_t *v, const char *f, mer_schedule *out, merd_refusal *why)
{
    if (!json_is_array(v) || json_array_size(v) == 0 || json_array_size(v) > MER_ORDERS_MAX)
        return merd_refuse(why, 422, "invalid-field", f,
                           "%s must be an array of 1 to %d steps (null: never), one per branch "
                           "order from the trunk", f, MER_ORDERS_MAX);
    size_t n = json_array_size(v);
    for (size_t k = 0; k < MER_ORDERS_MAX; k++) {
        const json_t *x = json_array_get(v, k < n ? k : n - 1);
        if (json_is_null(x)) {
            out->apical_off[k] = MER_NEVER;
        } else if (json_is_integer(x) && json_integer_value(x) >= 0 &&
                   json_integer_value(x) < (json_int_t)MER_NEVER) {
            out->apical_off[k] = (uint32_t)json_integer_value(x);
        } else {
            return merd_refuse(why, 422, "out-of-range", f,
                               "%s[%zu] must be a step (an integer from 0) or null for never", f,
                               k < n ? k : n - 1);
        }
    }
    return 0;
}

static int decode_eta_scale(const json_t *v, const char *f, mer_schedule *out, merd_refusal *why)
{
    if (!json_is_array(v) || json_array_size(v) == 0 || json_array_size(v) > MER_ORDERS_MAX)
        return merd_refuse(why, 422, "invalid-field", f,
                           "%s must be an array of 1 to %d numbers, one per branch order", f,
                           MER_ORDERS_MAX);
    size_t n = json_array_size(v);
    for (size_t k = 0; k < MER_ORDERS_MAX; k++) {
        const json_t *x = json_array_get(v, k < n ? k : n - 1);
        if (!json_is_number(x) || !(fabs(json_number_value(x)) <= ETA_MAX))
            return merd_refuse(why, 422, "out-of-range", f, "%s holds numbers from -100 to 100", f);
        out->eta_order_scale[k] = (float)json_number_value(x);
    }
    return 0;
}

static int decode_schedule(const json_t *o, const char *w, merd_decode_ctx *c, merd_edit *e,
                           merd_refusal *why)
{
    (void)c;
    char f[MERD_FIELD_MAX];
    const json_t *v;
    mer_schedule *s = &e->schedule;
    if ((v = json_object_get(o, "apical_off")) != NULL) {
        merd_path(f, sizeof f, w, "apical_off");
        if (decode_apical_off(v, f, s, why))
            return -1;
        e->sched_mask |= SCHED_APICAL;
    }
    if ((v = json_object_get(o, "eta_order_scale")) != NULL) {
        merd_path(f, sizeof f, w, "eta_order_scale");
        if (decode_eta_scale(v, f, s, why))
            return -1;
        e->sched_mask |= SCHED_ETA_SCALE;
    }
    if ((v = json_object_get(o, "lambda_keys")) != NULL) {
        merd_path(f, sizeof f, w, "lambda_keys");
        if (decode_keys(v, f, 0, 1, s->lambda_keys, &s->lambda_key_count, why))
            return -1;
        e->sched_mask |= SCHED_LAMBDA;
    }
    if ((v = json_object_get(o, "eta_keys")) != NULL) {
        merd_path(f, sizeof f, w, "eta_keys");
        if (decode_keys(v, f, -ETA_MAX, ETA_MAX, s->eta_keys, &s->eta_key_count, why))
            return -1;
        e->sched_mask |= SCHED_ETA;
    }
    if (e->sched_mask == 0)
        return merd_refuse(why, 422, "missing-field", w,
                           "a set_apical_schedule edit needs apical_off, eta_order_scale, "
                           "lambda_keys or eta_keys");
    return 0;
}

static int decode_params(const json_t *o, const char *w, merd_decode_ctx *c, merd_edit *e,
                         merd_refusal *why)
{
    (void)c;
    char f[MERD_FIELD_MAX];
    merd_path(f, sizeof f, w, "params");
    e->params = json_object_get(o, "params");
    if (e->params == NULL)
        return merd_refuse(why, 422, "missing-field", f, "%s is required", f);
    // Names and ranges now; cross-field rules against the tree's values when applied.
    mer_params scratch = mer_params_default();
    return merd_params_from_json(e->params, &scratch, f, why);
}

/* An L-system's source, decoded whole: its productions are checked when it is
 * applied (the library names the line and column). */
/* A definition text from member `name` of o, `what` saying what text it is. */
static int decode_text(const json_t *o, const char *w, const char *name, const char *what,
                       merd_edit *e, merd_refusal *why)
{
    char f[MERD_FIELD_MAX];
    merd_path(f, sizeof f, w, name);
    const json_t *v = json_object_get(o, name);
    if (v == NULL)
        return merd_refuse(why, 422, "missing-field", f, "%s is required", f);
    if (!json_is_string(v))
        return merd_refuse(why, 422, "invalid-field", f, "%s must be a string (%s)", f, what);
    if (json_string_length(v) > MERD_SOURCE_MAX)
        return merd_refuse(why, 422, "out-of-range", f, "%s may hold at most %d bytes", f,
                           MERD_SOURCE_MAX);
    e->source = json_string_value(v);
    e->source_len = json_string_length(v);
    return 0;
}

static int decode_source(const json_t *o, const char *w, merd_decode_ctx *c, merd_edit *e,
                         merd_refusal *why)
{
    (void)c;
    return decode_text(o, w, "source", "cpfg text", e, why);
}

static int decode_fset(const json_t *o, const char *w, merd_decode_ctx *c, merd_edit *e,
                       merd_refusal *why)
{
    (void)c;
    const json_t *fns = json_object_get(o, "functions");
    if (fns == NULL)
        return decode_text(o, w, "fset", ".fset text", e, why);
    char f[MERD_FIELD_MAX];
    merd_path(f, sizeof f, w, "functions");
    if (json_object_get(o, "fset") != NULL)
        return merd_refuse(why, 422, "invalid-field", f, "give fset or functions, not both");
    if (merd_functions_fset(fns, f, &e->owned, &e->source_len, why) != 0)
        return -1;
    e->source = e->owned;
    return 0;
}

/* ---------------------------------------------------------------- applying */

static int lib(const merd_apply_ctx *c, mer_result rc, const mer_error *err, merd_refusal *why)
{
    return rc == MER_OK ? 0 : merd_refuse_lib(why, rc, err, c->where);
}

static void on_step(void *ctx, uint32_t done, uint32_t total)
{
    merd_apply_ctx *c = ctx;
    const char *reason = c->stop != NULL ? c->stop(c->stop_ctx, done, total) : NULL;
    if (reason != NULL) {
        c->stopped = reason;
        c->cancel = 1;
    }
}

static int apply_step(const merd_edit *e, merd_apply_ctx *c, merd_refusal *why)
{
    mer_error err = {0};
    c->done = 0;
    return lib(c, mer_scene_step(c->scene, e->count, on_step, c, &c->cancel, &c->done, &err), &err,
               why);
}

static int apply_markers(const merd_edit *e, merd_apply_ctx *c, merd_refusal *why)
{
    mer_error err = {0};
    mer_result rc = MER_OK;
    if (e->points != NULL)
        return lib(c, mer_scene_add_markers(c->scene, e->points, e->npoints, &err), &err, why);
    if (e->constrain)
        rc = mer_scene_constrain(c->scene, e->node, e->bud, &err);
    if (rc == MER_OK)
        rc = mer_scene_brush(c->scene, &e->brush, e->has_symmetry ? &e->symmetry : NULL, NULL, &err);
    // Name the request's fields, not the library's.
    static const char *const names[][2] = {{"slot", "constrain.bud"},
                                           {"mirror_normal", "symmetry.mirror.normal"},
                                           {"tiles", "symmetry.tiles"},
                                           {"rotational", "symmetry.rotational"},
                                           {"max_count", "count"}};
    for (size_t k = 0; rc != MER_OK && k < sizeof names / sizeof names[0]; k++)
        if (strcmp(err.field, names[k][0]) == 0)
            snprintf(err.field, sizeof err.field, "%s", names[k][1]);
    return lib(c, rc, &err, why);
}

static int apply_prune(const merd_edit *e, merd_apply_ctx *c, merd_refusal *why)
{
    mer_error err = {0};
    return lib(c, mer_scene_prune(c->scene, e->node, &err), &err, why);
}

static int apply_bend(const merd_edit *e, merd_apply_ctx *c, merd_refusal *why)
{
    mer_error err = {0};
    return lib(c, mer_scene_bend_spread(c->scene, e->node, e->axis, e->angle, e->spread, &err), &err, why);
}

static int apply_schedule(const merd_edit *e, merd_apply_ctx *c, merd_refusal *why)
{
    mer_schedule sched = mer_scene_params(c->scene)->schedule;
    mer_schedule *s = &sched;
    if (e->sched_mask & SCHED_APICAL)
        memcpy(s->apical_off, e->schedule.apical_off, sizeof s->apical_off);
    if (e->sched_mask & SCHED_ETA_SCALE)
        memcpy(s->eta_order_scale, e->schedule.eta_order_scale, sizeof s->eta_order_scale);
    if (e->sched_mask & SCHED_LAMBDA) {
        s->lambda_key_count = e->schedule.lambda_key_count;
        memcpy(s->lambda_keys, e->schedule.lambda_keys, sizeof s->lambda_keys);
    }
    if (e->sched_mask & SCHED_ETA) {
        s->eta_key_count = e->schedule.eta_key_count;
        memcpy(s->eta_keys, e->schedule.eta_keys, sizeof s->eta_keys);
    }
    mer_error err = {0};
    return lib(c, mer_scene_set_schedule(c->scene, s, &err), &err, why);
}

static int apply_params(const merd_edit *e, merd_apply_ctx *c, merd_refusal *why)
{
    mer_params p = *mer_scene_params(c->scene);
    char f[MERD_FIELD_MAX];
    merd_path(f, sizeof f, c->where, "params");
    if (merd_params_from_json(e->params, &p, f, why) != 0)
        return -1;
    mer_error err = {0};
    return lib(c, mer_scene_set_params(c->scene, &p, &err), &err, why);
}

static int apply_release(const merd_edit *e, merd_apply_ctx *c, merd_refusal *why)
{
    (void)e;
    (void)why;
    mer_scene_unconstrain(c->scene);
    return 0;
}

/* The warnings about the definition just given, named after the member `name`
 * it came in, into the batch's outcome. */
static void definition_warnings(merd_apply_ctx *c, const char *name)
{
    merd_batch_outcome *o = c->outcome;
    mer_warning w[MERD_WARNINGS_MAX];
    size_t n = mer_scene_definition_warnings(c->scene, w, MERD_WARNINGS_MAX);
    for (size_t i = 0; i < n && i < MERD_WARNINGS_MAX && o->nwarnings < MERD_WARNINGS_MAX; i++) {
        merd_edit_warning *out = &o->warnings[o->nwarnings++];
        merd_path(out->field, sizeof out->field, c->where, name);
        out->w = w[i];
    }
}

/* A new definition text, its errors named after the member `name` it came in. */
static int define(const merd_edit *e, merd_apply_ctx *c, const char *name, merd_refusal *why)
{
    mer_error err = {0};
    mer_result rc = mer_scene_set_definition(c->scene, e->source, e->source_len, &err);
    if (rc == MER_OK) {
        if (c->outcome != NULL)
            definition_warnings(c, e->owned != NULL ? "functions" : name);
        return 0;
    }
    if (strcmp(err.field, "definition") == 0)
        snprintf(err.field, sizeof err.field, "%s", e->owned != NULL ? "functions" : name);
    return lib(c, rc, &err, why);
}

static int apply_lsystem(const merd_edit *e, merd_apply_ctx *c, merd_refusal *why)
{
    return define(e, c, "source", why);
}

/* The inverse model's functions (and scalars) replaced; the tree regrows from them. */
static int apply_functions(const merd_edit *e, merd_apply_ctx *c, merd_refusal *why)
{
    return define(e, c, "fset", why);
}

/* The tree becomes the one of a past revision, derived anew (revisions.h): a
 * revert journals as itself, and replaying it derives the same tree again. */
static int apply_revert(const merd_edit *e, merd_apply_ctx *c, merd_refusal *why)
{
    char f[MERD_FIELD_MAX];
    merd_path(f, sizeof f, c->where, "revision");
    if (c->past == NULL)
        return merd_refuse(why, 422, "unknown-revision", f, "this scene has no past revisions");
    mer_scene *past = NULL;
    if (c->past->scene_at(c->past->ctx, e->revision, f, &past, why) != 0)
        return -1;
    if (c->first && c->past->retire != NULL)
        c->past->retire(c->past->ctx, c->scene);
    else
        mer_scene_free(c->scene);
    c->scene = past;
    return 0;
}

/* ---------------------------------------------------------------- the table */

static const char *const step_fields[] = {"op", "count", NULL};
static const char *const node_fields[] = {"op", "node", NULL};
static const char *const bend_fields[] = {"op", "node", "axis", "angle", "spread", NULL};
static const char *const schedule_fields[] = {"op", "apical_off", "eta_order_scale",
                                              "lambda_keys", "eta_keys", NULL};
static const char *const params_fields[] = {"op", "params", NULL};
static const char *const release_fields[] = {"op", NULL};
static const char *const revert_fields[] = {"op", "revision", NULL};
static const char *const lsystem_fields[] = {"op", "source", NULL};
static const char *const functions_fields[] = {"op", "fset", "functions", NULL};

#define ANY                                                                           \
    (MERD_MODEL_P09 | MERD_MODEL_RUNIONS | MERD_MODEL_LSYSTEM | MERD_MODEL_INVERSE | \
     MERD_MODEL_GUIDING)
/* A forest's plants keep their presets: it takes the edits of its nodes. */
#define TREES (ANY | MERD_MODEL_FOREST)

static const merd_edit_op ops[] = {
    {"step", step_fields, "a step edit", decode_step, apply_step, TREES, MERD_OP_STEPS},
    {"add_markers", NULL, NULL, decode_markers, apply_markers, ANY & ~MERD_MODEL_INVERSE, 0},
    {"prune", node_fields, "a prune edit", decode_node, apply_prune, TREES, 0},
    {"bend", bend_fields, "a bend edit", decode_bend, apply_bend, TREES, 0},
    {"set_apical_schedule", schedule_fields, "a set_apical_schedule edit", decode_schedule,
     apply_schedule, MERD_MODEL_P09, 0},
    {"set_params", params_fields, "a set_params edit", decode_params, apply_params, ANY, 0},
    {"release", release_fields, "a release edit", NULL, apply_release, TREES, 0},
    {"revert", revert_fields, "a revert edit", decode_revert, apply_revert, TREES, 0},
    {"set_lsystem", lsystem_fields, "a set_lsystem edit", decode_source, apply_lsystem,
     MERD_MODEL_LSYSTEM, 0},
    {"set_functions", functions_fields, "a set_functions edit", decode_fset, apply_functions,
     MERD_MODEL_INVERSE, 0},
};
#define OPS (sizeof ops / sizeof ops[0])

const merd_edit_op *merd_edit_op_find(const char *name)
{
    for (size_t i = 0; i < OPS; i++)
        if (strcmp(ops[i].name, name) == 0)
            return &ops[i];
    return NULL;
}

void merd_edit_op_names(char *out, size_t n)
{
    size_t used = 0;
    out[0] = '\0';
    for (size_t i = 0; i < OPS && used < n; i++) {
        const char *sep = i == 0 ? "" : i + 1 == OPS ? " or " : ", ";
        int k = snprintf(out + used, n - used, "%s%s", sep, ops[i].name);
        used += k > 0 ? (size_t)k : 0;
    }
}
