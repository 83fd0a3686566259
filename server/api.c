/* meristemd — the /v1 handlers: sessions, edits, snapshots, presets, metrics.
 * Work that may take long (creating, editing, meshing) runs on the worker pool
 * with the connection suspended; everything else answers on the HTTP thread. */
#include "config.h"

#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <time.h>

#include <meristem/version.h>

#include "server/api.h"
#include "server/app.h"
#include "server/codec.h"

#define JSON_DEPTH_MAX 32

/* ----------------------------------------------------------------- helpers */

static enum MHD_Result refuse(merd_request *req, const merd_refusal *why)
{
    size_t size = 0;
    struct MHD_Response *r = merd_problem_response(why->status, why->slug, merd_status_title(why->status),
                                                  why->detail, why->field, &size);
    return merd_reply(req, why->status, r, size);
}

static struct MHD_Response *json_response(const json_t *j, size_t *size)
{
    char *text = json_dumps(j, MERD_JSON_DUMP_FLAGS);
    if (text == NULL)
        return NULL;
    *size = strlen(text);
    struct MHD_Response *r = MHD_create_response_from_buffer(*size, text, MHD_RESPMEM_MUST_FREE);
    if (r == NULL) {
        free(text);
        return NULL;
    }
    MHD_add_response_header(r, MHD_HTTP_HEADER_CONTENT_TYPE, "application/json");
    return r;
}

/* Queues `text` (taken over, freed by libmicrohttpd) as `content_type`. */
static enum MHD_Result reply_text(merd_request *req, unsigned status, char *text,
                                  const char *content_type)
{
    if (text == NULL)
        return MHD_NO;
    size_t size = strlen(text);
    struct MHD_Response *r = MHD_create_response_from_buffer(size, text, MHD_RESPMEM_MUST_FREE);
    if (r == NULL) {
        free(text);
        return MHD_NO;
    }
    MHD_add_response_header(r, MHD_HTTP_HEADER_CONTENT_TYPE, content_type);
    return merd_reply(req, status, r, size);
}

static struct MHD_Response *refusal_response(const merd_refusal *why, size_t *size)
{
    return merd_problem_response(why->status, why->slug, merd_status_title(why->status), why->detail,
                                why->field, size);
}

static int depth_of(const json_t *j)
{
    int deepest = 0;
    if (json_is_object(j)) {
        const char *k;
        const json_t *v;
        json_object_foreach((json_t *)j, k, v) {
            (void)k;
            int d = depth_of(v);
            deepest = d > deepest ? d : deepest;
        }
        return deepest + 1;
    }
    if (json_is_array(j)) {
        size_t i;
        const json_t *v;
        json_array_foreach(j, i, v) {
            int d = depth_of(v);
            deepest = d > deepest ? d : deepest;
        }
        return deepest + 1;
    }
    return 0;
}

/* The request body as JSON: an empty body is `{}`; a body must be
 * application/json (415), well-formed (400 naming line and column), without
 * duplicate keys and no deeper than JSON_DEPTH_MAX (400). */
static json_t *parse_body(merd_request *req, merd_refusal *why)
{
    if (req->body == NULL || req->body_size == 0)
        return json_object();
    const char *type = MHD_lookup_connection_value(req->connection, MHD_HEADER_KIND,
                                                   MHD_HTTP_HEADER_CONTENT_TYPE);
    if (type == NULL || strncasecmp(type, "application/json", 16) != 0 ||
        (type[16] != '\0' && type[16] != ';' && type[16] != ' ')) {
        merd_refuse(why, 415, "unsupported-media-type", "",
                   "send the body as application/json (got %s)", type ? type : "no Content-Type");
        return NULL;
    }
    json_error_t err;
    json_t *doc = json_loadb(req->body, req->body_size, JSON_REJECT_DUPLICATES, &err);
    if (doc == NULL) {
        merd_refuse(why, 400, "malformed-json", "", "malformed JSON at line %d, column %d: %s",
                   err.line, err.column, err.text);
        return NULL;
    }
    if (depth_of(doc) > JSON_DEPTH_MAX) {
        json_decref(doc);
        merd_refuse(why, 400, "malformed-json", "", "JSON nested deeper than %d levels", JSON_DEPTH_MAX);
        return NULL;
    }
    return doc;
}

static merd_session *find_session(merd_request *req, const char *id, merd_refusal *why)
{
    merd_session *s = merd_registry_get(req->app->registry, id);
    if (s == NULL)
        merd_refuse(why, 404, "unknown-session", "", "there is no session %.64s (GET /v1/sessions "
                   "lists them)", id);
    return s;
}

static const char *query(merd_request *req, const char *key)
{
    return MHD_lookup_connection_value(req->connection, MHD_GET_ARGUMENT_KIND, key);
}

static int query_uint(merd_request *req, const char *key, uint32_t lo, uint32_t hi, uint32_t *out,
                      merd_refusal *why)
{
    const char *v = query(req, key);
    if (v == NULL)
        return 0;
    char *end = NULL;
    unsigned long x = strtoul(v, &end, 10);
    if (end == v || *end != '\0' || x < lo || x > hi)
        return merd_refuse(why, 422, "out-of-range", key, "%s must be an integer from %u to %u, got '%.40s'",
                          key, lo, hi, v);
    *out = (uint32_t)x;
    return 0;
}

static int snapshot_options(merd_request *req, merd_snapshot_options *o, merd_refusal *why)
{
    memset(o, 0, sizeof *o);
    o->mesh.detail = 3;
    uint32_t quantize = 1, texcoords = 1;
    if (query_uint(req, "detail", 1, MER_MESH_DETAIL_MAX, &o->mesh.detail, why) ||
        query_uint(req, "leaves", 0, 1, &o->mesh.leaves, why) ||
        query_uint(req, "markers", 0, 1, &o->mesh.markers, why) ||
        query_uint(req, "quantize", 0, 1, &quantize, why) ||
        query_uint(req, "texcoords", 0, 1, &texcoords, why) ||
        query_uint(req, "twig_lines", 0, 1, &o->mesh.twig_lines, why))
        return -1;
    o->unquantized = !quantize;
    o->mesh.no_uvs = !texcoords;
    const char *compress = query(req, "compress");
    if (compress != NULL) {
        int mode = merd_compression_parse(compress);
        if (mode < 0)
            return merd_refuse(why, 422, "out-of-range", "compress",
                              "compress must be none or meshopt, got '%.40s'", compress);
        o->compression = (uint32_t)mode;
    }
    const char *color = query(req, "color");
    if (color != NULL) {
        int mode = merd_color_mode_parse(color);
        if (mode < 0)
            return merd_refuse(why, 422, "out-of-range", "color",
                              "color must be none, order, light or age, got '%.40s'", color);
        o->mesh.color = (uint32_t)mode;
    }
    return 0;
}

static struct MHD_Response *glb_response(merd_snapshot *snap, const char *etag, size_t *size)
{
    const uint8_t *bytes = merd_snapshot_bytes(snap, size);
    // The snapshot is shared with the cache: libmicrohttpd sends it in place and
    // releases our reference when the response is gone.
    struct MHD_Response *r = MHD_create_response_from_buffer_with_free_callback_cls(
        *size, (void *)bytes, (MHD_ContentReaderFreeCallback)merd_snapshot_release, snap);
    if (r == NULL) {
        merd_snapshot_release(snap);
        return NULL;
    }
    MHD_add_response_header(r, MHD_HTTP_HEADER_CONTENT_TYPE, "model/gltf-binary");
    MHD_add_response_header(r, MHD_HTTP_HEADER_ETAG, etag);
    MHD_add_response_header(r, MHD_HTTP_HEADER_CACHE_CONTROL, "no-cache");
    return r;
}

static bool wants_glb(merd_request *req)
{
    const char *accept = MHD_lookup_connection_value(req->connection, MHD_HEADER_KIND,
                                                     MHD_HTTP_HEADER_ACCEPT);
    return accept != NULL && strstr(accept, "model/gltf-binary") != NULL;
}

/* ----------------------------------------------------------- simple routes */

static char health_body[64];
static size_t health_size;

static void build_health(void)
{
    int n = snprintf(health_body, sizeof health_body, "{\"status\":\"ok\",\"version\":\"%s\"}",
                     mer_version());
    health_size = n > 0 && (size_t)n < sizeof health_body ? (size_t)n : 0;
}

enum MHD_Result merd_api_health(merd_request *req, const char *id)
{
    (void)id;
    // The hottest route: a constant body, built once.
    static pthread_once_t once = PTHREAD_ONCE_INIT;
    pthread_once(&once, build_health);
    struct MHD_Response *r = MHD_create_response_from_buffer(health_size, (void *)health_body,
                                                             MHD_RESPMEM_PERSISTENT);
    if (r == NULL)
        return MHD_NO;
    MHD_add_response_header(r, MHD_HTTP_HEADER_CONTENT_TYPE, "application/json");
    return merd_reply(req, 200, r, health_size);
}

/* The presets never change while meristemd runs: their JSON is built once. */
static char *presets_text;

static void build_presets(void)
{
    json_t *presets = json_array(), *fields = json_array();
    for (size_t i = 0; i < mer_preset_count(); i++) {
        mer_params p;
        mer_preset_params(mer_preset_name(i), &p, NULL);
        json_array_append_new(presets, json_pack("{s:s, s:s, s:o, s:o}", "name", mer_preset_name(i),
                                                 "description", mer_preset_description(i),
                                                 "params", merd_json_params(&p),
                                                 "schedule", merd_json_schedule(&p.schedule)));
    }
    mer_params d = mer_params_default();
    for (size_t f = 0; f < mer_params_field_count(); f++) {
        const char *name = mer_params_field_name(f);
        if (merd_param_in_schedule(name))
            continue;  // set_apical_schedule's business
        double lo, hi, v = 0;
        mer_params_field_range(f, &lo, &hi);
        mer_params_get(&d, name, &v, NULL);
        json_array_append_new(fields, json_pack("{s:s, s:s, s:o, s:o, s:o}", "name", name, "symbol",
                                                mer_params_field_symbol(f), "min", merd_json_param(lo),
                                                "max", merd_json_param(hi), "default",
                                                merd_json_param(v)));
    }
    json_t *body = json_pack("{s:o, s:o}", "presets", presets, "parameters", fields);
    presets_text = json_dumps(body, MERD_JSON_DUMP_FLAGS);
    json_decref(body);
}

enum MHD_Result merd_api_presets(merd_request *req, const char *id)
{
    (void)id;
    static pthread_once_t once = PTHREAD_ONCE_INIT;
    pthread_once(&once, build_presets);
    if (presets_text == NULL)
        return MHD_NO;
    size_t size = strlen(presets_text);
    struct MHD_Response *r =
        MHD_create_response_from_buffer(size, presets_text, MHD_RESPMEM_PERSISTENT);
    if (r == NULL)
        return MHD_NO;
    MHD_add_response_header(r, MHD_HTTP_HEADER_CONTENT_TYPE, "application/json");
    return merd_reply(req, 200, r, size);
}

enum MHD_Result merd_api_metrics(merd_request *req, const char *id)
{
    (void)id;
    uint32_t sessions;
    uint64_t internodes;
    merd_registry_totals(req->app->registry, &sessions, &internodes);
    char *text = merd_metrics_render(req->app->metrics, sessions, internodes,
                                    merd_jobs_pending(req->app->jobs));
    return reply_text(req, 200, text, "text/plain; version=0.0.4; charset=utf-8");
}

enum MHD_Result merd_api_list(merd_request *req, const char *id)
{
    (void)id;
    json_t *body = merd_registry_list(req->app->registry);
    enum MHD_Result ok = merd_reply_json(req, 200, body);
    json_decref(body);
    return ok;
}

enum MHD_Result merd_api_get(merd_request *req, const char *id)
{
    merd_refusal why = {0};
    merd_session *s = find_session(req, id, &why);
    if (s == NULL)
        return refuse(req, &why);
    uint64_t revision = 0;
    char *text = merd_session_summary_text(s, true, &revision);
    merd_session_unref(s);
    req->revision = (long long)revision;
    return reply_text(req, 200, text, "application/json");
}

enum MHD_Result merd_api_delete(merd_request *req, const char *id)
{
    merd_session *s = merd_registry_get(req->app->registry, id);
    if (s != NULL) {
        req->revision = (long long)merd_session_revision(s);
        merd_session_unref(s);
    }
    if (merd_registry_delete(req->app->registry, id) != 0) {
        merd_refusal why = {0};
        merd_refuse(&why, 404, "unknown-session", "", "there is no session %.64s", id);
        return refuse(req, &why);
    }
    struct MHD_Response *r = MHD_create_response_from_buffer(0, NULL, MHD_RESPMEM_PERSISTENT);
    return merd_reply(req, 204, r, 0);
}

enum MHD_Result merd_api_cancel(merd_request *req, const char *id)
{
    merd_refusal why = {0};
    merd_session *s = find_session(req, id, &why);
    if (s == NULL)
        return refuse(req, &why);
    bool running = merd_session_cancel(s);
    req->revision = (long long)merd_session_revision(s);
    merd_session_unref(s);
    json_t *body = json_pack("{s:b}", "cancelling", running);
    enum MHD_Result ok = merd_reply_json(req, 202, body);
    json_decref(body);
    return ok;
}

/* ------------------------------------------------------------ worker jobs */

typedef struct job {
    merd_request *req;
    merd_app *app;
    merd_session *session;   /* a reference, or NULL for create */
    json_t *spec;           /* create */
    merd_batch *batch;       /* edits */
    bool glb;               /* edits: answer with the snapshot */
    merd_snapshot_options snap;
    char etag[64];
} job;

static void job_free(job *j)
{
    merd_session_unref(j->session);
    json_decref(j->spec);
    merd_batch_free(j->batch);
    free(j);
}

static void finish_refused(job *j, const merd_refusal *why)
{
    size_t size = 0;
    struct MHD_Response *r = refusal_response(why, &size);
    merd_request_finish(j->req, why->status, r, size);
}

static void run_create(void *arg)
{
    job *j = arg;
    merd_refusal why = {0};
    merd_session *s = NULL;
    if (merd_registry_create(j->app->registry, j->spec, &s, &why) != 0) {
        finish_refused(j, &why);
    } else {
        json_t *body = merd_session_summary(s, true);
        size_t size = 0;
        struct MHD_Response *r = json_response(body, &size);
        json_decref(body);
        if (r != NULL) {
            char location[64];
            snprintf(location, sizeof location, "/v1/sessions/%s", merd_session_id(s));
            MHD_add_response_header(r, MHD_HTTP_HEADER_LOCATION, location);
        }
        j->req->revision = 0;
        merd_session_unref(s);
        merd_request_finish(j->req, 201, r, size);
    }
    job_free(j);
}

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void run_edits(void *arg)
{
    job *j = arg;
    merd_refusal why = {0};
    merd_batch_outcome outcome;
    double t0 = now();
    int rc = merd_session_apply(j->session, j->batch, &outcome, &why);
    if (rc == 0 && outcome.steps_done > 0)
        merd_metrics_step(j->app->metrics, now() - t0, outcome.steps_done);
    j->req->revision = (long long)merd_session_revision(j->session);
    if (rc != 0) {
        finish_refused(j, &why);
        job_free(j);
        return;
    }
    size_t size = 0;
    struct MHD_Response *r = NULL;
    if (j->glb) {
        merd_snapshot *snap = NULL;
        if (merd_session_snapshot(j->session, &j->snap, &snap, j->etag, &why) != 0) {
            finish_refused(j, &why);
            job_free(j);
            return;
        }
        r = glb_response(snap, j->etag, &size);
    } else {
        json_t *body = merd_session_summary(j->session, true);
        if (outcome.interrupted != NULL)
            json_object_set_new(body, "interrupted", json_string(outcome.interrupted));
        json_object_set_new(body, "steps_done", json_integer(outcome.steps_done));
        r = json_response(body, &size);
        json_decref(body);
    }
    if (r != NULL && outcome.interrupted != NULL)
        MHD_add_response_header(r, "Meristem-Interrupted", outcome.interrupted);
    merd_request_finish(j->req, 200, r, size);
    job_free(j);
}

static void run_snapshot(void *arg)
{
    job *j = arg;
    merd_refusal why = {0};
    merd_snapshot *snap = NULL;
    j->req->revision = (long long)merd_session_revision(j->session);
    if (merd_session_snapshot(j->session, &j->snap, &snap, j->etag, &why) != 0) {
        finish_refused(j, &why);
    } else {
        size_t size = 0;
        struct MHD_Response *r = glb_response(snap, j->etag, &size);
        merd_request_finish(j->req, 200, r, size);
    }
    job_free(j);
}

static enum MHD_Result submit(merd_request *req, job *j, merd_job_fn fn)
{
    merd_request_suspend(req);
    if (merd_jobs_submit(req->app->jobs, fn, j) != 0) {
        merd_refusal why = {0};
        merd_refuse(&why, 503, "shutting-down", "", "meristemd is stopping");
        finish_refused(j, &why);
        job_free(j);
    }
    return MHD_YES;
}

/* ---------------------------------------------------------- async routes */

enum MHD_Result merd_api_create(merd_request *req, const char *id)
{
    (void)id;
    merd_refusal why = {0};
    json_t *spec = parse_body(req, &why);
    if (spec == NULL)
        return refuse(req, &why);
    job *j = calloc(1, sizeof *j);
    if (j == NULL) {
        json_decref(spec);
        return MHD_NO;
    }
    *j = (job){.req = req, .app = req->app, .spec = spec};
    return submit(req, j, run_create);
}

enum MHD_Result merd_api_edits(merd_request *req, const char *id)
{
    merd_refusal why = {0};
    merd_session *s = find_session(req, id, &why);
    if (s == NULL)
        return refuse(req, &why);
    json_t *body = parse_body(req, &why);
    merd_batch *batch = NULL;
    merd_snapshot_options snap;
    if (body == NULL || merd_batch_decode(body, &req->app->session_config.limits, &batch, &why) != 0 ||
        snapshot_options(req, &snap, &why) != 0) {
        json_decref(body);
        merd_batch_free(batch);
        req->revision = (long long)merd_session_revision(s);
        merd_session_unref(s);
        return refuse(req, &why);
    }
    json_decref(body);
    job *j = calloc(1, sizeof *j);
    if (j == NULL) {
        merd_batch_free(batch);
        merd_session_unref(s);
        return MHD_NO;
    }
    *j = (job){.req = req, .app = req->app, .session = s, .batch = batch, .glb = wants_glb(req),
               .snap = snap};
    return submit(req, j, run_edits);
}

enum MHD_Result merd_api_snapshot(merd_request *req, const char *id)
{
    merd_refusal why = {0};
    merd_session *s = find_session(req, id, &why);
    if (s == NULL)
        return refuse(req, &why);
    merd_snapshot_options snap;
    req->revision = (long long)merd_session_revision(s);
    if (snapshot_options(req, &snap, &why) != 0) {
        merd_session_unref(s);
        return refuse(req, &why);
    }
    // A client that has this revision with these options gets 304 without meshing.
    char etag[64];
    merd_session_etag(s, &snap, etag);
    const char *match = MHD_lookup_connection_value(req->connection, MHD_HEADER_KIND,
                                                    MHD_HTTP_HEADER_IF_NONE_MATCH);
    if (match != NULL && (strstr(match, etag) != NULL || strcmp(match, "*") == 0)) {
        req->revision = (long long)merd_session_revision(s);
        merd_session_unref(s);
        struct MHD_Response *r = MHD_create_response_from_buffer(0, NULL, MHD_RESPMEM_PERSISTENT);
        if (r != NULL)
            MHD_add_response_header(r, MHD_HTTP_HEADER_ETAG, etag);
        return merd_reply(req, 304, r, 0);
    }
    job *j = calloc(1, sizeof *j);
    if (j == NULL) {
        merd_session_unref(s);
        return MHD_NO;
    }
    *j = (job){.req = req, .app = req->app, .session = s, .snap = snap};
    return submit(req, j, run_snapshot);
}
