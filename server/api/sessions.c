/* meristemd — the session routes: create, list, get, delete, cancel. */
#include "config.h"

#include <stdio.h>
#include <string.h>

#include "server/api/private.h"

merd_session *merd_api_find_session(merd_request *req, const char *id, merd_refusal *why)
{
    return merd_registry_get_loaded(req->app->registry, id, why);
}

static void run_load(void *arg)
{
    merd_api_job *j = arg;
    merd_refusal why = {0};
    // Loaded or not, the request is routed again: its handler then finds the
    // session loaded, quarantined or gone, and answers as for any request.
    (void)merd_registry_load(j->app->registry, j->session, &why);
    merd_api_job_reroute(j);
}

bool merd_api_load_first(merd_request *req, const char *id, enum MHD_Result *result)
{
    if (req->load_handed_off)
        return false;
    merd_session *s = merd_registry_get(req->app->registry, id);
    if (s == NULL)
        return false;
    if (merd_session_is_loaded(s)) {
        merd_session_unref(s);
        return false;
    }
    req->load_handed_off = true;
    merd_api_job *j = merd_api_job_new(req, s);
    *result = j != NULL ? merd_api_job_submit(j, run_load) : MHD_NO;
    return true;
}

/* Sessions per page of GET /v1/sessions when ?limit= is not given, and the most. */
#define LIST_DEFAULT 1000
#define LIST_MAX 10000

enum MHD_Result merd_api_list(merd_request *req, const char *id)
{
    (void)id;
    merd_refusal why = {0};
    uint64_t limit = LIST_DEFAULT;
    merd_list_query q = {
        .after = MHD_lookup_connection_value(req->connection, MHD_GET_ARGUMENT_KIND, "after"),
        .preset = MHD_lookup_connection_value(req->connection, MHD_GET_ARGUMENT_KIND, "preset"),
        .state = MHD_lookup_connection_value(req->connection, MHD_GET_ARGUMENT_KIND, "state"),
    };
    static const char *const states[] = {"live", "running", "idle", "loaded", "not loaded",
                                         "quarantined"};
    bool known = q.state == NULL;
    for (size_t k = 0; !known && k < sizeof states / sizeof states[0]; k++)
        known = strcmp(q.state, states[k]) == 0;
    if (!known)
        merd_refuse(&why, 422, "out-of-range", "state",
                    "state must be live, running, idle, loaded, not loaded or quarantined, got '%.40s'", q.state);
    if (!known || merd_api_query_uint(req, "limit", 1, LIST_MAX, &limit, NULL, &why) != 0)
        return merd_reply_refusal(req, &why);
    q.limit = (size_t)limit;
    json_t *body = merd_registry_list(req->app->registry, &q);
    enum MHD_Result ok = merd_reply_json(req, 200, body);
    json_decref(body);
    return ok;
}

enum MHD_Result merd_api_get(merd_request *req, const char *id)
{
    merd_refusal why = {0};
    merd_session *s = merd_api_find_session(req, id, &why);
    if (s == NULL)
        return merd_reply_refusal(req, &why);
    uint64_t revision = 0;
    char *text = merd_session_summary_text(s, true, &revision);
    merd_session_unref(s);
    req->revision = (long long)revision;
    return merd_reply_text(req, 200, text, "application/json");
}

enum MHD_Result merd_api_delete(merd_request *req, const char *id)
{
    // Loaded first, so that a damaged journal is quarantined (503), not removed.
    merd_refusal why = {0};
    merd_session *s = merd_api_find_session(req, id, &why);
    if (s == NULL)
        return merd_reply_refusal(req, &why);
    req->revision = (long long)merd_session_revision(s);
    merd_session_unref(s);
    if (merd_registry_delete(req->app->registry, id, &why) != 0)
        return merd_reply_refusal(req, &why);
    struct MHD_Response *r = MHD_create_response_from_buffer(0, NULL, MHD_RESPMEM_PERSISTENT);
    return merd_reply(req, 204, r, 0);
}

enum MHD_Result merd_api_cancel(merd_request *req, const char *id)
{
    merd_refusal why = {0};
    merd_session *s = merd_api_find_session(req, id, &why);
    if (s == NULL)
        return merd_reply_refusal(req, &why);
    bool running = merd_session_cancel(s);
    req->revision = (long long)merd_session_revision(s);
    merd_session_unref(s);
    json_t *body = json_pack("{s:b}", "cancelling", running);
    enum MHD_Result ok = merd_reply_json(req, 202, body);
    json_decref(body);
    return ok;
}

static void run_create(void *arg)
{
    merd_api_job *j = arg;
    merd_refusal why = {0};
    merd_session *s = NULL;
    if (merd_registry_create(j->app->registry, j->spec, &s, &why) != 0) {
        merd_api_job_refuse(j, &why);
        return;
    }
    json_t *body = merd_session_summary(s, true);
    size_t size = 0;
    struct MHD_Response *r = merd_json_response(body, &size);
    json_decref(body);
    if (r != NULL) {
        char location[64];
        snprintf(location, sizeof location, "/v1/sessions/%s", merd_session_id(s));
        MHD_add_response_header(r, MHD_HTTP_HEADER_LOCATION, location);
    }
    j->req->revision = 0;
    merd_session_unref(s);
    merd_api_job_finish(j, 201, r, size);
}

enum MHD_Result merd_api_create(merd_request *req, const char *id)
{
    (void)id;
    merd_refusal why = {0};
    json_t *spec = merd_request_json(req, &why);
    if (spec == NULL)
        return merd_reply_refusal(req, &why);
    merd_api_job *j = merd_api_job_new(req, NULL);
    if (j == NULL) {
        json_decref(spec);
        return MHD_NO;
    }
    j->spec = spec;
    return merd_api_job_submit(j, run_create);
}
