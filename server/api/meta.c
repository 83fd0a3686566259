/* meristemd — the routes about the daemon: health, presets, metrics. */
#include "config.h"

#include <pthread.h>
#include <string.h>

#include <meristem/version.h>

#include "server/api/private.h"
#include "server/codec.h"

/* Queues JSON text that lives as long as the daemon, without copying it. */
static enum MHD_Result reply_constant(merd_request *req, const char *text, size_t size)
{
    struct MHD_Response *r = MHD_create_response_from_buffer(size, (void *)text,
                                                             MHD_RESPMEM_PERSISTENT);
    if (r == NULL)
        return MHD_NO;
    MHD_add_response_header(r, MHD_HTTP_HEADER_CONTENT_TYPE, "application/json");
    return merd_reply(req, 200, r, size);
}

static char health_body[64];
static size_t health_size;

static void build_health(void)
{
    int n = snprintf(health_body, sizeof health_body, "{\"status\":\"ok\",\"version\":\"%s\"}\n",
                     mer_version());
    health_size = n > 0 && (size_t)n < sizeof health_body ? (size_t)n : 0;
}

enum MHD_Result merd_api_health(merd_request *req, const char *id)
{
    (void)id;
    // The hottest route: a constant body, built once.
    static pthread_once_t once = PTHREAD_ONCE_INIT;
    pthread_once(&once, build_health);
    return reply_constant(req, health_body, health_size);
}

/* The presets never change while meristemd runs: their JSON is built once. */
static char *presets_text;

static void build_presets(void)
{
    json_t *presets = json_array(), *fields = json_array();
    for (size_t i = 0; i < mer_preset_count(); i++) {
        mer_params p;
        mer_preset_params(mer_preset_name(i), &p, NULL);
        json_t *entry = json_pack("{s:s, s:s, s:s, s:o, s:o}", "name", mer_preset_name(i),
                                  "description", mer_preset_description(i), "model",
                                  mer_model_name(p.model), "params", merd_json_params(&p),
                                  "schedule", merd_json_schedule(&p.schedule));
        const char *source = mer_preset_definition(mer_preset_name(i));
        bool inverse = p.model == MER_MODEL_INVERSE;
        if (entry != NULL && source != NULL)
            json_object_set_new(entry, inverse ? "inverse" : "lsystem",
                                json_pack("{s:s}", inverse ? "fset" : "source", source));
        json_array_append_new(presets, entry);
    }
    mer_params d = mer_params_default();
    for (size_t f = 0; f < mer_params_field_count(); f++) {
        const char *name = mer_params_field_name(f);
        if (merd_param_in_schedule(name))
            continue;  // set_apical_schedule's business
        double lo, hi, v = 0;
        mer_params_field_range(f, &lo, &hi);
        mer_params_get(&d, name, &v, NULL);
        json_array_append_new(fields, json_pack("{s:s, s:s, s:o, s:o, s:o, s:s}", "name", name, "symbol",
                                                mer_params_field_symbol(f), "min", merd_json_param(lo),
                                                "max", merd_json_param(hi), "default",
                                                merd_json_param(v), "model",
                                                mer_params_field_model(f)));
    }
    // What a length means, for every preset and every snapshot (asset.extras.units).
    json_t *units = json_pack("{s:s, s:s, s:s}", "length", "metre", "up", "+Y", "internode_length",
                              "the parameter internode_length (l0, default 1): one internode is "
                              "l0 units long when it grows");
    json_t *body = json_pack("{s:o, s:o, s:o}", "presets", presets, "parameters", fields, "units",
                             units);
    presets_text = merd_json_body(body);
    json_decref(body);
}

enum MHD_Result merd_api_presets(merd_request *req, const char *id)
{
    (void)id;
    static pthread_once_t once = PTHREAD_ONCE_INIT;
    pthread_once(&once, build_presets);
    if (presets_text == NULL)
        return MHD_NO;
    return reply_constant(req, presets_text, strlen(presets_text));
}

enum MHD_Result merd_api_metrics(merd_request *req, const char *id)
{
    (void)id;
    uint32_t sessions;
    uint64_t internodes;
    merd_registry_totals(req->app->registry, &sessions, &internodes);
    char *text = merd_metrics_render(req->app->metrics, sessions, internodes,
                                     merd_jobs_pending(req->app->jobs), req->app->session_config.cores);
    return merd_reply_text(req, 200, text, "text/plain; version=0.0.4; charset=utf-8");
}
